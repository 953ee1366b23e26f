% Logistics: trucks carry packages between the places of their city and its airport, planes
% between airports; vehicles load and unload one package at a time and carry any number.
% Each problem's file gives its cities (city_of/2, airport/1), trucks, planes and go/2 problem.
vehicle(V) :- truck(V).
vehicle(V) :- plane(V).

action(drive_start(T, From, To),
    [idle(T), at(T, From)],
    [],
    [],
    [truck(T), city_of(From, C), city_of(To, C), From \== To],
    [del(idle(T)), del(at(T, From))]).
action(drive_end(T, _From, To),
    [],
    [],
    [],
    [],
    [add(at(T, To)), add(idle(T))]).
action(fly_start(P, From, To),
    [idle(P), at(P, From)],
    [],
    [],
    [plane(P), airport(To), From \== To],
    [del(idle(P)), del(at(P, From))]).
action(fly_end(P, _From, To),
    [],
    [],
    [],
    [],
    [add(at(P, To)), add(idle(P))]).
action(load_start(V, Pkg, L),
    [idle(V), at(V, L), pkg_at(Pkg, L)],
    [],
    [],
    [vehicle(V)],
    [del(idle(V)), del(pkg_at(Pkg, L))]).
action(load_end(V, Pkg, _L),
    [],
    [],
    [],
    [],
    [add(in(Pkg, V)), add(idle(V))]).
action(unload_start(V, Pkg, L),
    [idle(V), at(V, L), in(Pkg, V)],
    [],
    [],
    [vehicle(V)],
    [del(idle(V)), del(in(Pkg, V))]).
action(unload_end(V, Pkg, L),
    [],
    [],
    [],
    [],
    [add(pkg_at(Pkg, L)), add(idle(V))]).

duration(drive(_, _, _), 3, 6).
duration(fly(_, _, _), 5, 8).
duration(load(_, _, _), 1, 2).
duration(unload(_, _, _), 1, 2).
resources(idle(_)).
