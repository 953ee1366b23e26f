action(push_end(A, B),
    [pushing(A, B)],
    [], [], [],
    [del(pushing(A, B)), add(available(A))]).
