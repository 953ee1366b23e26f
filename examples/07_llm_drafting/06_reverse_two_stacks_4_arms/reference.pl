% The reference answer of 06_reverse_two_stacks_4_arms.
test_case :- go(
  [available(a1), available(a2), available(a3), available(a4), ontable(b2, 1, 1), on(b1, b2, 1, 1), ontable(b4, 2, 2), on(b3, b4, 2, 2), clear(b1), clear(b3)],
  [available(a1), available(a2), available(a3), available(a4), ontable(b1, 1, 1), on(b2, b1, 1, 1), ontable(b3, 2, 2), on(b4, b3, 2, 2), clear(b2), clear(b4)]
).
