% ui: kbc draft check $CASE
test_case :- go(
  [available(a1), ontable(b1, 1, 1), clear(b1)],
  [available(a2), ontable(b1, 2, 2), clear(b1)]
).
