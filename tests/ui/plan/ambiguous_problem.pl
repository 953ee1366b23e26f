% ui: kbc plan $CASE
% Two problems and no `--problem`: kbc does not guess which one is meant.
left :- go([available(a1), ontable(b1, 1, 1), clear(b1)], [available(a1), ontable(b1, 2, 2), clear(b1)]).
right :- go([available(a1), ontable(b1, 2, 2), clear(b1)], [available(a1), ontable(b1, 1, 1), clear(b1)]).
