% ui: kbc validate $CASE tests/ui/temporal/aux/timed_plan_too_early.txt
% The move starts before the grip has ended.
one_move :- go(
  [available(a1), ontable(b1, 1, 1), clear(b1)],
  [available(a1), ontable(b1, 2, 2), clear(b1)]
).
