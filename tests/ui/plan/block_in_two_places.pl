% ui: kbc plan $CASE
% A goal that puts b1 in two places at once: every action keeps each block in one place.
twice :- go(
  [available(a1), ontable(b1, 1, 1), ontable(b2, 2, 2), clear(b1), clear(b2)],
  [available(a1), ontable(b1, 1, 1), ontable(b1, 3, 3), clear(b1), clear(b2)]
).
