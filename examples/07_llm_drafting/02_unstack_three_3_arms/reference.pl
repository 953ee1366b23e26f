% The reference answer of 02_unstack_three_3_arms.
test_case :- go(
  [available(a1), available(a2), available(a3), ontable(b1, 1, 1), on(b2, b1, 1, 1), on(b3, b2, 1, 1), clear(b3)],
  [available(a1), available(a2), available(a3), ontable(b1, 3, 1), ontable(b2, 3, 2), ontable(b3, 3, 3), clear(b1), clear(b2), clear(b3)]
).
