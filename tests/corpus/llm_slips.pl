% expect: plan test_case
% expect: warn W0002
% expect: warn W0008
% expect: warn W0011
% expect: warn W0012
% A KB with the slips a language model makes, each of which Prolog runs: a misspelt Valid
% condition in an alternative action, an Invalid literal with a wrong arity, a start and an end
% with different arities, and `mappings/2` for `mapping/2`. The plan uses what works.
action(pick(A, B), [arm_free(A), on_table(B)], [holding(A, B, _)], [], [], [del(arm_free(A)), del(on_table(B)), add(holding(A, B))]).
action(pick(A, B), [arm_fre(A), on_shelf(B)], [], [], [], [del(on_shelf(B)), add(holding(A, B))]).
action(put_start(A, B), [holding(A, B)], [], [], [], [del(holding(A, B)), add(putting(A, B))]).
action(put_end(A), [putting(A, B)], [], [], [], [del(putting(A, B)), add(arm_free(A)), add(in_box(B))]).
mappings(pick(A, B), [reach(A, B)]).
test_case :- go([arm_free(a1), on_table(b1)], [in_box(b1), arm_free(a1)]).
