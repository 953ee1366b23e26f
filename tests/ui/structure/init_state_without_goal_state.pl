init_state([available(a1), ontable(b1, 1, 1), clear(b1)]).
