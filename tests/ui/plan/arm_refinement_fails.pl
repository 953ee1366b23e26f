% ui: kbc plan --level arm $CASE
% The mapping moves to the feeder and closes the gripper, but `ll_init` says the gripper is
% closed already and the closing step wants it open: no high-level plan refines (E0311).
:- include('aux/feeder.pl').
ll_init([ll_idle(arm1), ll_gripper(arm1, closed)]).
