near(X, Y) :- D is abs(X - Y), D <= 1.
