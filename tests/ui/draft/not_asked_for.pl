% ui: kbc draft check $CASE
test_one :- go(
  [available(a1), ontable(b1, 1, 1), clear(b1)],
  [available(a1), ontable(b1, 2, 2), clear(b1)]
).
pos(6, 6).
