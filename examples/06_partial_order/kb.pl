% The paper's example of a partial-order plan (section "Partial-Order Plan and STN", Tables
% "describing how the actions change the prior state" and "List of achievers"): two arms, two
% blocks; each arm grips a block and moves it to (3, 3), the second block onto the first.
%
% The paper's two tables disagree on the order of the last three steps and on which block lands
% first; this KB follows its table of achievers, whose step 8 (b2 arriving at (3, 3)) waits for
% step 7 (b1 arriving there) and step 3 (b2 leaving): so b1 stands on the table at (3, 3) and b2
% goes on top of it. `plan.txt` beside this file is that total order; `kbc plan kb.pl --plan
% plan.txt --schedule` prints its achievers, the partial order and the schedule.
%
% As in the paper, moving a block frees the arm when the block arrives (there is no release).

% grip: close the gripper on a clear block on the table.
action(grip_start(A, B),
    [available(A), ontable(B, _, _), clear(B)],
    [gripping(_, B), gripped(_, B)],
    [],
    [],
    [del(available(A)), add(gripping(A, B))]).
action(grip_end(A, B),
    [gripping(A, B)],
    [],
    [],
    [],
    [del(gripping(A, B)), del(clear(B)), add(gripped(A, B))]).

% move_block: carry the gripped block from (X1, Y1) to (X2, Y2), where the goal wants it.
action(move_block_start(A, B, X1, Y1, X2, Y2),
    [gripped(A, B), ontable(B, X1, Y1)],
    [],
    [],
    [destination(B, X2, Y2)],
    [del(gripped(A, B)), del(ontable(B, X1, Y1)), add(moving(A, B, X1, Y1, X2, Y2))]).
% Arriving at an empty cell: the block stands on the table.
action(move_block_end(A, B, X1, Y1, X2, Y2),
    [moving(A, B, X1, Y1, X2, Y2)],
    [ontable(_, X2, Y2)],
    [],
    [ontable(B, X2, Y2)],
    [del(moving(A, B, X1, Y1, X2, Y2)), add(ontable(B, X2, Y2)), add(clear(B)), add(available(A))]).
% Arriving at a stack: the block goes on the clear block there.
action(move_block_end(A, B, X1, Y1, X2, Y2),
    [moving(A, B, X1, Y1, X2, Y2), ontable(B2, X2, Y2), clear(B2)],
    [],
    [],
    [on(B, B2, X2, Y2)],
    [del(moving(A, B, X1, Y1, X2, Y2)), del(clear(B2)), add(on(B, B2, X2, Y2)), add(clear(B)),
     add(available(A))]).

% Where the goal wants each block (the goal's facts are part of the KB while planning).
:- dynamic ontable/3, on/4.
destination(B, X, Y) :- ontable(B, X, Y).
destination(B, X, Y) :- on(B, _, X, Y).

duration(grip(_, _), 1, 2).
duration(move_block(_, _, X1, Y1, X2, Y2), Min, Max) :-
    D is abs(X2 - X1) + abs(Y2 - Y1),
    Min is D + 1,
    Max is 2 * D + 2.

paper_example :- go(
  [available(a1), available(a2), ontable(b1, 1, 1), ontable(b2, 2, 2), clear(b1), clear(b2)],
  [available(a1), available(a2), ontable(b1, 3, 3), on(b2, b1, 3, 3), clear(b2)]
).
