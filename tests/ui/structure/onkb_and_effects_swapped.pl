action(move(A, X, Y), [at(A, X)], [], [], [del(at(A, X)), add(at(A, Y))], [cell(Y)]).
cell(1).
