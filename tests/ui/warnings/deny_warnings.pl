% ui: kbc check -D warnings $CASE
% With `-D warnings`, a warning (here W0002: a Valid condition nothing produces) is an error.
action(push(A), [avialable(A)], [], [], [], [del(available(A)), add(pushed(A))]).
test1 :- go([available(a1)], [pushed(a1)]).
