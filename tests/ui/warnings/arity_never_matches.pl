% A condition and a deletion with an arity no state fact has never match: warnings, and the
% problem still plans as Prolog would run it.
action(push(A), [available(A)], [pushed(A, _)], [], [], [del(available(A)), del(stuck(A, x)), add(pushed(A))]).
action(unstick(A), [stuck(A)], [], [], [], [del(stuck(A))]).
test1 :- go([available(a1), stuck(a1)], [pushed(a1)]).
