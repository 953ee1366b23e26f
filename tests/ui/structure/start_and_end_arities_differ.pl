action(push_start(A, B), [available(A), clear(B)], [], [], [], [del(available(A)), add(pushing(A, B))]).
action(push_end(A), [pushing(A, _)], [], [], [], [add(available(A))]).
