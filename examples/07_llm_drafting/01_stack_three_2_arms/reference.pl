% The reference answer of 01_stack_three_2_arms.
test_case :- go(
  [available(a1), available(a2), ontable(b1, 1, 1), ontable(b2, 2, 2), ontable(b3, 3, 3), clear(b1), clear(b2), clear(b3)],
  [available(a1), available(a2), ontable(b3, 4, 4), on(b2, b3, 4, 4), on(b1, b2, 4, 4), clear(b1)]
).
