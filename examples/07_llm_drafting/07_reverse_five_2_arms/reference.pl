% The reference answer of 07_reverse_five_2_arms.
test_case :- go(
  [available(a1), available(a2), ontable(b5, 1, 1), on(b4, b5, 1, 1), on(b3, b4, 1, 1), on(b2, b3, 1, 1), on(b1, b2, 1, 1), clear(b1)],
  [available(a1), available(a2), ontable(b1, 3, 3), on(b2, b1, 3, 3), on(b3, b2, 3, 3), on(b4, b3, 3, 3), on(b5, b4, 3, 3), clear(b5)]
).
