% The paper's example of an action schema (section "The Knowledge base"), verbatim, inside a
% small domain of its own: one arm picks a block up from the table and puts it down elsewhere.
%
%   action(Name, ValidConditions, InvalidConditions, InvalidConditionsAtEnd,
%          ConditionsOnKB, Effects).

% The cells a block may be put down on.
pos(1, 1).
pos(2, 2).
pos(3, 3).

action(grip_ontable_start(A, B),
       [ontable(B, X, Y), available(A), clear(B)],
       [gripped(_, B), gripping(_, B)],
       [ontable(B, X, Y)],
       [],
       [del(available(A)), add(gripping(A, B))]).
action(grip_ontable_end(A, B),
       [gripping(A, B), ontable(B, X, Y)],
       [],
       [],
       [],
       [del(gripping(A, B)), del(ontable(B, X, Y)), del(clear(B)), add(gripped(A, B))]).
action(put_down_start(A, B, X, Y),
       [gripped(A, B)],
       [ontable(_, X, Y)],
       [],
       [pos(X, Y)],
       [del(gripped(A, B)), add(putting_down(A, B, X, Y))]).
action(put_down_end(A, B, X, Y),
       [putting_down(A, B, X, Y)],
       [],
       [],
       [],
       [del(putting_down(A, B, X, Y)), add(ontable(B, X, Y)), add(clear(B)), add(available(A))]).

duration(grip_ontable(_, _), 1, 2).
duration(put_down(_, _, _, _), 2, 4).

% The paper's example query.
test1 :- go([available(a1), ontable(b1, 1, 1), clear(b1)],
            [available(a1), ontable(b1, 2, 2), clear(b1)]).
