:- dynamic ontable.
mapping(grip_start(_, _)).
