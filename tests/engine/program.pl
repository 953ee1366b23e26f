% The program both engines load for tests/engine_vs_swipl.rs.

app([], L, L).
app([H|T], L, [H|R]) :- app(T, L, R).

len([], 0).
len([_|T], N) :- len(T, M), N is M + 1.

rev(L, R) :- rev(L, [], R).
rev([], A, A).
rev([H|T], A, R) :- rev(T, [H|A], R).

colour(red).
colour(green).
colour(blue).

pos(1, 1).
pos(1, 2).
pos(2, 1).
pos(2, 2).

edge(a, b).
edge(b, c).
edge(c, d).
edge(a, d).

path(X, Y) :- edge(X, Y).
path(X, Y) :- edge(X, Z), path(Z, Y).

first_colour(C) :- colour(C), !.
max_of(X, Y, X) :- X >= Y, !.
max_of(_, Y, Y).

classify(N, small) :- N < 10, !.
classify(N, medium) :- N < 100, !.
classify(_, large).

neighbour(X1, Y1, X2, Y2) :- pos(X1, Y1), pos(X2, Y2), abs(X1 - X2) + abs(Y1 - Y2) =:= 1.

not_red(C) :- colour(C), \+ C = red.

sign(N, S) :- ( N > 0 -> S = positive ; N < 0 -> S = negative ; S = zero ).

twice(X) :- ( X = 1 ; X = 2 ), ( X = 1 ; X = 2 ).

cut_in_or(X) :- ( X = 1, ! ; X = 2 ).
cut_in_or(3).

count_to(N, N).
count_to(N, M) :- N < 3, N1 is N + 1, count_to(N1, M).

nested(f(X, g(Y, [X|Z])), X, Y, Z).

fact(0, 1) :- !.
fact(N, F) :- N1 is N - 1, fact(N1, F1), F is N * F1.

% Disjunctions of every shape: plain and if-then branches mixed, if-then chains, nests.
pick(X) :- ( X = 1 ; X = 2 -> true ; X = 3 ; member(X, [4, 5]) -> true ; X = 6 ).
then_chain(X, Y) :- ( member(X, [1, 2, 3]) -> member(Y, [a, b]) -> true ; X = none, Y = none ).
then_chain_fails(X) :- ( member(X, [1, 2]) -> fail -> true ; X = other ).
nest(X) :- ( ( X = 1 ; X = 2 ) ; ( X = 3 -> true ; X = 4 ) ; X = 5 ).
left_if(X) :- ( ( X = 1 -> true ; X = 2 ) ; X = 3 ).
last_if(X) :- ( X = 1 ; member(X, [2, 3]) -> true ).
last_if_fails(X) :- ( X = 1 ; fail -> true ).
cut_in_branch(X) :- ( member(X, [1, 2]) -> true ; X = 3 ; ! ; X = 4 ).
cut_in_branch(5).

% For the library queries: a closure, a comparison for predsort/3, facts to aggregate.
double(X, Y) :- Y is 2 * X.
add(X, Acc0, Acc) :- Acc is Acc0 + X.
positive(X) :- X > 0.
by_second(O, _-A, _-B) :- compare(O, A, B).
score(ann, 3).
score(bob, 5).
score(cid, 5).
score(dan, 1).
owns(ann, cat).
owns(bob, dog).
owns(ann, fish).
owns(cid, cat).

% A term as nested lists, name first: how it was read, whatever operators it was written with.
tree(T, T) :- atomic(T), !.
tree(T, V) :- var(T), !, V = var.
tree(T, [F|Ts]) :- T =.. [F|As], maplist(tree, As, Ts).
qualified(L) :- lists:append([a], [b], L0), user:reverse(L0, L).
