% The heuristic search's plan for a non-blocks domain, and its achievers: which step (or the
% initial state, a0) makes each condition true.
room(hall). room(lab).
connected(hall, lab). connected(lab, hall).

action(go_start(R, From, To), [robot(R), in(R, From), idle(R)], [], [], [connected(From, To)], [del(in(R, From)), del(idle(R))]).
action(go_end(R, From, To), [], [], [], [], [add(in(R, To)), add(idle(R))]).
action(pick(R, B, Room), [in(R, Room), in(B, Room), hand_empty(R), idle(R)], [], [], [box(B)], [del(in(B, Room)), del(hand_empty(R)), add(holding(R, B))]).
action(drop(R, B, Room), [in(R, Room), holding(R, B), idle(R)], [], [], [], [del(holding(R, B)), add(in(B, Room)), add(hand_empty(R))]).
box(b).
duration(go(_, _, _), 3, 5).

fetch :- go([robot(r), idle(r), in(r, hall), hand_empty(r), in(b, lab)], [in(b, hall)]).
