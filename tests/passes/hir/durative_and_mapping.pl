% A KB in the authors' two-level style: a durative high-level action with a start, an end
% whose name takes its start's values, a duration rule, a mapping onto arm-level actions,
% resources and one problem. The `hir` pass shows the resolved KB.
resources(arm(_)).
cell(1, 1). cell(2, 1).

action(carry_start(A, B, X1, Y1, X2, Y2),
    [arm(A), free(A), at(B, X1, Y1)],
    [at(_, X2, Y2)],
    [],
    [cell(X2, Y2), (X1, Y1) \= (X2, Y2)],
    [del(free(A)), del(at(B, X1, Y1)), add(carrying(A, B))]).
action(carry_end(A, B, X1, Y1, X2, Y2),
    [carrying(A, B)],
    [],
    [],
    [],
    [del(carrying(A, B)), add(at(B, X2, Y2)), add(free(A))]).

duration(carry(_, _, X1, Y1, X2, Y2), Min, Max) :-
    D is abs(X2 - X1) + abs(Y2 - Y1),
    Min is D + 1,
    Max is 2 * D + 2.

ll_action(ll_move(A, X, Y), [ll_arm(A)], [], [], [cell(X, Y)], [add(ll_at(A, X, Y))]).
mapping(carry_start(A, _, X1, Y1, X2, Y2), [ll_move(A, X1, Y1), ll_move(A, X2, Y2)]).

move_box :- go([arm(r1), free(r1), at(box, 1, 1)], [at(box, 2, 1), free(r1)]).
