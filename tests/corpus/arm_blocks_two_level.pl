% expect: plan stack2 length 4
% expect: arm stack2 length 14
% A blocks world in the authors' two-level style. The high level moves blocks between cells;
% each move refines into arm motion (`ll_arm_at/4`, whose height `ll_init` leaves open),
% gripper fluents (`ll_gripper/2`, whose state `ll_init` leaves open too: the first step that
% needs it open binds it), a durative lift, and two ways to approach a block. The fast
% approach is tried first and applies, but the grip needs the careful one, so the refinement
% backtracks into the second clause.
agent(a1).
block(b1). block(b2).
cell(1, 1). cell(2, 2). cell(3, 3).
resources(agent(_)).
action(move_start(A, B, X1, Y1, X2, Y2),
    [free(A), at(B, X1, Y1)],
    [at(_, X2, Y2)],
    [],
    [agent(A), block(B), cell(X2, Y2)],
    [del(free(A)), del(at(B, X1, Y1)), add(moving(A, B, X1, Y1, X2, Y2))]).
action(move_end(A, B, X1, Y1, X2, Y2),
    [moving(A, B, X1, Y1, X2, Y2)],
    [],
    [],
    [],
    [del(moving(A, B, X1, Y1, X2, Y2)), add(at(B, X2, Y2)), add(free(A))]).
duration(move(_, _, X1, Y1, X2, Y2), D, D) :- D is abs(X2 - X1) + abs(Y2 - Y1).
duration(ll_lift(_), 1, 2).

ll_action(ll_goto(A, X, Y), [ll_arm_at(A, X0, Y0, Z)], [], [], [],
    [del(ll_arm_at(A, X0, Y0, Z)), add(ll_arm_at(A, X, Y, Z))]).
ll_action(ll_approach(A), [ll_gripper(A, open)], [], [], [], [add(ll_near(A, fast))]).
ll_action(ll_approach(A), [ll_gripper(A, open)], [], [], [], [add(ll_near(A, careful))]).
ll_action(ll_grip(A, B), [ll_near(A, careful), ll_gripper(A, open)], [ll_holding(A, _)], [], [],
    [del(ll_near(A, careful)), del(ll_gripper(A, open)), add(ll_gripper(A, closed)), add(ll_holding(A, B))]).
ll_action(ll_lift_start(A), [ll_gripper(A, closed)], [], [], [], [add(ll_lifting(A))]).
ll_action(ll_lift_end(A), [ll_lifting(A)], [], [], [], [del(ll_lifting(A))]).
ll_action(ll_release(A, B), [ll_holding(A, B)], [], [], [],
    [del(ll_holding(A, B)), del(ll_gripper(A, closed)), add(ll_gripper(A, open))]).

mapping(move_start(A, B, X1, Y1, _, _),
    [ll_goto(A, X1, Y1), ll_approach(A), ll_grip(A, B), ll_lift_start(A), ll_lift_end(A)]).
mapping(move_end(A, B, _, _, X2, Y2), [ll_goto(A, X2, Y2), ll_release(A, B)]).

stack2 :- go([free(a1), at(b1, 1, 1), at(b2, 2, 2)], [at(b1, 3, 3), at(b2, 1, 1)]).
ll_init([ll_arm_at(a1, 0, 0, _), ll_gripper(a1, _)]).
ll_goal([ll_gripper(a1, open)]).
