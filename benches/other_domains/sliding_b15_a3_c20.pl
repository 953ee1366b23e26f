% A sliding puzzle: 15 blocks on a 5 x 4 grid of pos/2 cells, three agents, each push moves a
% block to a neighbouring free cell.
agent(a1).
agent(a2).
agent(a3).
block(b1).
block(b2).
block(b3).
block(b4).
block(b5).
block(b6).
block(b7).
block(b8).
block(b9).
block(b10).
block(b11).
block(b12).
block(b13).
block(b14).
block(b15).
pos(1, 1).
pos(1, 2).
pos(1, 3).
pos(1, 4).
pos(2, 1).
pos(2, 2).
pos(2, 3).
pos(2, 4).
pos(3, 1).
pos(3, 2).
pos(3, 3).
pos(3, 4).
pos(4, 1).
pos(4, 2).
pos(4, 3).
pos(4, 4).
pos(5, 1).
pos(5, 2).
pos(5, 3).
pos(5, 4).
adjacent(X, Y1, X, Y2) :- pos(X, Y1), pos(X, Y2), 1 =:= abs(Y1 - Y2).
adjacent(X1, Y, X2, Y) :- pos(X1, Y), pos(X2, Y), 1 =:= abs(X1 - X2).
resources(agent(_)).
action(push_start(A, B, X1, Y1, X2, Y2), [free(A), at(B, X1, Y1)], [at(_, X2, Y2), pushing(_, _, X2, Y2)], [], [agent(A), adjacent(X1, Y1, X2, Y2)], [del(free(A)), del(at(B, X1, Y1)), add(pushing(A, B, X2, Y2))]).
action(push_end(A, B, _X1, _Y1, X2, Y2), [pushing(A, B, X2, Y2)], [], [], [], [del(pushing(A, B, X2, Y2)), add(at(B, X2, Y2)), add(free(A))]).
duration(push(_, _, _, _, _, _), 1, 3).
sliding :- go([free(a1), free(a2), free(a3), at(b1, 3, 1), at(b2, 1, 4), at(b3, 2, 3), at(b4, 2, 2), at(b5, 4, 4), at(b6, 5, 1), at(b7, 1, 3), at(b8, 4, 1), at(b9, 1, 1), at(b10, 1, 2), at(b11, 4, 2), at(b12, 3, 3), at(b13, 5, 4), at(b14, 3, 2), at(b15, 4, 3)], [at(b1, 1, 4), at(b2, 5, 1), at(b3, 3, 3), at(b4, 3, 1), at(b5, 5, 4), at(b6, 4, 4), at(b7, 4, 2), at(b8, 1, 2), at(b9, 2, 2), at(b10, 2, 3), at(b11, 1, 3), at(b12, 4, 1), at(b13, 4, 3), at(b14, 3, 2), at(b15, 1, 1)]).
