% ui: kbc plan $CASE
% The only action that adds the goal has it in its InvalidAtEnd list, which is checked against
% the goal (the paper's meaning): E0306 points at that literal.
action(make(X), [raw(X)], [], [made(X)], [], [del(raw(X)), add(made(X))]).
t :- go([raw(a)], [made(a)]).
