action(push_start(A, B),
    [available(A), clear(B)],
    [], [], [],
    [del(available(A)), add(pushing(A, B))]).
