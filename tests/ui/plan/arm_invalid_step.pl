% ui: kbc validate --level arm $CASE tests/ui/plan/aux/arm_invalid_step.plan
% An arm-level plan with its steps out of order: the validator replays the arm-level actions
% on the arm-level state and stops at the first that does not apply.
:- include('aux/feeder.pl').
ll_init([ll_idle(arm1), ll_gripper(arm1, open)]).
