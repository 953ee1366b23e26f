% args: --plan aux/paper_partial_order.plan
% The paper's partial-order example (examples/06_partial_order), scheduled from the total order of
% its table of achievers; the `pop` pass after it.

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

action(move_block_start(A, B, X1, Y1, X2, Y2),
    [gripped(A, B), ontable(B, X1, Y1)],
    [],
    [],
    [destination(B, X2, Y2)],
    [del(gripped(A, B)), del(ontable(B, X1, Y1)), add(moving(A, B, X1, Y1, X2, Y2))]).
action(move_block_end(A, B, X1, Y1, X2, Y2),
    [moving(A, B, X1, Y1, X2, Y2)],
    [ontable(_, X2, Y2)],
    [],
    [ontable(B, X2, Y2)],
    [del(moving(A, B, X1, Y1, X2, Y2)), add(ontable(B, X2, Y2)), add(clear(B)), add(available(A))]).
action(move_block_end(A, B, X1, Y1, X2, Y2),
    [moving(A, B, X1, Y1, X2, Y2), ontable(B2, X2, Y2), clear(B2)],
    [],
    [],
    [on(B, B2, X2, Y2)],
    [del(moving(A, B, X1, Y1, X2, Y2)), del(clear(B2)), add(on(B, B2, X2, Y2)), add(clear(B)),
     add(available(A))]).

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
