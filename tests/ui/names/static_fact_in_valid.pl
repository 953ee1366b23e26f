action(move_start(A, X), [available(A), cell(X)], [], [], [], [del(available(A)), add(moving(A, X))]).
action(move_end(A, X), [moving(A, X)], [], [], [], [del(moving(A, X)), add(at(A, X)), add(available(A))]).
cell(1).
