% expect: plan pick length 2
% expect: refuse-arm pick E0311
% A slip language models make in two-level KBs: the mapping sends the arm to a fixed cell
% (0, 0) where the arm-level action expects the arm to be already, while `ll_init` puts it at
% the feeder (4, 4). The high level plans; no high-level plan refines. (Fixed in
% llm_arm_fixed_cell_fixed.pl.)
action(pick_start(A, P), [free(A), in_feeder(P)], [], [], [],
    [del(free(A)), del(in_feeder(P)), add(picking(A, P))]).
action(pick_end(A, P), [picking(A, P)], [], [], [], [del(picking(A, P)), add(holds(A, P))]).
ll_action(ll_grasp(A, X, Y), [ll_arm_at(A, X, Y), ll_gripper(A, open)], [], [], [],
    [del(ll_gripper(A, open)), add(ll_gripper(A, closed))]).
mapping(pick_start(A, _), [ll_grasp(A, 0, 0)]).
pick :- go([free(arm1), in_feeder(p1)], [holds(arm1, p1)]).
ll_init([ll_arm_at(arm1, 4, 4), ll_gripper(arm1, open)]).
