% ui: kbc run $CASE
% The mapping's steps use X and Y, which the high-level action does not bind.
action(fetch_start(A, B), [available(A), ontable(B, X, Y)], [], [], [], [del(available(A)), add(fetching(A, B, X, Y))]).
action(fetch_end(A, B), [fetching(A, B, X, Y)], [], [], [], [del(fetching(A, B, X, Y)), add(available(A)), add(fetched(B))]).
mapping(fetch_start(A, B), [move_over(A, X, Y), descend(A), close(A, B)]).
fetch :- go([available(a1), ontable(b1, 1, 1)], [fetched(b1)]).
duration(fetch(_, _), 1, 2).
