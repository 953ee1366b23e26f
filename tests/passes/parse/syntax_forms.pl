% The syntax a KB may use, printed back by the `parse` pass: operators by priority, quoted
% atoms with spaces and escapes, strings, lists with tails, negation, if-then-else.
:- dynamic(at/2).
room('hall & kitchen').
room(lab).
label("a string", 'it''s', 'tab\there').
door(X, Y) :- room(X), room(Y), X \= Y, \+ blocked(X, Y).
blocked(lab, 'hall & kitchen').
cost(X, Y, C) :- C is abs(X - Y) * 2 + 1, C >= 1.
pick([H|T], H, T).
choose(X, Y) :- ( X > Y -> Z = X ; Z = Y ), Z =:= Z.
pair(- 1, -1).
nested([1, [2, 3], f(g(h))], (a, b)).
