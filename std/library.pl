% std/library.pl: the library predicates of SWI-Prolog that kbc provides in Prolog, written for
% kbc from their documented behaviour (SWI-Prolog 9: library(lists), library(apply),
% library(aggregate), library(pairs), library(ordsets), and bagof/3 and setof/3).
%
% kbc loads the predicates of this file that a KB calls (by name, directly or through these
% clauses), unless the KB defines them itself: as SWI-Prolog's autoloader, a KB's own
% `append/3` replaces this one. The predicates written in Rust (`findall/3`, `length/2`,
% `between/3`, `msort/2`, ...) are in src/builtins.rs. Helpers are named `'$...'`, which no KB
% is expected to define. The tests hold every predicate here against SWI-Prolog
% (tests/engine/library_queries.pl).

% ---- control ---------------------------------------------------------------------------------

forall(Condition, Action) :- \+ (Condition, \+ Action).

% ---- lists -----------------------------------------------------------------------------------

memberchk(X, List) :- member(X, List), !.

append([], List, List).
append([X|Xs], List, [X|Rest]) :- append(Xs, List, Rest).

append(Lists, List) :- must_be(list, Lists), '$append'(Lists, List).
'$append'([], []).
'$append'([L|Ls], List) :- append(L, Rest, List), '$append'(Ls, Rest).

% nth0/3, nth1/3: by an integer index, the element there (a partial list is extended to it);
% by an unbound index, every element with its index.
nth0(Index, List, Elem) :- '$nth'(Index, List, Elem, 0).
nth1(Index, List, Elem) :- '$nth'(Index, List, Elem, 1).
'$nth'(Index, List, Elem, Base) :-
    integer(Index), !,
    Skip is Index - Base,
    Skip >= 0,
    '$nth_at'(Skip, List, Elem).
'$nth'(Index, List, Elem, Base) :-
    var(Index), !,
    '$nth_each'(List, Elem, Base, Index).
'$nth'(Index, _, _, _) :- must_be(integer, Index).
'$nth_at'(0, List, Elem) :- !, List = [Elem|_].
'$nth_at'(Skip, [_|Rest], Elem) :- Skip1 is Skip - 1, '$nth_at'(Skip1, Rest, Elem).
'$nth_each'([Elem|_], Elem, Index, Index).
'$nth_each'([_|Rest], Elem, At, Index) :- At1 is At + 1, '$nth_each'(Rest, Elem, At1, Index).

last([X|Xs], Last) :- '$last'(Xs, X, Last).
'$last'([], Last, Last).
'$last'([X|Xs], _, Last) :- '$last'(Xs, X, Last).

% reverse/2: the second list's length bounds the first's, so an unbound first list has one
% answer rather than an endless search.
reverse(List, Reversed) :- '$reverse'(List, [], Reversed, Reversed).
'$reverse'([], Reversed, Reversed, []).
'$reverse'([X|Xs], Acc, Reversed, [_|Bound]) :- '$reverse'(Xs, [X|Acc], Reversed, Bound).

nextto(X, Y, [X, Y|_]).
nextto(X, Y, [_|Rest]) :- nextto(X, Y, Rest).

select(X, [X|Rest], Rest).
select(X, [Y|Ys], [Y|Rest]) :- select(X, Ys, Rest).

selectchk(X, List, Rest) :- select(X, List, Rest), !.

select(X, [X|Rest], Y, [Y|Rest]).
select(X, [Z|Xs], Y, [Z|Ys]) :- select(X, Xs, Y, Ys).

subtract([], _, []).
subtract([X|Xs], Remove, Rest) :-
    (   memberchk(X, Remove)
    ->  subtract(Xs, Remove, Rest)
    ;   Rest = [X|Rest1],
        subtract(Xs, Remove, Rest1)
    ).

intersection([], _, []).
intersection([X|Xs], Other, Common) :-
    (   memberchk(X, Other)
    ->  Common = [X|Common1],
        intersection(Xs, Other, Common1)
    ;   intersection(Xs, Other, Common)
    ).

union([], Other, Other).
union([X|Xs], Other, Union) :-
    (   memberchk(X, Other)
    ->  union(Xs, Other, Union)
    ;   Union = [X|Union1],
        union(Xs, Other, Union1)
    ).

% delete/3: every element that unifies with Elem is left out (none is bound by the test).
delete([], _, []).
delete([X|Xs], Elem, Rest) :-
    (   X \= Elem
    ->  Rest = [X|Rest1],
        delete(Xs, Elem, Rest1)
    ;   delete(Xs, Elem, Rest)
    ).

permutation([], []).
permutation(List, [X|Perm]) :- select(X, List, Rest), permutation(Rest, Perm).

flatten(List, Flat) :- '$flatten'(List, [], Flat0), !, Flat = Flat0.
'$flatten'(Var, Tail, [Var|Tail]) :- var(Var), !.
'$flatten'([], Tail, Tail) :- !.
'$flatten'([X|Xs], Tail, Flat) :- !, '$flatten'(X, Rest, Flat), '$flatten'(Xs, Tail, Rest).
'$flatten'(X, Tail, [X|Tail]).

sum_list(Numbers, Sum) :- '$sum_list'(Numbers, 0, Sum).
sumlist(Numbers, Sum) :- '$sum_list'(Numbers, 0, Sum).
'$sum_list'([], Sum, Sum).
'$sum_list'([X|Xs], Sum0, Sum) :- Sum1 is Sum0 + X, '$sum_list'(Xs, Sum1, Sum).

max_list([X|Xs], Max) :- '$max_list'(Xs, X, Max).
'$max_list'([], Max, Max).
'$max_list'([X|Xs], Max0, Max) :- Max1 is max(Max0, X), '$max_list'(Xs, Max1, Max).

min_list([X|Xs], Min) :- '$min_list'(Xs, X, Min).
'$min_list'([], Min, Min).
'$min_list'([X|Xs], Min0, Min) :- Min1 is min(Min0, X), '$min_list'(Xs, Min1, Min).

numlist(Low, High, List) :-
    must_be(integer, Low),
    must_be(integer, High),
    Low =< High,
    '$numlist'(Low, High, List).
'$numlist'(High, High, List) :- !, List = [High].
'$numlist'(Low, High, [Low|Rest]) :- Next is Low + 1, '$numlist'(Next, High, Rest).

% max_member/2, min_member/2: in the standard order of terms.
max_member(Max, [X|Xs]) :- '$max_member'(Xs, X, Max).
'$max_member'([], Max, Max).
'$max_member'([X|Xs], Max0, Max) :-
    (   X @> Max0
    ->  '$max_member'(Xs, X, Max)
    ;   '$max_member'(Xs, Max0, Max)
    ).
min_member(Min, [X|Xs]) :- '$min_member'(Xs, X, Min).
'$min_member'([], Min, Min).
'$min_member'([X|Xs], Min0, Min) :-
    (   X @< Min0
    ->  '$min_member'(Xs, X, Min)
    ;   '$min_member'(Xs, Min0, Min)
    ).

% list_to_set/2: the first of each set of identical (==) elements, in their order.
list_to_set(List, Set) :- '$list_to_set'(List, [], Set).
'$list_to_set'([], _, []).
'$list_to_set'([X|Xs], Seen, Set) :-
    (   '$seen'(X, Seen)
    ->  '$list_to_set'(Xs, Seen, Set)
    ;   Set = [X|Set1],
        '$list_to_set'(Xs, [X|Seen], Set1)
    ).
'$seen'(X, [Y|Ys]) :- ( X == Y -> true ; '$seen'(X, Ys) ).

pairs_keys_values([], [], []).
pairs_keys_values([K-V|Pairs], [K|Ks], [V|Vs]) :- pairs_keys_values(Pairs, Ks, Vs).
pairs_keys([], []).
pairs_keys([K-_|Pairs], [K|Ks]) :- pairs_keys(Pairs, Ks).
pairs_values([], []).
pairs_values([_-V|Pairs], [V|Vs]) :- pairs_values(Pairs, Vs).

% ---- applying goals to lists ---------------------------------------------------------------

include(_, [], []).
include(Goal, [X|Xs], Included) :-
    (   call(Goal, X)
    ->  Included = [X|Included1]
    ;   Included = Included1
    ),
    include(Goal, Xs, Included1).

exclude(_, [], []).
exclude(Goal, [X|Xs], Kept) :-
    (   call(Goal, X)
    ->  Kept = Kept1
    ;   Kept = [X|Kept1]
    ),
    exclude(Goal, Xs, Kept1).

partition(_, [], [], []).
partition(Goal, [X|Xs], Included, Excluded) :-
    (   call(Goal, X)
    ->  Included = [X|Included1],
        Excluded = Excluded1
    ;   Included = Included1,
        Excluded = [X|Excluded1]
    ),
    partition(Goal, Xs, Included1, Excluded1).

maplist(_, []).
maplist(Goal, [X|Xs]) :- call(Goal, X), maplist(Goal, Xs).
maplist(_, [], []).
maplist(Goal, [X|Xs], [Y|Ys]) :- call(Goal, X, Y), maplist(Goal, Xs, Ys).
maplist(_, [], [], []).
maplist(Goal, [X|Xs], [Y|Ys], [Z|Zs]) :- call(Goal, X, Y, Z), maplist(Goal, Xs, Ys, Zs).
maplist(_, [], [], [], []).
maplist(Goal, [X|Xs], [Y|Ys], [Z|Zs], [W|Ws]) :- call(Goal, X, Y, Z, W), maplist(Goal, Xs, Ys, Zs, Ws).

foldl(Goal, List, V0, V) :- '$foldl'(List, Goal, V0, V).
'$foldl'([], _, V, V).
'$foldl'([X|Xs], Goal, V0, V) :- call(Goal, X, V0, V1), '$foldl'(Xs, Goal, V1, V).
foldl(Goal, List1, List2, V0, V) :- '$foldl'(List1, List2, Goal, V0, V).
'$foldl'([], [], _, V, V).
'$foldl'([X|Xs], [Y|Ys], Goal, V0, V) :- call(Goal, X, Y, V0, V1), '$foldl'(Xs, Ys, Goal, V1, V).
foldl(Goal, List1, List2, List3, V0, V) :- '$foldl'(List1, List2, List3, Goal, V0, V).
'$foldl'([], [], [], _, V, V).
'$foldl'([X|Xs], [Y|Ys], [Z|Zs], Goal, V0, V) :-
    call(Goal, X, Y, Z, V0, V1),
    '$foldl'(Xs, Ys, Zs, Goal, V1, V).

% ---- every solution --------------------------------------------------------------------------

% bagof/3: the solutions of Goal, one list for each value of its free variables (those not in
% Template and not marked `V^`), in the standard order of those values; setof/3 sorts each.
bagof(Template, Goal, List) :-
    '$bagof_split'(Template^Goal, Stripped, Witness),
    (   Witness == []
    ->  findall(Template, Stripped, List),
        List \== []
    ;   findall(Witness-Template, Stripped, Pairs),
        '$bagof_groups'(Pairs, Groups),
        member(Witness-List, Groups)
    ).
setof(Template, Goal, Set) :- bagof(Template, Goal, List), sort(List, Set).

aggregate_all(count, Goal, Count) :- !, findall(x, Goal, List), length(List, Count).
aggregate_all(sum(Expr), Goal, Sum) :- !, findall(Expr, Goal, List), '$sum_list'(List, 0, Sum).
aggregate_all(max(Expr), Goal, Max) :- !, findall(Expr, Goal, [X|Xs]), '$aggregate_max'(Xs, X, Max).
aggregate_all(min(Expr), Goal, Min) :- !, findall(Expr, Goal, [X|Xs]), '$aggregate_min'(Xs, X, Min).
aggregate_all(max(Expr, Witness), Goal, max(Max, With)) :- !,
    findall(Expr-Witness, Goal, [X-W|Pairs]),
    '$aggregate_max_with'(Pairs, X, W, Max, With).
aggregate_all(min(Expr, Witness), Goal, min(Min, With)) :- !,
    findall(Expr-Witness, Goal, [X-W|Pairs]),
    '$aggregate_min_with'(Pairs, X, W, Min, With).
aggregate_all(bag(Template), Goal, Bag) :- !, findall(Template, Goal, Bag).
aggregate_all(set(Template), Goal, Set) :- !, findall(Template, Goal, Bag), sort(Bag, Set).
aggregate_all(Spec, _, _) :- must_be(oneof([count, sum(_), max(_), min(_), max(_, _), min(_, _), bag(_), set(_)]), Spec).
'$aggregate_max'([], Max0, Max) :- Max is Max0.
'$aggregate_max'([X|Xs], Max0, Max) :- Max1 is max(Max0, X), '$aggregate_max'(Xs, Max1, Max).
'$aggregate_min'([], Min0, Min) :- Min is Min0.
'$aggregate_min'([X|Xs], Min0, Min) :- Min1 is min(Min0, X), '$aggregate_min'(Xs, Min1, Min).
'$aggregate_max_with'([], Max0, With, Max, With) :- Max is Max0.
'$aggregate_max_with'([X-W|Pairs], Max0, With0, Max, With) :-
    (   X > Max0
    ->  '$aggregate_max_with'(Pairs, X, W, Max, With)
    ;   '$aggregate_max_with'(Pairs, Max0, With0, Max, With)
    ).
'$aggregate_min_with'([], Min0, With, Min, With) :- Min is Min0.
'$aggregate_min_with'([X-W|Pairs], Min0, With0, Min, With) :-
    (   X < Min0
    ->  '$aggregate_min_with'(Pairs, X, W, Min, With)
    ;   '$aggregate_min_with'(Pairs, Min0, With0, Min, With)
    ).

% ---- sorting ---------------------------------------------------------------------------------

% predsort/3: a merge sort on the order Goal gives (`<`, `>` or `=`); of two elements it calls
% `=`, the second is left out.
predsort(Goal, List, Sorted) :-
    length(List, N),
    '$predsort'(N, Goal, List, _, Sorted0), !,
    Sorted = Sorted0.
'$predsort'(0, _, List, List, []) :- !.
'$predsort'(1, _, [X|List], List, [X]) :- !.
'$predsort'(N, Goal, List0, List, Sorted) :-
    Half is N // 2,
    Other is N - Half,
    '$predsort'(Half, Goal, List0, List1, Sorted1),
    '$predsort'(Other, Goal, List1, List, Sorted2),
    '$predmerge'(Sorted1, Sorted2, Goal, Sorted).
'$predmerge'([], Sorted, _, Sorted) :- !.
'$predmerge'(Sorted, [], _, Sorted) :- !.
'$predmerge'([X|Xs], [Y|Ys], Goal, Sorted) :-
    call(Goal, Order, X, Y), !,
    '$predmerge'(Order, X, Xs, Y, Ys, Goal, Sorted).
'$predmerge'(<, X, Xs, Y, Ys, Goal, [X|Sorted]) :- '$predmerge'(Xs, [Y|Ys], Goal, Sorted).
'$predmerge'(=, X, Xs, _, Ys, Goal, [X|Sorted]) :- '$predmerge'(Xs, Ys, Goal, Sorted).
'$predmerge'(>, X, Xs, Y, Ys, Goal, [Y|Sorted]) :- '$predmerge'([X|Xs], Ys, Goal, Sorted).

% ---- ordered sets (lists sorted in the standard order, without duplicates) -------------------

list_to_ord_set(List, Set) :- sort(List, Set).

ord_union([], Set, Set) :- !.
ord_union(Set, [], Set) :- !.
ord_union([X|Xs], [Y|Ys], Union) :-
    compare(Order, X, Y),
    '$ord_union'(Order, X, Xs, Y, Ys, Union).
'$ord_union'(<, X, Xs, Y, Ys, [X|Union]) :- ord_union(Xs, [Y|Ys], Union).
'$ord_union'(=, X, Xs, _, Ys, [X|Union]) :- ord_union(Xs, Ys, Union).
'$ord_union'(>, X, Xs, Y, Ys, [Y|Union]) :- ord_union([X|Xs], Ys, Union).

ord_subtract([], _, []) :- !.
ord_subtract(Set, [], Set) :- !.
ord_subtract([X|Xs], [Y|Ys], Rest) :-
    compare(Order, X, Y),
    '$ord_subtract'(Order, X, Xs, Y, Ys, Rest).
'$ord_subtract'(<, X, Xs, Y, Ys, [X|Rest]) :- ord_subtract(Xs, [Y|Ys], Rest).
'$ord_subtract'(=, _, Xs, _, Ys, Rest) :- ord_subtract(Xs, Ys, Rest).
'$ord_subtract'(>, X, Xs, _, Ys, Rest) :- ord_subtract([X|Xs], Ys, Rest).

ord_intersection([], _, []) :- !.
ord_intersection(_, [], []) :- !.
ord_intersection([X|Xs], [Y|Ys], Common) :-
    compare(Order, X, Y),
    '$ord_intersection'(Order, X, Xs, Y, Ys, Common).
'$ord_intersection'(<, _, Xs, Y, Ys, Common) :- ord_intersection(Xs, [Y|Ys], Common).
'$ord_intersection'(=, X, Xs, _, Ys, [X|Common]) :- ord_intersection(Xs, Ys, Common).
'$ord_intersection'(>, X, Xs, _, Ys, Common) :- ord_intersection([X|Xs], Ys, Common).

ord_memberchk(X, [Y|Ys]) :-
    compare(Order, X, Y),
    '$ord_memberchk'(Order, X, Ys).
'$ord_memberchk'(=, _, _).
'$ord_memberchk'(>, X, Ys) :- ord_memberchk(X, Ys).

ord_subset([], _).
ord_subset([X|Xs], [Y|Ys]) :-
    compare(Order, X, Y),
    '$ord_subset'(Order, X, Xs, Ys).
'$ord_subset'(=, _, Xs, Ys) :- ord_subset(Xs, Ys).
'$ord_subset'(>, X, Xs, Ys) :- ord_subset([X|Xs], Ys).
