% A warehouse: robots drive to a crate, then carry it to a spot no crate stands on or heads for.
% The robots (robot/1) and spots (spot/2) come with each problem's file.
dist(X1, Y1, X2, Y2, D) :- D is abs(X1 - X2) + abs(Y1 - Y2).

action(drive_start(R, X1, Y1, X2, Y2),
    [idle(R), robot_at(R, X1, Y1)],
    [],
    [],
    [spot(X2, Y2), (X1 \== X2 ; Y1 \== Y2)],
    [del(idle(R)), del(robot_at(R, X1, Y1))]).
action(drive_end(R, _X1, _Y1, X2, Y2),
    [],
    [],
    [],
    [],
    [add(robot_at(R, X2, Y2)), add(idle(R))]).
action(carry_start(R, C, X1, Y1, X2, Y2),
    [idle(R), robot_at(R, X1, Y1), crate_at(C, X1, Y1)],
    [crate_at(_, X2, Y2), heading(_, X2, Y2)],
    [],
    [spot(X2, Y2), (X1 \== X2 ; Y1 \== Y2)],
    [del(idle(R)), del(robot_at(R, X1, Y1)), del(crate_at(C, X1, Y1)), add(heading(C, X2, Y2))]).
action(carry_end(R, C, _X1, _Y1, X2, Y2),
    [heading(C, X2, Y2)],
    [],
    [],
    [],
    [del(heading(C, X2, Y2)), add(crate_at(C, X2, Y2)), add(robot_at(R, X2, Y2)), add(idle(R))]).

duration(drive(_, X1, Y1, X2, Y2), D, inf) :- dist(X1, Y1, X2, Y2, D).
duration(carry(_, _, X1, Y1, X2, Y2), D, M) :- dist(X1, Y1, X2, Y2, D0), D is D0 + 1, M is 3 * D.
