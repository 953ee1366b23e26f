% expect: plan test1
% expect: refuse-arm test1 E0311
% A multi-arm blocks world in the paper's format with the authors' second level: high-level
% actions, arm-level ll_actions with their own fluents, mappings from each start, and
% arm-level states. The move's end names the destination only in its head: it takes the value
% its start bound. The high level plans; the arm level does not: `ll_init` knows only arm
% `a1`, and `ll_grip` closes a gripper nothing opens again, so no high-level plan refines.
agent(a1). agent(a2).
block(b1). block(b2).
pos(1, 1). pos(2, 2). pos(3, 3).
resources(agent(_)).
action(move_start(A, B, X1, Y1, X2, Y2),
    [free(A), at(B, X1, Y1), clear(B)],
    [at(_, X2, Y2), moving(_, _, _, _, X2, Y2)],
    [],
    [agent(A), block(B), pos(X2, Y2)],
    [del(free(A)), del(at(B, X1, Y1)), add(moving(A, B, X1, Y1, X2, Y2))]).
action(move_end(A, B, X1, Y1, X2, Y2),
    [moving(A, B, X1, Y1, _, _)],
    [],
    [],
    [],
    [del(moving(A, B, X1, Y1, X2, Y2)), add(at(B, X2, Y2)), add(free(A))]).
duration(move(_, _, X1, Y1, X2, Y2), D, D2) :- D is abs(X2 - X1) + abs(Y2 - Y1), D2 is 2 * D.
ll_action(ll_reach(A, X, Y), [ll_arm_at(A, _, _)], [], [], [], []).
ll_action(ll_grip(A), [ll_gripper(A, open)], [], [], [], [del(ll_gripper(A, open)), add(ll_gripper(A, closed))]).
mapping(move_start(A, _, X1, Y1, _, _), [ll_reach(A, X1, Y1), ll_grip(A)]).
test1 :- go([free(a1), free(a2), at(b1, 1, 1), at(b2, 2, 2), clear(b1), clear(b2)],
            [at(b1, 3, 3), at(b2, 1, 1)]).
ll_init([ll_arm_at(a1, 0, 0), ll_gripper(a1, open)]).
ll_goal([ll_gripper(a1, closed)]).
