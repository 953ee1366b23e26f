adjacent(X, Y, Z) :- Y is X + 1.
