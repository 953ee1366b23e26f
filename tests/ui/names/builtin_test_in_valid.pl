action(move(A, X, Y), [at(A, X), Y > X], [], [], [cell(Y)], [del(at(A, X)), add(at(A, Y))]).
cell(1).
cell(2).
test1 :- go([at(a1, 1)], [at(a1, 2)]).
