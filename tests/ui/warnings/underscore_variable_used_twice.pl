same(_X, _X).
