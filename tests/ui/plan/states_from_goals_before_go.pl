% ui: kbc plan $CASE
% The states come from facts and findall/3, as Prolog computes them before `go`.
wanted(b1, 2, 2).
start_state([available(a1), ontable(b1, 1, 1), clear(b1)]).
test1 :- start_state(Init), findall(ontable(B, X, Y), wanted(B, X, Y), Goal), go(Init, Goal).
