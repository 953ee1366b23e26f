% The goals before `go` never end: the engine's budget stops them, with no cascade of
% warnings about the state facts the missing initial state would have held.
action(a, [p], [], [], [], [add(q)]).
loop(X) :- loop(X).
t1 :- loop(I), go(I, [q]).
