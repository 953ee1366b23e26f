% ui: kbc plan $CASE
% The goal puts b1 at (9,9), but the standard blocks world only moves blocks to the
% positions the problem uses (or the table cells a KB declares), so no action reaches it.
far_away :- go(
  [available(a1), ontable(b1, 1, 1), ontable(b2, 2, 2), clear(b1), clear(b2)],
  [available(a1), ontable(b1, 9, 9), clear(b1)]
).
