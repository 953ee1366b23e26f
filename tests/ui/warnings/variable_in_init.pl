% ui: kbc plan $CASE
% An initial fact with a variable (W0015): Prolog leaves `A` unbound and the paper's planner
% moves the block with it; kbc plans with a value of the variable's own, `'_A'`.
test1 :- go([available(A), ontable(b1, 1, 1), clear(b1)],
            [ontable(b1, 2, 2)]).
