% expect: plan pick length 2
% expect: arm pick length 2
% llm_arm_fixed_cell.pl fixed: the mapping moves the arm to the feeder's cell before it
% grasps, and takes the cell from where the arm is (the step's Valid list binds X and Y).
action(pick_start(A, P), [free(A), in_feeder(P)], [], [], [],
    [del(free(A)), del(in_feeder(P)), add(picking(A, P))]).
action(pick_end(A, P), [picking(A, P)], [], [], [], [del(picking(A, P)), add(holds(A, P))]).
ll_action(ll_goto(A, X, Y), [ll_arm_at(A, X0, Y0)], [], [], [feeder(X, Y)],
    [del(ll_arm_at(A, X0, Y0)), add(ll_arm_at(A, X, Y))]).
ll_action(ll_grasp(A, X, Y), [ll_arm_at(A, X, Y), ll_gripper(A, open)], [], [], [],
    [del(ll_gripper(A, open)), add(ll_gripper(A, closed))]).
feeder(4, 4).
mapping(pick_start(A, _), [ll_goto(A, _, _), ll_grasp(A, _, _)]).
pick :- go([free(arm1), in_feeder(p1)], [holds(arm1, p1)]).
ll_init([ll_arm_at(arm1, 0, 0), ll_gripper(arm1, open)]).
