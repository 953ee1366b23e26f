% ui: kbc plan $CASE
% A maximum duration below the minimum: no schedule exists.
action(grip_start(A, B), [free(A), loose(B)], [], [], [], [del(free(A)), add(gripping(A, B))]).
action(grip_end(A, B), [gripping(A, B)], [], [], [], [del(gripping(A, B)), del(loose(B)), add(held(A, B))]).
duration(grip(_, _), 3, 2).
hold :- go([free(a1), loose(b1)], [held(a1, b1)]).
