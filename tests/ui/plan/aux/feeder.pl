% A pick at a feeder, refined into two arm-level steps: move to the feeder, close the
% gripper (shared by the arm-level UI cases, which give their own `ll_init`).
action(pick_start(A, P), [free(A), in_feeder(P)], [], [], [],
    [del(free(A)), del(in_feeder(P)), add(picking(A, P))]).
action(pick_end(A, P), [picking(A, P)], [], [], [], [del(picking(A, P)), add(holds(A, P))]).
duration(pick(_, _), 2, 3).
ll_action(to_feeder(A), [ll_idle(A)], [], [], [], [del(ll_idle(A)), add(ll_at_feeder(A))]).
ll_action(close_gripper(A), [ll_at_feeder(A), ll_gripper(A, open)], [], [], [],
    [del(ll_gripper(A, open)), add(ll_gripper(A, closed))]).
mapping(pick_start(A, _), [to_feeder(A), close_gripper(A)]).
feed :- go([free(arm1), in_feeder(p1)], [holds(arm1, p1)]).
