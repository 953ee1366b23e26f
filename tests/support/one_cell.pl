% A table with a single cell, for drafting tests: any goal that moves a block is unsolvable
% here, although each state on its own is fine.
cell(1, 1).

% b1 stays where it is.
test1 :- go([available(a1), ontable(b1, 1, 1), clear(b1)], [available(a1), ontable(b1, 1, 1), clear(b1)]).
