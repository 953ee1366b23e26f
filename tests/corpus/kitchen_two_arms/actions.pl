:- discontiguous action/6.
:- use_module(library(lists)).

% Picking: the end names only the arm and the object; the spot stays with the start.
action(pick_start(Arm, Obj),
       [free(Arm), on_counter(Obj, Spot)],
       [holding(_, Obj), picking(_, Obj)],
       [],
       [arm(Arm), object(Obj), reachable(Arm, Spot)],
       [del(free(Arm)), del(on_counter(Obj, Spot)), add(picking(Arm, Obj))]).
action(pick_end(Arm, Obj),
       [picking(Arm, Obj)],
       [],
       [],
       [],
       [del(picking(Arm, Obj)), add(holding(Arm, Obj))]).
action(place_start(Arm, Obj, Spot),
       [holding(Arm, Obj)],
       [on_counter(_, Spot), placing(_, _, Spot)],
       [],
       [spot(Spot), reachable(Arm, Spot), \+ forbidden(Obj, Spot)],
       [del(holding(Arm, Obj)), add(placing(Arm, Obj, Spot))]).
action(place_end(Arm, Obj, Spot),
       [placing(Arm, Obj, Spot)],
       [on_counter(_, Spot)],
       [],
       [],
       [del(placing(Arm, Obj, Spot)), add(on_counter(Obj, Spot)), add(free(Arm))]).
% Handing over between the arms, instantaneous.
action(hand_over(From, To, Obj),
       [holding(From, Obj), free(To)],
       [],
       [],
       [dif(From, To)],
       [del(holding(From, Obj)), del(free(To)), add(holding(To, Obj)), add(free(From))]).
