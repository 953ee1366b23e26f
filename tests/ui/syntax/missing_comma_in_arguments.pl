pos(1 2).
