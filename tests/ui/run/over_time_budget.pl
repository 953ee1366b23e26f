% ui: kbc run $CASE --max-time 1
% The plan takes longer than the run's virtual-time budget.
init_state([ontable(b1, 1, 1), clear(b1), available(a1)]).
goal_state([ontable(b1, 2, 2), clear(b1)]).
