% The reference answer of 04_stack_four_2_arms.
test_case :- go(
  [available(a1), available(a2), ontable(b1, 1, 1), ontable(b2, 2, 2), ontable(b3, 3, 3), ontable(b4, 4, 4), clear(b1), clear(b2), clear(b3), clear(b4)],
  [available(a1), available(a2), ontable(b4, 5, 5), on(b3, b4, 5, 5), on(b2, b3, 5, 5), on(b1, b2, 5, 5), clear(b1)]
).
