% ui: kbc draft check $CASE
test_case :- go(
  [available(a1), ontable(b1, 1, 1), ontable(b2, 2, 2), clear(b1)],
  [available(a1), ontable(b2, 3, 3), on(b1, b2, 3, 3), clear(b1), clear(b2)]
).
