arm(left).
arm(right).
object(cup).
object(plate).
object(knife).
object(bowl).
spot(S) :- member(S, [s1, s2, s3, s4, s5]).
% The left arm reaches s1-s3, the right arm s3-s5.
reach(left, 1, 3).
reach(right, 3, 5).
reachable(Arm, Spot) :- reach(Arm, Lo, Hi), spot(Spot), atom_number_(Spot, N), N >= Lo, N =< Hi.
atom_number_(s1, 1). atom_number_(s2, 2). atom_number_(s3, 3). atom_number_(s4, 4). atom_number_(s5, 5).
forbidden(knife, s1).
weight(cup, 1). weight(plate, 2). weight(knife, 1). weight(bowl, 3).
duration(pick(_, _), 2, 4).
duration(place(_, Obj, _), D, Max) :- weight(Obj, W), D is W + 1, Max is 2 * D.
