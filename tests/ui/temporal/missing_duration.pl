% ui: kbc plan $CASE
% A durative action without `duration/3`: the plan is scheduled with the default, and a
% warning says so.
action(grip_start(A, B), [free(A), loose(B)], [], [], [], [del(free(A)), add(gripping(A, B))]).
action(grip_end(A, B), [gripping(A, B)], [], [], [], [del(gripping(A, B)), del(loose(B)), add(held(A, B))]).
hold :- go([free(a1), loose(b1)], [held(a1, b1)]).
