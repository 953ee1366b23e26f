test1(Actions, Times) :- go([available(a1), ontable(b1, 1, 1), clear(b1)],
                            [ontable(b1, 2, 2)], Actions, Times, deep).
