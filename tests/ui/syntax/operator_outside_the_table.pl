first(X) :- member(X, [1, 2]) *-> true.
