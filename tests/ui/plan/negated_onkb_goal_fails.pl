% ui: kbc plan $CASE
% The only action that could reach the goal needs `\+ forbidden(knife, s1)`, and the KB
% proves `forbidden(knife, s1)`: E0306 says the negation fails because its goal is provable
% (not that the goal is unprovable).
spot(s1).
spot(s2).
forbidden(knife, s1).
action(place(Obj, Spot), [holding(Obj)], [], [], [spot(Spot), \+ forbidden(Obj, Spot)],
    [del(holding(Obj)), add(on_counter(Obj, Spot))]).
test1 :- go([holding(knife)], [on_counter(knife, s1)]).
