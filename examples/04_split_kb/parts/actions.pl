% Mobile robots move between neighbouring cells, one robot per cell.

action(drive_start(R, X1, Y1, X2, Y2),
    [at(R, X1, Y1), idle(R)],
    [at(_, X2, Y2), heading(_, X2, Y2)],
    [],
    [agent(R), neighbour(X1, Y1, X2, Y2)],
    [del(idle(R)), add(heading(R, X2, Y2))]).
action(drive_end(R, X1, Y1, X2, Y2),
    [heading(R, X2, Y2), at(R, X1, Y1)],
    [],
    [],
    [],
    [del(heading(R, X2, Y2)), del(at(R, X1, Y1)), add(at(R, X2, Y2)), add(idle(R))]).

% Driving takes longer for the second robot, which is slower.
duration(drive(R, _, _, _, _), Min, Max) :-
    (R == r2 -> Min = 2, Max = 4 ; Min = 1, Max = 2).
