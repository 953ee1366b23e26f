% The paper's Algorithm 1 in SWI-Prolog, written for kbc's tests from the paper's description and
% docs/dsl.md, as an independent check of `kbc plan --search paper`: the same semantics (Valid,
% OnKB, Invalid, InvalidAtEnd, effects in list order, durative pairs with no self-overlap, every
% fact that unifies deleted by an open `del`) and the paper's enumeration order (the state is a
% list with the newest addition first; actions in clause order; OnKB solutions in Prolog order).
%
% Usage: swipl -q -g "consult(KB), consult(this), run(Problem, MaxDepth), halt" prints the
% first plan, one snap action per line, or `no plan`.

:- dynamic action/6.

go(_, _).  % the KB's problems are `prob :- go(Init, Goal).`; `run/2` reads them instead.

% A problem is `prob :- Goals, go(Init, Goal), After.`: the goals before `go` run first (their
% first solution, as kbc takes it), those after it are not run.
run(Problem, Max) :-
    clause(Problem, Body),
    test_call(Body, Before, Init, Goal),
    once(Before),
    (   first_plan(Init, Goal, Max, Plan)
    ->  forall(member(Step, Plan), (print(Step), nl))
    ;   writeln('no plan')
    ).

test_call(go(Init, Goal), true, Init, Goal) :- !.
test_call((go(Init, Goal), _), true, Init, Goal) :- !.
test_call((First, Rest), (First, Before), Init, Goal) :- test_call(Rest, Before, Init, Goal).

first_plan(Init, Goal, _, []) :-
    satisfied(Goal, Init, []), !.
first_plan(Init, Goal, Max, Plan) :-
    search(Init, [], Goal, [Init-[]], 1, Max, Plan), !.

% search(+State, +Running, +Goal, +Path, +Frames, +Max, -Plan): depth first; a child that
% satisfies the goal ends the search; otherwise it is expanded unless it is on the path or the
% path is at the depth limit.
search(State, Running, Goal, Path, Frames, Max, [Name|Rest]) :-
    step(State, Running, Goal, Name, State1, Running1),
    (   satisfied(Goal, State1, Running1)
    ->  Rest = []
    ;   \+ on_path(State1-Running1, Path),
        Frames < Max,
        Frames1 is Frames + 1,
        search(State1, Running1, Goal, [State1-Running1|Path], Frames1, Max, Rest)
    ).

on_path(State-Running, Path) :-
    msort(State, S), msort(Running, R),
    member(State0-Running0, Path),
    msort(State0, S), msort(Running0, R), !.

satisfied(Goal, State, []) :-
    copy_term(Goal, G),
    all_in(G, State).

all_in([], _).
all_in([L|Ls], State) :- member(L, State), all_in(Ls, State).

% One applicable action, in the paper's order, and the lists it leads to.
step(State, Running, Goal, Name, State1, Running1) :-
    action(Name, Valid, Invalid, AtEnd, OnKB, Effects),
    Name =.. [Functor|Args],
    snap(Functor, Base, Snap),
    (   Snap == end
    ->  Open =.. [Base|Args], member(Open, Running), select(Open, Running, Running1)
    ;   true
    ),
    all_in(Valid, State),
    call_all(OnKB),
    ground(Name),
    (   Snap == start
    ->  Open =.. [Base|Args], \+ memberchk(Open, Running), Running1 = [Open|Running]
    ;   Snap == instant
    ->  Running1 = Running
    ;   true
    ),
    \+ ( member(L, Invalid), member(L, State) ),
    \+ ( member(L, AtEnd), member(G, Goal), \+ L \= G ),
    adds_ground(Effects),
    apply_all(Effects, State, State1).

snap(Functor, Base, start) :- atom_concat(Base, '_start', Functor), !.
snap(Functor, Base, end) :- atom_concat(Base, '_end', Functor), !.
snap(Functor, Functor, instant).

call_all([]).
call_all([G|Gs]) :- call(G), call_all(Gs).

adds_ground([]).
adds_ground([add(F)|Es]) :- !, ground(F), adds_ground(Es).
adds_ground([_|Es]) :- adds_ground(Es).

apply_all([], S, S).
apply_all([add(F)|Es], S0, S) :- !,
    (   memberchk(F, S0) -> S1 = S0 ; S1 = [F|S0] ),
    apply_all(Es, S1, S).
apply_all([del(F)|Es], S0, S) :-
    exclude(unifies_with(F), S0, S1),
    apply_all(Es, S1, S).

unifies_with(F, X) :- \+ F \= X.
