% A domain written as a module, as SWI-Prolog users split a KB.
:- module(pushing, [action/6, duration/3]).
action(push_start(R, B), [free(R), at(B, X)], [], [], [X < 3], [del(free(R)), add(pushing(R, B))]).
action(push_end(R, B), [pushing(R, B), at(B, X)], [], [], [X1 is X + 1, X1 =< 3], [del(pushing(R, B)), del(at(B, X)), add(at(B, X1)), add(free(R))]).
duration(push(_, _), 2, 3).
