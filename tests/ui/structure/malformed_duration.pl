action(push_start(A), [available(A)], [], [], [], [del(available(A)), add(pushing(A))]).
action(push_end(A), [pushing(A)], [], [], [], [del(pushing(A)), add(available(A))]).
duration(3, 1, 2).
duration(push(_), 1, long).
