% ui: kbc run $CASE
% The KB says a nudge moves the block, but its mapping only lifts the gripper: the tree
% succeeds and the world read back disagrees with the goal.
action(nudge_start(A, B), [available(A), ontable(B, 1, 1)], [], [], [], [del(available(A)), del(ontable(B, 1, 1)), add(ontable(B, 2, 2)), add(nudging(A, B))]).
action(nudge_end(A, B), [nudging(A, B)], [], [], [], [del(nudging(A, B)), add(available(A))]).
mapping(nudge_start(A, _), [lift(A)]).
nudge :- go([available(a1), ontable(b1, 1, 1), clear(b1)], [ontable(b1, 2, 2)]).
duration(nudge(_, _), 1, 2).
