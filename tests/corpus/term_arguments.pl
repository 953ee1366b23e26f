% expect: plan t
% Arguments of every kind of term an action can take: an operator term, a float, a list, a
% string, atoms that need quotes, a nested compound. tests/cli.rs runs it on the trace host.
action(put_start(R, X, P), [free(R), item(X)], [], [], [member(P, [1-2, 2.5, [a, b], "s", 'odd name', '_A', f(g(h))])], [del(free(R)), add(putting(R, X, P))]).
action(put_end(R, X, P), [putting(R, X, P)], [], [], [], [del(putting(R, X, P)), add(placed(X, P)), add(free(R))]).
t :- go([free(r1), free(r2), item(i1), item(i2), item(i3), item(i4), item(i5), item(i6), item(i7)],
        [placed(i1, 1-2), placed(i2, 2.5), placed(i3, [a, b]), placed(i4, "s"), placed(i5, 'odd name'), placed(i6, '_A'), placed(i7, f(g(h)))]).
