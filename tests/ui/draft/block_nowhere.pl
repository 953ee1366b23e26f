% ui: kbc draft check $CASE
test_case :- go(
  [available(a1), ontable(b1, 1, 1), ontable(b2, 2, 2), ontable(b3, 4, 4), clear(b1), clear(b2), clear(b3)],
  [available(a1), ontable(b1, 3, 3), on(b2, b1, 3, 3), clear(b2), clear(b3)]
).
