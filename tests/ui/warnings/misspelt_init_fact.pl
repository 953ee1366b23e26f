test1 :- go([avaliable(a1), available(a2), ontable(b1, 1, 1), clear(b1)],
            [ontable(b1, 2, 2)]).
