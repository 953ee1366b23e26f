different(X, Y) :- X != Y.
