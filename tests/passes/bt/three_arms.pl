% A goal file for the standard blocks world: three arms build a tower of three blocks. The
% `bt` pass shows the behaviour tree: parallel branches per arm, waits where one arm's work
% needs another's.
tower :- go(
  [available(a1), available(a2), available(a3),
   ontable(b1, 1, 1), clear(b1), ontable(b2, 2, 2), clear(b2), ontable(b3, 4, 4), clear(b3)],
  [ontable(b1, 3, 3), on(b2, b1, 3, 3), on(b3, b2, 3, 3),
   available(a1), available(a2), available(a3)]).
