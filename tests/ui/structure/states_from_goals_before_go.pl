% Tests whose goals before `go` do not give it two lists of facts.
start([available(a1), ontable(b1, 1, 1), clear(b1)]).
no_start :- start(I), go(I, [ontable(b1, 2, 2) | _]).
not_a_list :- I = available(a1), go(I, [ontable(b1, 2, 2)]).
no_solution :- start(I), I = [], go(I, [ontable(b1, 2, 2)]).
an_error :- start(I), N is b1 + 1, go(I, [ontable(b1, N, 2)]).
a_number :- start(I), append(I, [3], J), go(J, [ontable(b1, 2, 2)]).
