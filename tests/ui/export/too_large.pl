% ui: kbc export pddl $CASE -o target/ui-export-never-written --limit 20
% Every cell is a possible destination: the relaxed exploration passes the limit of 20 action
% instances.
cell(X, Y) :- member(X, [1, 2, 3, 4, 5, 6]), member(Y, [1, 2, 3, 4, 5, 6]).
action(move_start(R, X1, Y1, X2, Y2), [at(R, X1, Y1)], [], [], [cell(X2, Y2)], [del(at(R, X1, Y1)), add(going(R, X2, Y2))]).
action(move_end(R, _X1, _Y1, X2, Y2), [going(R, X2, Y2)], [], [], [], [del(going(R, X2, Y2)), add(at(R, X2, Y2))]).
duration(move(_, _, _, _, _), 1, 1).
tour :- go([at(r1, 1, 1)], [at(r1, 6, 6)]).
