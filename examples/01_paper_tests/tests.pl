% The test cases of the paper's figure "Example of message used to query the LLM", verbatim.
% This file declares no action schema, so kbc plans them in the standard multi-arm blocks
% world, std/blocks.pl.

% from b1 at the point (2,2), b2 on the table at point (1,1) to b2,b1 stacked at point (3,3).
test1 :- go(
  [available(a1), available(a2), available(a3), ontable(b1, 2, 2), ontable(b2, 1, 1), clear(b1), clear(b2)],
  [available(a1), available(a2), available(a3), ontable(b2,3,3), on(b1, b2, 3, 3), clear(b1)]
).

% from b2,b1 stacked to b1, b2 on the table.
test2 :- go(
  [available(a1), available(a2), available(a3), ontable(b2,1,1), on(b1, b2, 1, 1), clear(b1)],
  [available(a1), available(a2), available(a3), ontable(b1,2,2), ontable(b2, 3, 3), clear(b1), clear(b2)]
).

% from b2,b1 stacked and b3 on the table to b1,b2,b3 stacked.
test3 :- go(
  [available(a1), available(a2), available(a3), ontable(b2,1,1), on(b1, b2, 1, 1), clear(b1), ontable(b3, 2, 2), clear(b3)],
  [available(a1), available(a2), available(a3), ontable(b1,3,3), on(b2, b1, 3, 3), on(b3, b2, 3, 3), clear(b3)]
).
