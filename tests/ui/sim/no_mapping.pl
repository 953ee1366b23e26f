% ui: kbc run $CASE --host sim
% The simulated arms cannot wave: `wave` has no mapping onto their primitives.
action(wave_start(A), [idle(A)], [], [], [], [del(idle(A)), add(waving(A))]).
action(wave_end(A), [waving(A)], [], [], [], [del(waving(A)), add(idle(A)), add(waved(A))]).
hello :- go([idle(a1), available(a1), ontable(b1, 1, 1)], [waved(a1)]).
duration(wave(_), 1, 2).
