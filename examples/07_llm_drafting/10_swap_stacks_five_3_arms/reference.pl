% The reference answer of 10_swap_stacks_five_3_arms.
test_case :- go(
  [available(a1), available(a2), available(a3), ontable(b3, 1, 1), on(b2, b3, 1, 1), on(b1, b2, 1, 1), ontable(b5, 2, 2), on(b4, b5, 2, 2), clear(b1), clear(b4)],
  [available(a1), available(a2), available(a3), ontable(b5, 1, 1), on(b4, b5, 1, 1), ontable(b3, 2, 2), on(b2, b3, 2, 2), on(b1, b2, 2, 2), clear(b4), clear(b1)]
).
