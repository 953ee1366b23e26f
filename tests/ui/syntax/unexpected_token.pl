double(X, Y) :- Y is X * .
