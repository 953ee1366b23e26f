% ui: kbc export pddl $CASE -o target/ui-export-never-written
% A state literal with a variable inside a compound argument: PDDL cannot look inside it.
action(pick_start(A, B), [free(A), at(B, pos(X, Y))], [], [], [], [del(free(A)), del(at(B, pos(X, Y))), add(holding(A, B))]).
action(pick_end(A, B), [holding(A, B)], [], [], [], [add(free(A))]).
duration(pick(_, _), 1, 1).
demo :- go([free(a1), at(b1, pos(1, 1))], [holding(a1, b1)]).
