% expect: plan deliver length 3
% expect: warn W0015
% A language model's KB for a warehouse robot whose initial state does not say where the robot
% is: `at(r1, Where)`. SWI-Prolog runs it (the first condition that meets the variable binds
% it); kbc gives `Where` the first value with a plan, here `aisle2`, beside the parcel.
road(depot, aisle1).
road(aisle1, aisle2).
road(aisle2, dock).
action(drive(R, From, To), [at(R, From)], [], [], [road(From, To)], [del(at(R, From)), add(at(R, To))]).
action(load(R, P), [at(R, L), parcel_at(P, L)], [carrying(R, _)], [], [], [del(parcel_at(P, L)), add(carrying(R, P))]).
action(unload(R, P), [at(R, dock), carrying(R, P)], [], [], [], [del(carrying(R, P)), add(parcel_at(P, dock))]).
deliver :- go([at(r1, Where), parcel_at(p1, aisle2)], [parcel_at(p1, dock)]).
