% expect: plan deliver
% expect: warn W0016
% A delivery domain written the way a language model writes Prolog: the grid from
% between/3, distances with nested arithmetic (`2*(...)`), findall/3 with length/2 and
% sum_list/2, forall/2, aggregate_all/3, maplist/2, sort/2, nth1/3, `@<` and `=..`, an
% operator as an atom (`Op = (+)`), and a debugging format/2 that kbc does not print.
:- use_module(library(lists)).
:- use_module(library(apply)).
:- use_module(library(aggregate)).

robot(r1).
robot(r2).
station(s1, 1, 1).
station(s2, 4, 3).
station(s3, 2, 4).
cell(X, Y) :- between(1, 4, X), between(1, 4, Y).
blocked(3, 2).
blocked(3, 3).

free(X, Y) :- cell(X, Y), \+ blocked(X, Y).
step(X1, Y1, X2, Y2) :-
    member(D, [1-0, -1-0, 0-1, 0-(-1)]),
    D =.. [_, DX, DY],
    X2 is X1 + DX, Y2 is Y1 + DY,
    free(X2, Y2).
% Every station lies on a free cell, and there are more free cells than stations.
sane :-
    forall(station(_, X, Y), free(X, Y)),
    findall(X-Y, free(X, Y), Cells), length(Cells, N),
    aggregate_all(count, station(_, _, _), S),
    N > S.
% Robots in a canonical order, for the tie a model likes to break by name.
first_robot(R) :- findall(A, robot(A), As), sort(As, [R|_]).
cost(X1, Y1, X2, Y2, C) :- Op = (+), E =.. [Op, abs(X2 - X1), abs(Y2 - Y1)], C is 2*(E) - 1.
report(R) :- format("robot ~w moves~n", [R]).

action(move_start(R, X1, Y1, X2, Y2),
    [at(R, X1, Y1), idle(R)],
    [at(_, X2, Y2), going(_, _, _, X2, Y2)],
    [],
    [robot(R), sane, step(X1, Y1, X2, Y2), report(R)],
    [del(idle(R)), add(going(R, X1, Y1, X2, Y2))]).
action(move_end(R, X1, Y1, X2, Y2),
    [going(R, X1, Y1, X2, Y2)],
    [],
    [],
    [],
    [del(going(R, X1, Y1, X2, Y2)), del(at(R, X1, Y1)), add(at(R, X2, Y2)), add(idle(R))]).
action(drop(R, P, S),
    [at(R, X, Y), idle(R), carries(R, P)],
    [],
    [],
    [station(S, X, Y), maplist(robot, [R]), nth1(_, [s1, s2, s3], S), first_robot(F), ( F @< R ; F == R )],
    [del(carries(R, P)), add(delivered(P, S))]).

duration(move(_, X1, Y1, X2, Y2), C, C) :- cost(X1, Y1, X2, Y2, C0), sum_list([C0], C).

deliver :- go([at(r1, 1, 1), at(r2, 4, 4), idle(r1), idle(r2), carries(r1, p1), carries(r2, p2)],
              [delivered(p1, s2), delivered(p2, s3)]).
