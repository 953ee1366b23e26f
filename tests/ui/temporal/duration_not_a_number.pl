% ui: kbc plan $CASE
% A duration rule that binds its bounds to atoms.
action(grip_start(A, B), [free(A), loose(B)], [], [], [], [del(free(A)), add(gripping(A, B))]).
action(grip_end(A, B), [gripping(A, B)], [], [], [], [del(gripping(A, B)), del(loose(B)), add(held(A, B))]).
duration(grip(_, _), Min, Max) :- Min = short, Max = long.
hold :- go([free(a1), loose(b1)], [held(a1, b1)]).
