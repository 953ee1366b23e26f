% ui: kbc plan $CASE --schedule -q
% `unstack_start` has no end: planned as an instantaneous action (W0019), as the paper's
% planner applies it; `take` is durative, and its end follows its own start.
action(unstack_start(H, X), [free(H), on(X, table)], [], [], [],
    [del(free(H)), del(on(X, table)), add(loose(X)), add(free(H))]).
action(take_start(H, X), [free(H), loose(X)], [], [], [],
    [del(free(H)), del(loose(X)), add(taking(H, X))]).
action(take_end(H, X), [taking(H, X)], [], [], [],
    [del(taking(H, X)), add(held(H, X)), add(free(H))]).
duration(take(_, _), 2, 3).
test1 :- go([free(h1), on(a, table)], [held(h1, a)]).
