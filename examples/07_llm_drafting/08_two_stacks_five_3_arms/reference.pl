% The reference answer of 08_two_stacks_five_3_arms.
test_case :- go(
  [available(a1), available(a2), available(a3), ontable(b1, 1, 1), ontable(b2, 1, 2), ontable(b3, 1, 3), ontable(b4, 1, 4), ontable(b5, 1, 5), clear(b1), clear(b2), clear(b3), clear(b4), clear(b5)],
  [available(a1), available(a2), available(a3), ontable(b3, 5, 1), on(b2, b3, 5, 1), on(b1, b2, 5, 1), ontable(b5, 5, 5), on(b4, b5, 5, 5), clear(b1), clear(b4)]
).
