% expect: plan test1
% expect: plan test2 length 5
% expect: warn W0014
% expect: refuse E0306
% expect: note
% A two-arm kitchen in the style of the paper's authors, split in three files: the actions
% (an end that takes the spot from its start's Valid list, an instantaneous hand-over with
% `dif/2`), the KB (`member/2` spots, reach by rules, a `\+` in OnKB) and these tests, which
% load the other two as SWI-Prolog would (the corpus loads all three, so the `include` is
% W0014). `testCase/2` unifies around its test and
% `testTrace/0` runs the debugger: test wrappers, notes. test3 asks for the knife on the one
% spot it is forbidden: E0306, which says the negation fails because `forbidden(knife, s1)`
% is provable. SWI-Prolog's run of the paper's search (tests/support/paper_search.pl) agrees:
% plans for test1 and test2, none for test3.
:- include('actions.pl').
:- ensure_loaded(kb).

test1 :- go([free(left), free(right), on_counter(cup, s1), on_counter(plate, s2), on_counter(bowl, s5)],
            [on_counter(cup, s5), on_counter(plate, s1), on_counter(bowl, s2)]).
test2 :- go([free(left), free(right), on_counter(knife, s5)], [on_counter(knife, s2)]).
test3 :- go([free(left), free(right), on_counter(knife, s5)], [on_counter(knife, s1)]).
testCase(1, T) :- test1, T = ok.
testTrace :- leash(-all), trace, testCase(_, _).
