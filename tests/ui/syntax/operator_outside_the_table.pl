before(X, Y) :- X @< Y.
