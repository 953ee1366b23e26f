% ui: kbc validate $CASE tests/ui/plan/aux/invalid_step.plan
% The plan moves b1 before gripping it.
one_move :- go(
  [available(a1), ontable(b1, 1, 1), clear(b1)],
  [available(a1), ontable(b1, 2, 2), clear(b1)]
).
