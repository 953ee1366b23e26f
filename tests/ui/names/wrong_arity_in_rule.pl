% An OnKB goal reaches `free/1`, whose body calls `cell` with the wrong number of arguments.
action(take(X), [], [], [], [free(X)], [add(taken(X))]).
cell(1, 1).
cell(2, 1).
free(X) :- cell(X).
