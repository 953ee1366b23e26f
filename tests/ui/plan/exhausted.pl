% ui: kbc plan $CASE
% One token, consumed by whichever action runs first: each goal literal is reachable on its
% own, but never both, and no invariant tells the two apart before the search has tried.
action(bake(cake), [flour], [], [], [], [del(flour), add(baked(cake))]).
action(bake(bread), [flour], [], [], [], [del(flour), add(baked(bread))]).
breakfast :- go([flour], [baked(cake), baked(bread)]).
