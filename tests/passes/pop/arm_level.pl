% args: --level arm
% The two-level blocks world of the corpus at the arm level: achievers among arm-level steps,
% each mapping's steps in sequence and the high-level order between mappings ("refinement"),
% and one step at a time per arm ("same unit", which here every other ordering already implies).
:- include('../../corpus/arm_blocks_two_level.pl').
