% ui: kbc validate $CASE tests/ui/plan/aux/bad_plan_file.plan
% The plan file has a step with a variable and a step that does not parse.
one_move :- go(
  [available(a1), ontable(b1, 1, 1), clear(b1)],
  [available(a1), ontable(b1, 2, 2), clear(b1)]
).
