% ui: kbc plan $CASE --problem stack_tow
% A `--problem` name that matches no problem, close to one that exists.
stack_two :- go(
  [available(a1), ontable(b1, 1, 1), ontable(b2, 2, 2), clear(b1), clear(b2)],
  [available(a1), ontable(b2, 2, 2), on(b1, b2, 2, 2), clear(b1)]
).
