% A warehouse: robots drive to a crate, lift it, carry it to a free spot and drop it.
robot(r1). robot(r2).
spot(X,Y):- member(X,[0,1,2,3,4]), member(Y,[0,1,2,3,4]).
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

test_shuffle :- go(
  [ idle(r1),
    idle(r2),
    robot_at(r1, 2, 4),
    robot_at(r2, 3, 4),
    crate_at(c1, 1, 2),
    crate_at(c2, 0, 2),
    crate_at(c3, 3, 2),
    crate_at(c4, 4, 0),
    crate_at(c5, 0, 3),
    crate_at(c6, 4, 2),
    crate_at(c7, 2, 2),
    crate_at(c8, 1, 1),
    crate_at(c9, 3, 3),
    crate_at(c10, 2, 3),
    crate_at(c11, 4, 1),
    crate_at(c12, 4, 3),
    crate_at(c13, 0, 1),
    crate_at(c14, 1, 4),
    crate_at(c15, 3, 0),
    crate_at(c16, 4, 4),
    crate_at(c17, 3, 1),
    crate_at(c18, 2, 0),
    crate_at(c19, 0, 0),
    crate_at(c20, 1, 0) ],
  [ crate_at(c1, 2, 1),
    crate_at(c2, 3, 1),
    crate_at(c3, 1, 4),
    crate_at(c4, 1, 2),
    crate_at(c5, 2, 4),
    crate_at(c6, 1, 0),
    crate_at(c7, 3, 4),
    crate_at(c8, 4, 4),
    crate_at(c9, 2, 2),
    crate_at(c10, 2, 3),
    crate_at(c11, 3, 3),
    crate_at(c12, 4, 3),
    crate_at(c13, 0, 4),
    crate_at(c14, 1, 3),
    crate_at(c15, 0, 1),
    crate_at(c16, 3, 0),
    crate_at(c17, 4, 2),
    crate_at(c18, 4, 1),
    crate_at(c19, 0, 0),
    crate_at(c20, 2, 0) ]).
