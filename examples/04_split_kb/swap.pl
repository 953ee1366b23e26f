% One problem per file with init_state/goal_state: it is named after the file (`swap`).
init_state([at(r1, 1, 1), idle(r1), at(r2, 3, 1), idle(r2)]).
goal_state([at(r1, 3, 1), at(r2, 1, 1)]).
