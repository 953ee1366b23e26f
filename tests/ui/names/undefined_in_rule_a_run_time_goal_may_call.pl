% An OnKB goal calls a goal known only at run time (`call(G)`), which may be any rule: so
% `ok_to_go/0` is not taken as a rule planning never runs, and its undefined call stays
% E0210 (SWI-Prolog raises the existence error while planning), not W0020.
check_goal(ok_to_go).
ok_to_go :- weather_ok.
action(go_out, [home], [], [], [check_goal(G), call(G)], [del(home), add(out)]).
t1 :- go([home], [out]).
