cell(1, 1).
cell(2, 1).
free(X) :- cell(X).
