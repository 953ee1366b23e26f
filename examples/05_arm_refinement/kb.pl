% High-level actions can be refined into arm-level steps. `ll_action/6` declares an arm-level
% action with the same six slots as `action/6`; `mapping(HighLevelStart, [Step, ...])` says
% which steps carry out a high-level start (variables pass through by unification).

% A high-level pick: the arm takes a part from the feeder.
action(pick_start(A, P),
    [free(A), in_feeder(P)],
    [],
    [],
    [],
    [del(free(A)), del(in_feeder(P)), add(picking(A, P))]).
action(pick_end(A, P),
    [picking(A, P)],
    [],
    [],
    [],
    [del(picking(A, P)), add(holds(A, P))]).

% The arm-level steps a pick is made of.
ll_action(move_to_feeder(A),
    [ll_free(A)],
    [],
    [],
    [],
    [add(ll_at_feeder(A))]).
ll_action(close_gripper(A),
    [ll_at_feeder(A)],
    [],
    [],
    [],
    [del(ll_free(A)), add(ll_closed(A))]).

mapping(pick_start(A, _), [move_to_feeder(A), close_gripper(A)]).

duration(pick(_, _), 3, 5).

feed :- go([free(arm1), in_feeder(p1), ll_free(arm1)], [holds(arm1, p1)]).
