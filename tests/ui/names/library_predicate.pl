remember(X) :- assertz(seen(X)).
