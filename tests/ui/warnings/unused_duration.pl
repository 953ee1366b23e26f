% ui: kbc plan $CASE
% A misspelt name, an instantaneous action, and a start and end of different arities: Prolog
% loads the three durations and nothing reads them, so the KB plans with warnings.
action(push_start(A), [available(A)], [], [], [], [del(available(A)), add(pushing(A))]).
action(push_end(A), [pushing(A)], [], [], [], [del(pushing(A)), add(available(A)), add(pushed(A))]).
action(wave(A), [available(A)], [], [], [], [add(waved(A))]).
action(lift_start(A, L), [available(A), load(L)], [], [], [], [add(lifting(A))]).
action(lift_end(A), [lifting(A)], [], [], [], [del(lifting(A)), add(lifted(A))]).
duration(psuh(_), 1, 2).
duration(wave(_), 1, 2).
duration(lift(_, _), 1, 2).
prob :- go([available(a1), load(l1)], [pushed(a1), waved(a1), lifted(a1)]).
