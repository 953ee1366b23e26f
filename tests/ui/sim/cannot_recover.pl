% ui: kbc run $CASE --fault stop:a1@move_block
% a1, the only arm, stops for good while it carries b1: the goal needs b1, and nothing can
% take it from a stopped gripper.
only_arm :- go([available(a1), ontable(b1, 1, 1), clear(b1)], [ontable(b1, 2, 2), clear(b1)]).
