% A robot in two rooms with a box, instantaneous actions only: the `task` pass shows the
% schemas, the interned facts and the problem's initial state and goal.
room(hall). room(lab).
connected(hall, lab). connected(lab, hall).

action(go(R, From, To), [robot(R), in(R, From)], [], [], [connected(From, To)], [del(in(R, From)), add(in(R, To))]).
action(pick(R, B, Room), [in(R, Room), in(B, Room), hand_empty(R)], [], [], [box(B)], [del(in(B, Room)), del(hand_empty(R)), add(holding(R, B))]).
action(drop(R, B, Room), [in(R, Room), holding(R, B)], [], [], [], [del(holding(R, B)), add(in(B, Room)), add(hand_empty(R))]).
box(b).

fetch :- go([robot(r), in(r, hall), hand_empty(r), in(b, lab)], [in(b, hall)]).
