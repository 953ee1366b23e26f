action(stack(A, B), [holding(A, B)], [on(B, _)], [], [], [del(holding(A, B)), add(on(B, Below)), add(free(A))]).
