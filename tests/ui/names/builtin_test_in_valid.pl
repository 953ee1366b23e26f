% ui: kbc plan $CASE
% A test among the Valid conditions is matched against the state, as the paper's planner does:
% Prolog runs it and the action never applies, so it is a warning, and the goal that needed
% the action cannot be reached.
action(move(A, X, Y), [at(A, X), Y > X], [], [], [cell(Y)], [del(at(A, X)), add(at(A, Y))]).
cell(1).
cell(2).
test1 :- go([at(a1, 1)], [at(a1, 2)]).
