action(push_start(A, B), [avialable(A), clear(B)], [], [], [], [del(available(A)), add(pushing(A, B))]).
action(push_end(A, B), [pushing(A, B)], [], [], [], [del(pushing(A, B)), add(available(A))]).
test1 :- go([available(a1), clear(b1)], [pushing(a1, b1)]).
