test1 :- go([available(a1), ontable(b1, 1, 1), clear(b1)], [ontable(b1, 2, 2)]), write(done), nl.
test2 :- ( go([available(a1), ontable(b1, 1, 1), clear(b1)], [ontable(b1, 3, 3)]) -> true ; write(failed) ).
