% A test that succeeds when there is no plan, and one that plans only if `true` fails.
test1 :- \+ go([available(a1), ontable(b1, 1, 1), clear(b1)], [ontable(b1, 2, 2)]).
test2 :- ( true ; go([available(a1), ontable(b1, 1, 1), clear(b1)], [ontable(b1, 2, 2)]) ).
