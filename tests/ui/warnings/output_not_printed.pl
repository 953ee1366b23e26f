free_cell(X, Y) :- cell(X, Y), format("trying ~w~n", [X-Y]), \+ taken(X, Y).
cell(1, 1).
cell(1, 2).
taken(1, 1).
