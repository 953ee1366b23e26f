action(push(A), [available(A)], [broken(A)], [], [], [del(available(A)), add(pushed(A))]).
test1 :- go([available(a1)], [pushed(a1)]).
