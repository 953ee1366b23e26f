% The reference answer of 09_spread_five_4_arms.
test_case :- go(
  [available(a1), available(a2), available(a3), available(a4), ontable(b5, 1, 1), on(b4, b5, 1, 1), on(b3, b4, 1, 1), on(b2, b3, 1, 1), on(b1, b2, 1, 1), clear(b1)],
  [available(a1), available(a2), available(a3), available(a4), ontable(b1, 1, 5), ontable(b2, 2, 5), ontable(b3, 3, 5), ontable(b4, 4, 5), ontable(b5, 5, 5), clear(b1), clear(b2), clear(b3), clear(b4), clear(b5)]
).
