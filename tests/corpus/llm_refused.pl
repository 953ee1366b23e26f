% expect: refuse E0213
% expect: warn W0010
% A language model's KB whose only way to the goal adds a fact with a variable nothing binds.
action(stack(A, B), [holding(A, B)], [], [], [], [del(holding(A, B)), add(on(B, Below)), add(free(A))]).
test1 :- go([holding(a1, b1)], [on(b1, _)]).
