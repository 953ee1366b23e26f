report(X) :- format("~w~n", [X]).
