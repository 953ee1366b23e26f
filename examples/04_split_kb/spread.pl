% A test that computes its states before calling `go`, as Prolog runs it: every agent starts
% idle on its own cell of the first row, and must end on the cell above it.
start_cell(r1, 1, 1).
start_cell(r2, 3, 1).
spread :-
    findall(at(R, X, 1), start_cell(R, X, 1), At),
    findall(idle(R), agent(R), Idle),
    append(At, Idle, Init),
    findall(at(R, X, 2), start_cell(R, X, 1), Goal),
    go(Init, Goal).
