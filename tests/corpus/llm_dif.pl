% expect: plan deliver
% expect: refuse E0306
% expect: plan round_trip length 4
% A courier domain in the style language models write, keeping two values apart with dif/2
% (SWI-Prolog's disequality constraint) instead of `\==`, once before the goal that binds
% the value (`dif(From, To), room(To)`: the constraint waits, and fails `room(To)`'s solution
% `To = From`), once after it. A courier never walks to where it stands: the attic's only
% route leads back into it, so in `stay` no plan exists; from the shed, whose route leads back
% into it too, the way back in goes through the yard (`round_trip`: two walks, not one).
room(hall).
room(lab).
room(store).
room(attic).
room(shed).
room(yard).
route(hall, lab).
route(lab, store).
route(store, hall).
route(attic, attic).
route(shed, shed).
route(shed, yard).
linked(A, B) :- route(A, B).
linked(A, B) :- route(B, A).

action(walk_start(C, From, To),
    [courier_at(C, From), idle(C)],
    [],
    [],
    [dif(From, To), room(To), linked(From, To)],
    [del(idle(C)), del(courier_at(C, From)), add(walking(C, From, To))]).
action(walk_end(C, From, To),
    [walking(C, From, To)],
    [], [], [],
    [del(walking(C, From, To)), add(courier_at(C, To)), add(idle(C)), add(visited(C, To))]).
action(carry_start(C, P, From, To),
    [courier_at(C, From), idle(C), parcel_at(P, From)],
    [],
    [],
    [room(To), dif(To, From)],
    [del(idle(C)), del(courier_at(C, From)), del(parcel_at(P, From)), add(carrying(C, P, From, To))]).
action(carry_end(C, P, From, To),
    [carrying(C, P, From, To)],
    [], [], [],
    [del(carrying(C, P, From, To)), add(courier_at(C, To)), add(parcel_at(P, To)), add(idle(C))]).

duration(walk(_, _, _), 2, 3).
duration(carry(_, _, _, _), 3, 4).

deliver :- go([courier_at(ann, hall), idle(ann), courier_at(bob, store), idle(bob),
               parcel_at(p1, hall), parcel_at(p2, lab), parcel_at(p3, store)],
              [parcel_at(p1, store), parcel_at(p2, hall), parcel_at(p3, lab)]).

stay :- go([courier_at(cat, attic), idle(cat)], [visited(cat, attic)]).
round_trip :- go([courier_at(dan, shed), idle(dan)], [visited(dan, shed)]).
