% std/blocks.pl: the multi-arm blocks world of Saccon et al., "When Prolog meets generative
% models" (the paper kbc implements), written in kbc's KB language.
%
% kbc uses this file as the domain when the files it is given declare no action schema, so a
% goal file with the paper's tests (`test1 :- go(Init, Goal).`) is enough to plan.
%
% Blocks stand on the cells of a table, in stacks. Arms (the `available/1` facts of the initial
% state) grip a clear block, move it to another cell (onto the table or onto the top of the
% stack there), and release it. Each step is a durative action, a `_start`/`_end` pair, so the
% planner can run several arms at once. Every step consumes the fluent the previous one
% produced, which keeps the KB correct under the paper's planner too (it has no other way of
% knowing that an action has started).
%
% State fluents:
%   available(A)                 arm A is idle
%   ontable(B, X, Y)             block B stands on the table at cell (X, Y)
%   on(B, B1, X, Y)              block B stands on block B1, in the stack at cell (X, Y)
%   clear(B)                     nothing stands on B and no arm holds it
%   gripping(A, B)               arm A is closing its gripper on B
%   gripped(A, B)                arm A holds B where it stood
%   moving(A, B, X1, Y1, X2, Y2) arm A carries B from cell (X1, Y1) to cell (X2, Y2)
%   placed(A, B)                 arm A has put B down and still holds it
%   releasing(A, B)              arm A is opening its gripper on B

% The arms are the `available/1` facts of the initial state.
resources(available(_)).

% pos(X, Y): a cell of the table. A goal file declares its table with cell(X, Y) facts; without
% any, the table is the 5 x 5 grid the paper's examples use.
:- dynamic cell/2.
pos(X, Y) :- cell(X, Y).
pos(X, Y) :- \+ cell(_, _), member(X, [1, 2, 3, 4, 5]), member(Y, [1, 2, 3, 4, 5]).

% Where blocks may be put down. While a problem is planned, its goal's facts are part of the
% KB (as in the paper), so these rules can ask the goal where a block belongs: a block is put
% on the table where the goal wants it or on a buffer cell (one the goal leaves empty), and on
% another block only where the goal stacks it there. Destinations come goal first, which
% steers the paper's depth-first search.
:- dynamic ontable/3, on/4.
destination(B, X, Y) :- ontable(B, X, Y), pos(X, Y).
destination(B, X, Y) :- on(B, _, X, Y), pos(X, Y).
destination(_, X, Y) :- buffer(X, Y).
table_place(B, X, Y) :- ontable(B, X, Y).
table_place(_, X, Y) :- buffer(X, Y).
buffer(X, Y) :- pos(X, Y), \+ ontable(_, X, Y), \+ on(_, _, X, Y).

% grip: close the gripper on a clear block. The InvalidAtEnd lists keep a block that already
% stands where the goal wants it from being picked up, as the paper's KB does.
action(grip_start(A, B),
    [available(A), ontable(B, X, Y), clear(B)],
    [gripping(_, B), gripped(_, B)],
    [ontable(B, X, Y)],
    [],
    [del(available(A)), add(gripping(A, B))]).
action(grip_start(A, B),
    [available(A), on(B, B1, X, Y), clear(B)],
    [gripping(_, B), gripped(_, B)],
    [on(B, B1, X, Y)],
    [],
    [del(available(A)), add(gripping(A, B))]).
action(grip_end(A, B),
    [gripping(A, B)],
    [],
    [],
    [],
    [del(gripping(A, B)), del(clear(B)), add(gripped(A, B))]).

% move_block: lift the held block off its support and carry it to another cell, one the
% goal wants it on first.
action(move_block_start(A, B, X1, Y1, X2, Y2),
    [gripped(A, B), ontable(B, X1, Y1)],
    [],
    [],
    [destination(B, X2, Y2), (X1 \== X2 ; Y1 \== Y2)],
    [del(gripped(A, B)), del(ontable(B, X1, Y1)), add(moving(A, B, X1, Y1, X2, Y2))]).
action(move_block_start(A, B, X1, Y1, X2, Y2),
    [gripped(A, B), on(B, B1, X1, Y1)],
    [],
    [],
    [destination(B, X2, Y2), (X1 \== X2 ; Y1 \== Y2)],
    [del(gripped(A, B)), del(on(B, B1, X1, Y1)), add(clear(B1)), add(moving(A, B, X1, Y1, X2, Y2))]).
% Arriving at an empty cell, the block stands on the table (where the goal wants it, or on a
% buffer cell).
action(move_block_end(A, B, X1, Y1, X2, Y2),
    [moving(A, B, X1, Y1, X2, Y2)],
    [ontable(_, X2, Y2)],
    [],
    [table_place(B, X2, Y2)],
    [del(moving(A, B, X1, Y1, X2, Y2)), add(ontable(B, X2, Y2)), add(placed(A, B))]).
% Arriving at a stack, the block goes on its top block, where the goal stacks it on that block;
% the top block must be clear and not being gripped.
action(move_block_end(A, B, X1, Y1, X2, Y2),
    [moving(A, B, X1, Y1, X2, Y2), ontable(B2, X2, Y2), clear(B2)],
    [gripping(_, B2)],
    [],
    [on(B, B2, X2, Y2)],
    [del(moving(A, B, X1, Y1, X2, Y2)), del(clear(B2)), add(on(B, B2, X2, Y2)), add(placed(A, B))]).
action(move_block_end(A, B, X1, Y1, X2, Y2),
    [moving(A, B, X1, Y1, X2, Y2), on(B2, _, X2, Y2), clear(B2)],
    [gripping(_, B2)],
    [],
    [on(B, B2, X2, Y2)],
    [del(moving(A, B, X1, Y1, X2, Y2)), del(clear(B2)), add(on(B, B2, X2, Y2)), add(placed(A, B))]).

% release: open the gripper; the arm is free again and the block is clear.
action(release_start(A, B),
    [placed(A, B)],
    [],
    [],
    [],
    [del(placed(A, B)), add(releasing(A, B))]).
action(release_end(A, B),
    [releasing(A, B)],
    [],
    [],
    [],
    [del(releasing(A, B)), add(available(A)), add(clear(B))]).

% Durations, in time units: bounds on end minus start. Gripping and releasing take one to two
% units. Moving takes at least one unit per cell of Manhattan distance plus one to lift and
% lower, and has no upper bound (`inf`): an arm may hold its block above the destination until
% the place there is ready (the block below it placed and released).
duration(grip(_, _), 1, 2).
duration(move_block(_, _, X1, Y1, X2, Y2), Min, inf) :-
    Min is abs(X2 - X1) + abs(Y2 - Y1) + 1.
duration(release(_, _), 1, 2).

% On the simulated arms (std/arms.pl), each durative action runs as arm-level steps: those of
% its start's mapping when it starts, those of its end's mapping when the plan allows it to end.
% Gripping reaches for the block and closes on it. Moving lifts the block and takes it to the
% arm's resting point beside the table; when the place at the destination is ready (the end),
% the arm carries it over the cell and lowers it onto what stands there. Releasing opens the gripper, lifts
% clear and sends the arm to its resting point beside the table, out of the other arms' way.
mapping(grip_start(A, B), [reach(A, B), descend(A), close(A, B)]).
mapping(move_block_start(A, _, _, _, _, _), [lift(A), home(A)]).
mapping(move_block_end(A, _, _, _, X2, Y2), [move_over(A, X2, Y2), descend(A)]).
mapping(release_start(A, B), [open(A, B), lift(A), home(A)]).
