% expect: plan pillars_architraves length 6
% expect: refuse-arm pillars_architraves E0311
% An assembly of two pillars and an architrave, in the two-level spelling (hl_init/hl_goal,
% and an ll_init with a variable, which only the arm level reads). The architrave may only go
% on once both pillars stand, and InvalidAtEnd keeps `remove` from undoing a goal. There is no
% `mapping/2`, so `--level arm` has nothing to refine into.
pillar(p1). pillar(p2).
action(raise_start(P), [free_crew], [standing(P)], [], [pillar(P)], [del(free_crew), add(raising(P))]).
action(raise_end(P), [raising(P)], [], [], [], [del(raising(P)), add(standing(P)), add(free_crew)]).
action(place_architrave, [standing(p1), standing(p2), free_crew], [architrave_on], [], [], [add(architrave_on)]).
action(remove(P), [standing(P)], [architrave_on], [standing(P)], [], [del(standing(P))]).
action(inspect, [architrave_on], [inspected], [], [], [add(inspected)]).
duration(raise(_), 2, 4).
hl_init([free_crew]).
hl_goal([architrave_on, inspected, standing(p1), standing(p2)]).
ll_init([ll_arm_at(a1, 4, 4, _)]).
