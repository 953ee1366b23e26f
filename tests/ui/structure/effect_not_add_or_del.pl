action(push(A), [available(A)], [], [], [], [retract(available(A)), assert(busy(A))]).
