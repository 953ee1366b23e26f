% ui: kbc plan $CASE
% An OnKB goal that evaluates an atom as a number: SWI-Prolog raises a type error, and so
% does kbc's resolution engine, which stops the search.
action(step(N), [counter(N)], [], [], [M is N + one], [del(counter(N)), add(counter(M))]).
count :- go([counter(0)], [counter(2)]).
