action(wait_start, [idle], [], [], [], [del(idle), add(waiting)]).
action(wait_end, [waiting], [], [], [], [del(waiting), add(idle), add(waited)]).
duration(wait, 3, 1).
t1 :- go([idle], [waited]).
