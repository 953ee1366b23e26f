neighbour(X1, Y1, X2, Y2) :-
    pos(X1, Y1)
    pos(X2, Y2),
    abs(X1 - X2) + abs(Y1 - Y2) =:= 1.
pos(1, 1).
