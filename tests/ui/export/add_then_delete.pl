% ui: kbc export pddl $CASE -o target/ui-export-never-written
% Effects apply in list order in kbc, deletions first in PDDL: this list would mean something
% else there.
action(stack_start(A, B, C), [holding(A, B), clear(C)], [], [], [], [add(clear(B)), del(clear(C)), del(holding(A, B))]).
action(stack_end(A, B, C), [clear(B)], [], [], [], [add(on(B, C)), add(free(A))]).
duration(stack(_, _, _), 1, 2).
demo :- go([holding(a1, b1), clear(b2)], [on(b1, b2)]).
