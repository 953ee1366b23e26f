% Pick and place, in the style of a language model's KB: an agent (agent/1, free/1; no
% resources/1) picks a box from its cell and places it on an empty one, two durative actions.
% The problems (pick_place_*.pl) give the agents, the pos/2 cells and the go/2 test.
action(pick_start(R, B, X, Y), [free(R), at(B, X, Y)], [], [], [agent(R)],
    [del(free(R)), del(at(B, X, Y)), add(picking(R, B, X, Y))]).
action(pick_end(R, B, X, Y), [picking(R, B, X, Y)], [], [], [],
    [del(picking(R, B, X, Y)), add(holding(R, B)), add(empty(X, Y))]).
action(place_start(R, B, X, Y), [holding(R, B), empty(X, Y)], [placing(_, _, X, Y)], [], [pos(X, Y)],
    [del(holding(R, B)), del(empty(X, Y)), add(placing(R, B, X, Y))]).
action(place_end(R, B, X, Y), [placing(R, B, X, Y)], [], [], [],
    [del(placing(R, B, X, Y)), add(at(B, X, Y)), add(free(R))]).
duration(pick(_, _, _, _), 2, 3).
duration(place(_, _, _, _), 2, 3).
