% q(Number, Template, Goal): every solution of Goal, as Template, in order.
q(1, X, app(X, _, [a, b, c])).
q(2, X-Y, app(X, Y, [a, b])).
q(3, N, len([a, b, c, d], N)).
q(4, R, rev([1, 2, 3], R)).
q(5, C, colour(C)).
q(6, X-Y, pos(X, Y)).
q(7, Y, path(a, Y)).
q(8, C, first_colour(C)).
q(9, M, max_of(3, 7, M)).
q(10, M, max_of(9, 7, M)).
q(11, S, classify(5, S)).
q(12, S, classify(50, S)).
q(13, S, classify(500, S)).
q(14, X2-Y2, neighbour(1, 1, X2, Y2)).
q(15, C, not_red(C)).
q(16, S, sign(5, S)).
q(17, S, sign(-5, S)).
q(18, S, sign(0, S)).
q(19, X, twice(X)).
q(20, X, cut_in_or(X)).
q(21, M, count_to(0, M)).
q(22, X-Y-Z, nested(f(1, g(2, [1, 3, 4])), X, Y, Z)).
q(23, F, fact(5, F)).
q(24, X, X is 7 / 2).
q(25, X, X is 6 / 3).
q(26, X, X is -7 // 2).
q(27, X, X is -7 mod 2).
q(28, X, X is 7 mod -2).
q(29, X, X is abs(-3) + min(2, 5) * max(1, 4)).
q(30, X, X is 2.5 * 4).
q(31, X, X is 1 + 2 * 3 - 4).
q(32, yes, 1 =:= 1.0).
q(33, yes, 1 == 1.0).
q(34, yes, 2 < 3).
q(35, yes, 3 =< 3).
q(36, yes, 4 >= 5).
q(37, yes, 4 =\= 5).
q(38, yes, a \= b).
q(39, yes, f(X) \= f(1)).
q(40, X, (X = 1 ; X = 2 ; X = 3)).
q(41, X, (member(X, [1, 2, 3]), X > 1)).
q(42, X, (member(X, [1, 2, 3]) -> true ; X = none)).
q(43, X, (member(X, []) -> true ; X = none)).
q(44, X, \+ member(x, [a, b])).
q(45, X-Y, (X = Y, Y = z)).
q(46, yes, f(A, B) == f(A, B)).
q(47, yes, f(A, B) == f(B, A)).
q(48, yes, A \== B).
q(49, L, (X = [1|T], T = [2, 3], L = X)).
q(50, X, (colour(X), X \== green)).
q(51, X, (member(X, [a, b, c]), !)).
q(52, X, ( \+ fail, X = ok )).
q(53, X, (true ; X = late)).
q(54, X, ((X = 1 ; X = 2) -> true ; true)).
q(55, X, (colour(X) , \+ (X = red ; X = blue))).
q(56, X, X is 10 - 2 - 3).
q(57, X, X is 2 * 3 / 4).
q(58, X, X is max(1, 1.0)).
q(59, Y, path(d, Y)).
q(60, X-Y, (edge(X, Y), \+ path(Y, d))).
q(61, X, X is 1 / 0).
q(62, X, X is foo + 1).
q(63, X, X is Y + 1).
q(64, X, (X > 1)).
q(65, T, (A = f(B), B = g(C), C = h, T = A)).
q(66, X, not(member(z, [a]))).
q(67, X-Y, (member(X, [1, 2]), member(Y, [a, b]))).
q(68, L, app([1], [2], L)).
q(69, yes, app(_, [c], [a, b, c])).
q(70, X, (X = 1, (X == 1 -> true ; fail))).
q(71, X, pick(X)).
q(72, X-Y, then_chain(X, Y)).
q(73, X, then_chain_fails(X)).
q(74, X, nest(X)).
q(75, X, left_if(X)).
q(76, X, last_if(X)).
q(77, X, last_if_fails(X)).
q(78, X, (X = 7, pick(X))).
q(79, X, (X = 5, pick(X))).
q(80, X, (X = 9, cut_in_branch(X))).
q(81, X, (X = 4, cut_in_branch(X))).
q(82, X, (X = 3, cut_in_branch(X))).
% Type tests and the standard order of terms.
q(100, T, (member(X, [_, 1, 2.5, a, "s", f(x), [y]]), ( var(X) -> T = var ; atom(X) -> T = atom ; integer(X) -> T = int ; float(X) -> T = float ; compound(X) -> T = compound ; T = other ))).
q(101, X, (member(X, [1, a, f(b), [], "s"]), atomic(X))).
q(102, X, (member(X, [1, a, f(b), [], _]), callable(X))).
q(103, X, (member(X, [[a], [a|_], a, []]), is_list(X))).
q(104, X, (member(X, [f(a), f(_), [a, b]]), ground(X))).
q(105, O, compare(O, 1, a)).
q(106, O, compare(O, f(a, b), g(a))).
q(107, O, compare(O, 1.0, 1)).
q(108, O, compare(O, b, a)).
q(109, O, compare(O, f(a, c), f(a, b))).
q(110, yes, a @< b).
q(111, yes, f(b) @> g(a)).
q(112, yes, "abc" @> zzz).
q(113, yes, 2 @=< 2.0).
q(114, S, msort([c, 1, b, f(a), 2.0, a, 1], S)).
q(115, S, sort([c, b, a, b, c], S)).
q(116, S, sort(0, @>=, [1, 3, 2, 3], S)).
q(117, S, sort(1, @<, [f(2, a), f(1, b), f(2, c)], S)).
q(118, S, sort(2, @>, [f(2, a), f(1, b), f(2, c)], S)).
q(119, S, keysort([b-1, a-2, b-0, a-1], S)).
q(120, S, predsort(by_second, [x-3, y-1, z-3, w-2], S)).
q(121, S, sort(a, S)).
q(122, S, msort([a|_], S)).
q(123, S, keysort([a-1, b], S)).
q(124, O, compare(foo, a, b)).
q(125, yes, f(A, B) =@= f(C, D)).
q(126, yes, f(A, A) =@= f(C, D)).
q(127, yes, f(A, b) \=@= f(C, D)).
% Terms.
q(130, N/A, functor(foo(a, b), N, A)).
q(131, T, functor(T, foo, 3)).
q(132, N/A, functor(abc, N, A)).
q(133, T, functor(T, 7, 0)).
q(134, X, arg(2, f(a, b, c), X)).
q(135, N-X, arg(N, f(a, b, c), X)).
q(136, L, f(a, g(b)) =.. L).
q(137, T, T =.. [point, 1, 2]).
q(138, T, T =.. [x]).
q(139, C, copy_term(f(X, Y, X), C)).
q(140, V, term_variables(f(X, g(Y, X), _Z), V)).
q(141, T, functor(T, foo, -1)).
q(142, T, arg(x, f(a), T)).
q(143, T, T =.. L).
q(144, T, functor(T, N, 2)).
% Numbers.
q(150, X, between(1, 4, X)).
q(151, X, between(3, 1, X)).
q(152, X, (between(1, inf, X), X > 3, !)).
q(153, yes, between(1, 3, 2)).
q(154, X, between(a, 3, X)).
q(155, X, between(1, 3, 2.0)).
q(156, X, succ(3, X)).
q(157, X, succ(X, 4)).
q(158, X, succ(X, 0)).
q(159, X, succ(X, _)).
q(160, X, succ(-1, X)).
q(161, X, plus(2, X, 7)).
q(162, X, plus(X, _, 7)).
q(163, N, length([a, b, c], N)).
q(164, L, length(L, 2)).
q(165, L-N, (length(L, N), N >= 2, !)).
q(166, L, (L = [a|T], length(L, 3))).
q(167, N, length(a, N)).
q(168, N, length([a|b], N)).
q(169, L, length(L, -1)).
q(170, L, length(L, a)).
q(171, yes, length([a, b], 3)).
% Arithmetic functions.
q(180, X, X is 2 ** 3).
q(181, X, X is 2 ** -1).
q(182, X, X is 2.0 ** 3).
q(183, X, X is 2 ^ 10).
q(184, X, X is 9 ** 0.5).
q(185, X, X is sqrt(16)).
q(186, X, X is sqrt(-1)).
q(187, X, X is 7 rem -2).
q(188, X, X is -7 div 2).
q(189, X, X is truncate(3.7)).
q(190, X, X is round(2.5)).
q(191, X, X is round(-2.5)).
q(192, X, X is ceiling(2.1)).
q(193, X, X is floor(-2.1)).
q(194, X, X is integer(2.5)).
q(195, X, X is float(3)).
q(196, X, X is sign(-3)).
q(197, X, X is sign(-2.5)).
q(198, X, X is gcd(12, 18)).
q(199, X, X is msb(8)).
q(200, X, X is 5 >> 1).
q(201, X, X is 5 << 2).
q(202, X, X is 5 /\ 3).
q(203, X, X is 5 \/ 3).
q(204, X, X is 5 xor 3).
q(205, X, X is \ 5).
q(206, X, X is pi).
q(207, X, X is e).
q(208, X, X is atan2(1, 2)).
q(209, X, X is atan(1, 2)).
q(210, X, X is exp(1)).
q(211, X, X is log(0)).
q(212, X, X is float_integer_part(3.7)).
q(213, X, X is float_fractional_part(-3.5)).
q(214, X, X is 0 ^ -1).
q(215, X, X is 1 ^ -3).
q(216, X, X is -1 ^ -3).
q(217, X, X is sin(pi / 2) + cos(0)).
q(218, X, X is 10 mod 0).
q(219, X, X is 7 rem 0).
q(220, X, X is abs(-3.0) + max(2, 3.0)).
q(221, X, X is 2 * (3 + 4)).
q(222, X, X is 10 - (2 - 3)).
q(223, X, X is asin(2)).
q(224, X, X is 2.5 rem 1).
% Every solution.
q(230, L, findall(X, member(X, [c, a, b]), L)).
q(231, L, findall(X-Y, (member(X, [1, 2]), member(Y, [a, b])), L)).
q(232, L, findall(X, fail, L)).
q(233, L, findall(X, member(X, [1, 2]), L, [end])).
q(234, L, findall(X, (member(X, [1, 2, 3]), !), L)).
q(235, L, findall(L1, findall(Y, member(Y, [x, y]), L1), L)).
q(236, yes, forall(member(X, [1, 2, 3]), X > 0)).
q(237, yes, forall(member(X, [1, -2, 3]), X > 0)).
q(238, N, aggregate_all(count, owns(_, _), N)).
q(239, S, aggregate_all(sum(S0), score(_, S0), S)).
q(240, M, aggregate_all(max(S0), score(_, S0), M)).
q(241, M, aggregate_all(min(S0), score(_, S0), M)).
q(242, M, aggregate_all(max(S0, P), score(P, S0), M)).
q(243, B, aggregate_all(bag(P), owns(P, _), B)).
q(244, B, aggregate_all(set(P), owns(P, _), B)).
q(245, M, aggregate_all(max(S0), (score(_, S0), S0 > 10), M)).
q(246, N, aggregate_all(count, fail, N)).
q(247, P-L, bagof(A, owns(P, A), L)).
q(248, L, bagof(A, P^owns(P, A), L)).
q(249, P-L, setof(A, owns(P, A), L)).
q(250, L, setof(A-P, owns(P, A), L)).
q(251, L, bagof(X, fail, L)).
q(252, A-L, setof(P, owns(P, A), L)).
q(253, L, setof(S0, P^score(P, S0), L)).
q(254, M, aggregate_all(min(S0, P), score(P, S0), M)).
% Calling goals.
q(260, X, call(member(X), [a, b])).
q(261, Y, call(double, 4, Y)).
q(262, X, call((X = 1 ; X = 2))).
q(263, X, call((member(X, [1, 2, 3]), !))).
q(264, X, (call(member(X, [1, 2])), X > 1)).
q(265, X, once(member(X, [a, b]))).
q(266, yes, ignore(fail)).
q(267, X, ignore(member(X, [p, q]))).
q(268, X, call(G)).
q(269, X, call(3)).
q(270, X, (G = member(X, [u, v]), G)).
q(271, X, (member(G, [X = 1, X = 2]), call(G))).
% Lists.
q(280, X-Y, append(X, Y, [1, 2])).
q(281, L, append([[a], [b, c], []], L)).
q(282, X, nth0(1, [a, b, c], X)).
q(283, I-X, nth1(I, [a, b], X)).
q(284, X, nth0(5, [a, b], X)).
q(285, L, nth0(1, L, x)).
q(286, X, nth1(a, [a], X)).
q(287, X, last([1, 2, 3], X)).
q(288, R, reverse([1, 2, 3], R)).
q(289, L, reverse(L, [1, 2])).
q(290, X-Y, nextto(X, Y, [1, 2, 3])).
q(291, X-R, select(X, [a, b, c], R)).
q(292, R, selectchk(b, [a, b, c, b], R)).
q(293, R, select(b, [a, b, c], x, R)).
q(294, R, subtract([1, 2, 3, 4], [2, 4], R)).
q(295, R, intersection([1, 2, 3, 4], [4, 2, 5], R)).
q(296, R, union([1, 2, 3], [2, 5], R)).
q(297, R, delete([a, B, a, c], a, R)).
q(298, R, include(positive, [1, -1, 2, 0], R)).
q(299, R, exclude(positive, [1, -1, 2, 0], R)).
q(300, I-E, partition(positive, [1, -1, 2, 0], I, E)).
q(301, L, maplist(double, [1, 2, 3], L)).
q(302, yes, maplist(positive, [1, 2, 3])).
q(303, L, (length(L, 2), maplist(=(z), L))).
q(304, S, foldl(add, [1, 2, 3], 0, S)).
q(305, S, sum_list([1, 2.5, 3], S)).
q(306, M, max_list([3, 1, 4, 1.5], M)).
q(307, M, min_list([3, 1, 4], M)).
q(308, L, numlist(3, 6, L)).
q(309, L, numlist(6, 3, L)).
q(310, M, max_member(M, [b, f(a), 3, z])).
q(311, M, min_member(M, [b, f(a), 3, z])).
q(312, S, list_to_set([a, b, a, c, b], S)).
q(313, P, permutation([1, 2, 3], P)).
q(314, F, flatten([1, [2, [3, 4]], [], 5], F)).
q(315, K-V, pairs_keys_values([a-1, b-2], K, V)).
q(316, P, pairs_keys_values(P, [x, y], [1, 2])).
q(317, K, pairs_keys([a-1, b-2], K)).
q(318, V, pairs_values([a-1, b-2], V)).
q(319, yes, memberchk(b, [a, b, c])).
q(320, X, memberchk(X, [a, b])).
q(321, S, list_to_ord_set([c, a, b, a], S)).
q(322, U, ord_union([a, c], [b, c, d], U)).
q(323, D, ord_subtract([a, b, c], [b], D)).
q(324, I, ord_intersection([a, b, c], [b, c, d], I)).
q(325, yes, ord_memberchk(b, [a, b, c])).
q(326, yes, ord_subset([a, c], [a, b, c])).
q(327, S, sum_list([], S)).
q(328, M, max_list([], M)).
q(329, X, (append(X, [c], [a, b, c]))).
q(330, L, sumlist([1, 2], L)).
q(331, S, foldl(add, [], 5, S)).
q(332, L, append(a, L)).
q(333, X, must_be(integer, 3)).
q(334, X, must_be(integer, a)).
q(335, X, must_be(integer, _)).
q(336, X, must_be(positive_integer, 0)).
q(337, X, must_be(nonneg, -1)).
q(338, X, must_be(list, [a|_])).
q(339, X, must_be(oneof([a, b]), c)).
q(340, X, must_be(boolean, true)).
q(341, X, (X = [1, 2], msort(X, Y), Y == X)).
q(342, X, (between(1, 3, X), X =\= 2)).
q(343, X, (length(L, X), X > 1, !)).
q(344, X, last([], X)).
q(345, X, max_member(X, [])).
% How terms are read, as SWI-Prolog reads them.
q(400, C, tree(2*(3+4), C)).
q(401, C, tree(a-(b), C)).
q(402, C, tree(f(+, -, *), C)).
q(403, C, tree([mod, rem, is, (-)], C)).
q(404, C, tree(a^b^c, C)).
q(405, C, tree(2**3, C)).
q(406, C, tree(- 1 + 2, C)).
q(407, C, tree(-(1), C)).
q(408, C, tree(- (1), C)).
q(409, C, tree(a- -1, C)).
q(410, C, tree(1 - 2 - 3, C)).
q(411, C, tree(f(a;b, c), C)).
q(412, C, tree([a:-b, (c,d)], C)).
q(413, C, tree(f(a->b;c), C)).
q(414, C, tree(\+ a, C)).
q(415, C, tree(\ 5 /\ 3 \/ 1 xor 2, C)).
q(416, C, tree(7 rem 2 div 3 mod 4 << 1 >> 2, C)).
q(417, C, tree((X @< Y, Y @> Z), C)).
q(418, C, tree(a =.. b, C)).
q(419, C, tree(a =@= b, C)).
q(420, C, tree(+ a, C)).
q(421, C, tree(- a ^ b, C)).
q(422, C, tree(2 - (-3), C)).
q(423, C, tree(f(a:-b), C)).
q(424, C, tree(1.5e3 * 0x1F - 0'a, C)).
q(425, X-Y, (X = 1_000_000, Y is 2_500 * -1_0)).
q(426, L, lists:append([a], [b], L)).
q(427, X, call(user:member(X, [z, y]))).
q(428, C, tree(a:b:c, C)).
q(429, L, findall(X, lists:member(X, [p, q]), L)).
q(430, L, qualified(L)).
q(431, L, maplist(lists:reverse, [[a, b], [c]], L)).
q(432, X, call(lists:member, X, [u, v])).
% dif/2: checked at once, then again whenever bindings could make its terms identical.
q(433, X-Y, (dif(X, Y), X = a, member(Y, [a, b, c]))).
q(434, X, (dif(X, a), member(X, [a, b, a, c]))).
q(435, t, dif(a, a)).
q(436, t, dif(a, b)).
q(437, Y, (dif(f(X, b), f(a, Y)), X = a, member(Y, [a, b, c]))).
q(438, X-Y, (dif(X, Y), X = Y)).
q(439, X-Y, (dif(X, Y), (X = 1 ; true), (Y = 1 ; Y = 2))).
q(440, X, (dif(X, a), \+ X = a, X = b)).
q(441, X, \+ dif(X, a)).
q(442, L, findall(X, (member(X, [p, q, r]), dif(X, q)), L)).
q(443, X, (dif(X, a), (X = a -> true ; X = c))).
q(444, X-Y, (dif(g(X), g(Y)), X = Y)).
q(445, X, ((dif(X, Y), X = Y) ; X = z)).
q(446, X-Y, (dif([X|Y], [a, b]), X = a, Y = [b])).
q(447, X-Y, (dif([X|Y], [a, b]), X = a, Y = [c])).
q(448, X, dif(X, a)).
q(449, X-Y, (dif(X, Y), X \= Y)).
q(450, X-Y, (dif(f(X), f(Y)), dif(X, b), member(X-Y, [a-a, a-b, b-c, c-d]))).
