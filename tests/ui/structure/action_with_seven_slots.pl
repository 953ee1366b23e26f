action(push(A), [available(A)], [], [], [], [], [del(available(A))]).
