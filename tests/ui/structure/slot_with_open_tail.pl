action(push(A), [available(A)|Rest], [], [], [], [del(available(A))]).
