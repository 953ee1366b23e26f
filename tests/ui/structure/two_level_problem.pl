% ui: kbc plan $CASE
% The authors' two-level spelling of a problem: hl_init/hl_goal plan; ll_init/ll_goal are the
% arm-level state and goal that `--level arm` refines against, read without a word here.
action(go_a, [start], [], [], [], [add(at_a)]).
hl_init([start]).
hl_goal([at_a]).
ll_init([ll_arm_at(a1, 0, 0)]).
ll_goal([ll_arm_at(a1, 1, 1)]).
