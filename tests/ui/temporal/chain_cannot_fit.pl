% ui: kbc plan $CASE
% The arm may hold the part for at most 2 time units, but the part must be polished while it
% is held, which takes at least 5: the orderings and durations form a cycle.
action(hold_start(A, P), [free(A), raw(P)], [], [], [], [del(free(A)), add(holding(A, P))]).
action(polish_start(P), [holding(_, P), raw(P)], [], [], [], [del(raw(P)), add(polishing(P))]).
action(polish_end(P), [polishing(P)], [], [], [], [del(polishing(P)), add(polished(P))]).
action(hold_end(A, P), [holding(A, P), polished(P)], [], [], [], [del(holding(A, P)), add(free(A))]).
duration(hold(_, _), 1, 2).
duration(polish(_), 5, 8).
finish :- go([free(a1), raw(p1)], [free(a1), polished(p1)]).
