% An OnKB goal reaches `remember/1`, which calls a predicate kbc does not provide.
action(note(X), [], [], [], [remember(X)], [add(noted(X))]).
remember(X) :- assertz(seen(X)).
