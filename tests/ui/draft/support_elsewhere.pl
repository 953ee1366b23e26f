% ui: kbc draft check $CASE
test_case :- go(
  [available(a1), ontable(b1, 1, 1), on(b2, b1, 2, 2), clear(b2)],
  [available(a1), ontable(b1, 3, 3), on(b2, b1, 3, 3), clear(b2)]
).
