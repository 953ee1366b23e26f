% A deletion with a variable nothing binds removes every fact that unifies (W0009).
action(reset(X), [box(X)], [], [], [], [del(at(X, _)), add(home(X))]).
test1 :- go([box(b1), at(b1, 3), at(b1, 4)], [home(b1)]).
