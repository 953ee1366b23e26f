% ui: kbc plan $CASE
% Test wrappers as older KBs write them, and a debugger directive: recognised and ignored with
% notes; the problem plans.
:- trace(action, all).
action(go_a, [], [], [], [], [add(at_a)]).
test3(Actions, Times) :- go([], [at_a], Actions, Times).
testCase(A, T) :- test3(A, T).
testTrace :- leash(-all), trace, testCase(_, _).
