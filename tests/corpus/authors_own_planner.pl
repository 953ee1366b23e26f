% expect: plan test1 length 2
% expect: note
% A KB as the paper's authors ship it: their planner (`go/2` over `plan/5`, which reads the
% `action/6` facts and prints the plan) beside the actions and the tests. SWI-Prolog runs the
% test through that planner; kbc plans the problem itself, so the planner's rules are a note,
% not unknown predicates or output warnings.
:- discontiguous action/6.

go(S, G) :- plan(S, G, [S], [], 12).

plan(State, Goal, _, Moves, _) :-
    equal_set(State, Goal),
    reverse(Moves, Plan),
    write('plan is:'), nl,
    write_moves(Plan).
plan(State, Goal, Been, Moves, MaxDepth) :-
    length(Moves, L), L < MaxDepth,
    action(Name, Valid, Invalid, InvalidAtEnd, OnKB, Effects),
    conditions_met(Valid, State),
    conditions_not_met(Invalid, State),
    conditions_not_met(InvalidAtEnd, Goal),
    call_all(OnKB),
    change_state(State, Effects, Child),
    \+ member_state(Child, Been),
    plan(Child, Goal, [Child|Been], [Name|Moves], MaxDepth).

conditions_met(P, S) :- subset(P, S).
conditions_not_met([], _).
conditions_not_met([H|T], S) :- \+ member(H, S), conditions_not_met(T, S).
call_all([]).
call_all([G|Gs]) :- call(G), call_all(Gs).
change_state(S, [], S).
change_state(S, [add(P)|T], S_new) :- change_state(S, T, S2), add_to_set(P, S2, S_new), !.
change_state(S, [del(P)|T], S_new) :- change_state(S, T, S2), remove_from_set(P, S2, S_new), !.
add_to_set(X, S, [X|S]).
remove_from_set(_, [], []).
remove_from_set(X, [X|T], T) :- !.
remove_from_set(X, [H|T], [H|R]) :- remove_from_set(X, T, R).
member_state(S, [H|_]) :- equal_set(S, H).
member_state(S, [_|T]) :- member_state(S, T).
equal_set(S1, S2) :- subset(S1, S2), subset(S2, S1).
subset([], _).
subset([H|T], S) :- member(H, S), subset(T, S).
write_moves([]).
write_moves([H|T]) :- write(H), nl, write_moves(T).

pos(X, Y) :- member(X, [1, 2, 3]), member(Y, [1, 2, 3]).

action(move_start(A, B, X1, Y1, X2, Y2),
    [available(A), ontable(B, X1, Y1), clear(B)],
    [moving(_, B, _, _, _, _)],
    [ontable(B, X1, Y1)],
    [pos(X2, Y2), (X1 \== X2 ; Y1 \== Y2)],
    [del(available(A)), del(ontable(B, X1, Y1)), add(moving(A, B, X1, Y1, X2, Y2))]).
action(move_end(A, B, X1, Y1, X2, Y2),
    [moving(A, B, X1, Y1, X2, Y2)],
    [ontable(_, X2, Y2)],
    [],
    [],
    [del(moving(A, B, X1, Y1, X2, Y2)), add(ontable(B, X2, Y2)), add(available(A))]).

test1 :- go([available(a1), ontable(b1, 1, 1), clear(b1)], [available(a1), ontable(b1, 2, 2), clear(b1)]).
