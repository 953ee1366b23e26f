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
