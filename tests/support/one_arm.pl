% A one-arm world for the language server's tests, with one mistake: a misspelt predicate
% in pick_start's Valid list (line 5).
resources(agent(_)).
action(pick_start(A, B),
    [agent(A), ontabel(B), clear(B)], [], [], [],
    [del(agent(A)), del(ontable(B)), add(holding(A, B))]).
action(pick_end(A, B),
    [holding(A, B)], [], [], [],
    [del(holding(A, B)), add(agent(A)), add(held(B))]).

duration(pick(_, _), 1, 2).

test1 :- go([agent(a1), ontable(b1), clear(b1)], [held(b1)]).
