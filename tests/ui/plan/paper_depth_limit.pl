% ui: kbc plan $CASE --search paper --max-depth 5
% Moving one block takes six snap actions (grip, move, release; each a start and an end), so
% the paper's search finds nothing within a depth limit of five.
one_move :- go(
  [available(a1), ontable(b1, 1, 1), clear(b1)],
  [available(a1), ontable(b1, 2, 2), clear(b1)]
).
