% ui: kbc plan $CASE
% A `duration/3` rule that calls itself runs out of its budget when the search asks it for
% the action's least time: the error names the duration clause, not the action's OnKB goals.
action(a_start, [p], [], [], [], [del(p), add(r)]).
action(a_end, [r], [], [], [], [del(r), add(q)]).
duration(a, D, D) :- duration(a, D, D).
t :- go([p], [q]).
