% expect: plan test1
% expect: plan test2
% expect: note
% A harbour crane world in the authors' split-file style: actions here, facts in kb.pl,
% problems in tests.pl. The lift's end names the destination stack only in its head: it takes
% the value its start bound.
action(lift_start(C, K, From, To),
    [crane_free(C), top(K, From)],
    [busy(To)],
    [],
    [stack(To), From \= To],
    [del(crane_free(C)), del(top(K, From)), add(carrying(C, K)), add(busy(To))]).
action(lift_end(C, K, From, To),
    [carrying(C, K)],
    [],
    [],
    [],
    [del(carrying(C, K)), del(busy(To)), add(crane_free(C)), add(top(K, To))]).
