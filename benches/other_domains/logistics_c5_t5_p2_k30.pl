% Logistics: 5 cities of 5 places and an airport, a truck in each city, 2 planes,
% 30 packages. Trucks drive inside a city, planes fly between airports; both load and unload.
city_of(l1_1, c1). city_of(l1_2, c1). city_of(l1_3, c1). city_of(l1_4, c1). city_of(l1_5, c1). city_of(a1, c1). city_of(l2_1, c2). city_of(l2_2, c2). city_of(l2_3, c2). city_of(l2_4, c2). city_of(l2_5, c2). city_of(a2, c2). city_of(l3_1, c3). city_of(l3_2, c3). city_of(l3_3, c3). city_of(l3_4, c3). city_of(l3_5, c3). city_of(a3, c3). city_of(l4_1, c4). city_of(l4_2, c4). city_of(l4_3, c4). city_of(l4_4, c4). city_of(l4_5, c4). city_of(a4, c4). city_of(l5_1, c5). city_of(l5_2, c5). city_of(l5_3, c5). city_of(l5_4, c5). city_of(l5_5, c5). city_of(a5, c5).
airport(a1). airport(a2). airport(a3). airport(a4). airport(a5).
truck(t1). truck(t2). truck(t3). truck(t4). truck(t5).
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
    idle(t5),
    idle(p1),
    idle(p2),
    at(t1, l1_1),
    at(t2, l2_1),
    at(t3, l3_1),
    at(t4, l4_1),
    at(t5, l5_1),
    at(p1, a2),
    at(p2, a5),
    pkg_at(k1, a3),
    pkg_at(k2, a2),
    pkg_at(k3, l3_4),
    pkg_at(k4, l4_1),
    pkg_at(k5, l4_2),
    pkg_at(k6, a5),
    pkg_at(k7, l3_4),
    pkg_at(k8, a3),
    pkg_at(k9, l2_1),
    pkg_at(k10, l3_4),
    pkg_at(k11, l5_3),
    pkg_at(k12, l3_4),
    pkg_at(k13, l4_3),
    pkg_at(k14, l1_5),
    pkg_at(k15, l4_3),
    pkg_at(k16, l5_4),
    pkg_at(k17, l3_1),
    pkg_at(k18, l1_1),
    pkg_at(k19, l5_1),
    pkg_at(k20, a1),
    pkg_at(k21, l4_1),
    pkg_at(k22, l2_4),
    pkg_at(k23, l1_1),
    pkg_at(k24, l5_4),
    pkg_at(k25, l3_4),
    pkg_at(k26, a4),
    pkg_at(k27, l3_1),
    pkg_at(k28, l5_2),
    pkg_at(k29, l3_1),
    pkg_at(k30, l5_2)
  ],
  [ pkg_at(k1, l1_5),
    pkg_at(k2, l4_3),
    pkg_at(k3, l4_4),
    pkg_at(k4, l1_3),
    pkg_at(k5, l1_1),
    pkg_at(k6, l5_3),
    pkg_at(k7, l2_3),
    pkg_at(k8, l2_2),
    pkg_at(k9, a4),
    pkg_at(k10, l4_1),
    pkg_at(k11, a3),
    pkg_at(k12, l3_1),
    pkg_at(k13, l5_5),
    pkg_at(k14, l2_3),
    pkg_at(k15, l1_5),
    pkg_at(k16, l3_5),
    pkg_at(k17, l5_1),
    pkg_at(k18, l4_5),
    pkg_at(k19, l1_3),
    pkg_at(k20, l5_2),
    pkg_at(k21, l1_2),
    pkg_at(k22, l5_2),
    pkg_at(k23, l5_4),
    pkg_at(k24, l2_3),
    pkg_at(k25, l4_3),
    pkg_at(k26, a5),
    pkg_at(k27, a4),
    pkg_at(k28, l3_2),
    pkg_at(k29, l5_1),
    pkg_at(k30, l4_1)
  ]
).
