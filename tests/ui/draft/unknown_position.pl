% ui: kbc draft check $CASE
test_case :- go(
  [available(a1), ontable(b1, 1, 1), clear(b1)],
  [available(a1), ontable(b1, 6, 6), clear(b1)]
).
