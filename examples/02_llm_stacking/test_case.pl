% The task of the paper's LLM query: "a new test case, namely test_case, in which we use 3
% agents to move the boxes b1, b2, b3, b4 on the table, which are at (1,1), (2,2), (3,3), and
% (4,4), respectively, to a final stack [b1,b2,b3,b4] at point (5,5), which is ordered from top
% to bottom". This is the answer the paper expects: b4 at the bottom, b1 on top.
%
% The paper reports that its own Prolog planner finds no plan for this case within 60 CPU
% seconds; it is the first case kbc's planner must solve in milliseconds.

test_case :- go(
  [available(a1), available(a2), available(a3),
   ontable(b1, 1, 1), ontable(b2, 2, 2), ontable(b3, 3, 3), ontable(b4, 4, 4),
   clear(b1), clear(b2), clear(b3), clear(b4)],
  [available(a1), available(a2), available(a3),
   ontable(b4, 5, 5), on(b3, b4, 5, 5), on(b2, b3, 5, 5), on(b1, b2, 5, 5),
   clear(b1)]
).
