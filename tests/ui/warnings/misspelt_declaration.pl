% A fact named like a declaration kbc reads, that nothing calls (W0012).
action(go_a, [start], [], [], [], [add(at_a)]).
mappings(go_a, [step1]).
t :- go([start], [at_a]).
