% Tests written `test(N) :- go(...)`: Prolog runs `?- test(1).` and `?- test(2).` apart, so
% each head with arguments and no variable in them is a problem of its own, named as written.
% The same head twice is still one problem defined twice.
test(1) :- go([available(a1), ontable(b1, 1, 1), clear(b1)], [ontable(b1, 2, 2)]).
test(2) :- go([available(a1), ontable(b1, 1, 1), clear(b1)], [ontable(b1, 3, 3)]).
test(two, 'B') :- go([available(a1), ontable(b1, 1, 1), clear(b1)], [ontable(b1, 4, 4)]).
test( 1 ) :- go([available(a1), ontable(b1, 1, 1), clear(b1)], [ontable(b1, 5, 5)]).
