% ui: kbc plan $CASE
% The initial state's variable is tried with every value kbc tries (W0015); none gives a plan,
% and E0306 explains the first while a note says what was tried.
action(press, [lamp(on)], [], [], [], [add(done)]).
t :- go([lamp(Q)], [done, lamp(off)]).
