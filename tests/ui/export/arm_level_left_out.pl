% ui: kbc export pddl $CASE -o target/ui-export-arm-level
% Arm-level actions and mappings have no PDDL counterpart: the export says it leaves them out.
action(pick_start(A, P), [free(A), in_feeder(P)], [], [], [], [del(free(A)), del(in_feeder(P)), add(picking(A, P))]).
action(pick_end(A, P), [picking(A, P)], [], [], [], [del(picking(A, P)), add(holds(A, P))]).
ll_action(close_gripper(A), [ll_open(A)], [], [], [], [del(ll_open(A)), add(ll_closed(A))]).
mapping(pick_start(A, _), [close_gripper(A)]).
duration(pick(_, _), 3, 5).
feed :- go([free(arm1), in_feeder(p1), ll_open(arm1)], [holds(arm1, p1)]).
