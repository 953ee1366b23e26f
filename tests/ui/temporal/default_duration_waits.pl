% ui: kbc plan --schedule $CASE
% `wait` has no duration/3 answer, and its end must wait for `long` (5 units), which it starts.
% The default duration is at least 1 unit with no maximum, so the schedule is consistent:
% wait lasts as long as it must (W0006 only; with exactly 1 unit this was E0401).
duration(long, 5, 5).
action(wait_start, [idle], [], [], [], [del(idle), add(waiting)]).
action(long_start, [waiting], [], [], [], [add(working)]).
action(long_end, [working], [], [], [], [del(working), add(made)]).
action(wait_end, [waiting, made], [], [], [], [del(waiting), add(idle), add(done)]).
t :- go([idle], [idle, done]).
