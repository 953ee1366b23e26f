% ui: kbc plan $CASE
% The only action that adds the goal leaves `Below` unbound (W0010): it never applies, and
% the plan that needs it fails with E0213, naming the effect.
action(stack(A, B), [holding(A, B)], [], [], [], [del(holding(A, B)), add(on(B, Below)), add(free(A))]).
test1 :- go([holding(a1, b1)], [on(b1, _)]).
