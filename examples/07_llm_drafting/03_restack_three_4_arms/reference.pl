% The reference answer of 03_restack_three_4_arms.
test_case :- go(
  [available(a1), available(a2), available(a3), available(a4), ontable(b2, 1, 1), on(b1, b2, 1, 1), ontable(b3, 2, 2), clear(b1), clear(b3)],
  [available(a1), available(a2), available(a3), available(a4), ontable(b2, 3, 3), on(b1, b2, 3, 3), on(b3, b1, 3, 3), clear(b3)]
).
