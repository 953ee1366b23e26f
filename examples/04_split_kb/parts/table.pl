% A 3 x 2 table.
cell(1, 1).
cell(2, 1).
cell(3, 1).
cell(1, 2).
cell(2, 2).
cell(3, 2).

% Two cells are neighbours when they differ by one step in one direction.
neighbour(X1, Y1, X2, Y2) :-
    cell(X1, Y1),
    cell(X2, Y2),
    abs(X1 - X2) + abs(Y1 - Y2) =:= 1.
