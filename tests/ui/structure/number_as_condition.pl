action(wait(A), [available(A), 42], [], [], [], [add(rested(A))]).
