% ui: kbc plan $CASE
% Test wrappers as older KBs write them, and a debugger directive: recognised and ignored with
% notes; the problem plans.
:- trace(action, all).
action(go_a, [], [], [], [], [add(at_a)]).
test3(Actions, Times) :- go([], [at_a], Actions, Times).
testCase(A, T) :- test3(A, T).
testTrace :- leash(-all), trace, testCase(_, _).
% A wrapper may also unify and compare around its test.
testCase(1, T, R) :- test3(A, T), A \== [], R = ok.
% And stop SWI-Prolog after it.
main :- testCase(_, _), halt.
