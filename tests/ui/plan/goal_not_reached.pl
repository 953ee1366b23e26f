% ui: kbc validate $CASE tests/ui/plan/aux/goal_not_reached.plan
% Every step applies, but the plan stops with b1 gripped and nothing moved.
one_move :- go(
  [available(a1), ontable(b1, 1, 1), clear(b1)],
  [available(a1), ontable(b1, 2, 2), clear(b1)]
).
