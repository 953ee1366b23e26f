% Logistics: 4 cities of 4 places and an airport, a truck in each city, 2 planes,
% 20 packages. Trucks drive inside a city, planes fly between airports; both load and unload.
city_of(l1_1, c1). city_of(l1_2, c1). city_of(l1_3, c1). city_of(l1_4, c1). city_of(a1, c1). city_of(l2_1, c2). city_of(l2_2, c2). city_of(l2_3, c2). city_of(l2_4, c2). city_of(a2, c2). city_of(l3_1, c3). city_of(l3_2, c3). city_of(l3_3, c3). city_of(l3_4, c3). city_of(a3, c3). city_of(l4_1, c4). city_of(l4_2, c4). city_of(l4_3, c4). city_of(l4_4, c4). city_of(a4, c4).
airport(a1). airport(a2). airport(a3). airport(a4).
truck(t1). truck(t2). truck(t3). truck(t4).
plane(p1). plane(p2).
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

deliver :- go(
  [ idle(t1),
    idle(t2),
    idle(t3),
    idle(t4),
    idle(p1),
    idle(p2),
    at(t1, l1_1),
    at(t2, l2_1),
    at(t3, l3_1),
    at(t4, l4_1),
    at(p1, a1),
    at(p2, a1),
    pkg_at(k1, l1_3),
    pkg_at(k2, l2_1),
    pkg_at(k3, l2_4),
    pkg_at(k4, a4),
    pkg_at(k5, l4_4),
    pkg_at(k6, l3_4),
    pkg_at(k7, l4_2),
    pkg_at(k8, l4_3),
    pkg_at(k9, l4_2),
    pkg_at(k10, l1_2),
    pkg_at(k11, l3_2),
    pkg_at(k12, l3_1),
    pkg_at(k13, l3_4),
    pkg_at(k14, l2_1),
    pkg_at(k15, l2_1),
    pkg_at(k16, l2_3),
    pkg_at(k17, l2_1),
    pkg_at(k18, l2_1),
    pkg_at(k19, l4_2),
    pkg_at(k20, l3_2)
  ],
  [ pkg_at(k1, l3_3),
    pkg_at(k2, l3_1),
    pkg_at(k3, l2_2),
    pkg_at(k4, l1_2),
    pkg_at(k5, l2_1),
    pkg_at(k6, l3_3),
    pkg_at(k7, l3_2),
    pkg_at(k8, a3),
    pkg_at(k9, l2_4),
    pkg_at(k10, l1_1),
    pkg_at(k11, l4_1),
    pkg_at(k12, l3_4),
    pkg_at(k13, l4_3),
    pkg_at(k14, l4_4),
    pkg_at(k15, l2_4),
    pkg_at(k16, l1_1),
    pkg_at(k17, l3_2),
    pkg_at(k18, a1),
    pkg_at(k19, l4_3),
    pkg_at(k20, l4_3)
  ]
).
