action(grip_start(A, B), [available(A)], [], [], [], [del(available(A)), add(holding(A, B))]).
action(grip_end(A, B), [holding(A, B)], [], [], [], [add(available(A))]).
ll_action(close_gripper(A), [], [], [], [], [add(closed(A))]).
mapping(grip_start(A, _), [move_above(A), close_griper(A)]).
