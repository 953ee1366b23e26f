% ui: kbc plan $CASE
% Rules nothing kbc runs calls (no OnKB goal, `duration/3` or goal before `go` reaches them)
% may call undefined predicates: SWI-Prolog loads them and raises an existence error only if
% they are called, so each is warning W0020 and the problem plans. The same call in a rule an
% OnKB goal reaches stays error E0210 (tests/ui/errors).
action(heat(Pan), [cold(Pan)], [], [], [ok_pan(Pan)], [del(cold(Pan)), add(hot(Pan))]).
pan(p1).
ok_pan(P) :- pan(P).
report :- show_plan, format("done~n").
report_all :- tset1, write(done).
first_pan(P) :- member(P).
after(X) :- test1, X = 1, heat_all.
test1 :- go([cold(p1)], [hot(p1)]).
