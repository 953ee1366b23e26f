% Pick and place, in the style of a language model's KB: 50 boxes on a grid of 64 pos/2 cells, 5
% agent/1 agents, free/1 and no resources/1; an agent picks a box from its cell and places it on
% an empty one, two durative actions. (kbc plan pick_place_domain.pl pick_place_b50_a5_c64.pl --schedule)
agent(r1).
agent(r2).
agent(r3).
agent(r4).
agent(r5).
pos(1,1).
pos(1,2).
pos(1,3).
pos(1,4).
pos(1,5).
pos(1,6).
pos(1,7).
pos(1,8).
pos(2,1).
pos(2,2).
pos(2,3).
pos(2,4).
pos(2,5).
pos(2,6).
pos(2,7).
pos(2,8).
pos(3,1).
pos(3,2).
pos(3,3).
pos(3,4).
pos(3,5).
pos(3,6).
pos(3,7).
pos(3,8).
pos(4,1).
pos(4,2).
pos(4,3).
pos(4,4).
pos(4,5).
pos(4,6).
pos(4,7).
pos(4,8).
pos(5,1).
pos(5,2).
pos(5,3).
pos(5,4).
pos(5,5).
pos(5,6).
pos(5,7).
pos(5,8).
pos(6,1).
pos(6,2).
pos(6,3).
pos(6,4).
pos(6,5).
pos(6,6).
pos(6,7).
pos(6,8).
pos(7,1).
pos(7,2).
pos(7,3).
pos(7,4).
pos(7,5).
pos(7,6).
pos(7,7).
pos(7,8).
pos(8,1).
pos(8,2).
pos(8,3).
pos(8,4).
pos(8,5).
pos(8,6).
pos(8,7).
pos(8,8).
test1 :- go([
  free(r1),
  free(r2),
  free(r3),
  free(r4),
  free(r5),
  at(box1, 4, 7),
  at(box2, 5, 6),
  at(box3, 5, 3),
  at(box4, 2, 1),
  at(box5, 3, 8),
  at(box6, 8, 3),
  at(box7, 5, 7),
  at(box8, 8, 8),
  at(box9, 6, 1),
  at(box10, 8, 7),
  at(box11, 1, 5),
  at(box12, 8, 2),
  at(box13, 1, 1),
  at(box14, 8, 1),
  at(box15, 3, 1),
  at(box16, 5, 4),
  at(box17, 2, 7),
  at(box18, 2, 5),
  at(box19, 6, 6),
  at(box20, 7, 3),
  at(box21, 8, 6),
  at(box22, 7, 1),
  at(box23, 6, 5),
  at(box24, 4, 2),
  at(box25, 2, 2),
  at(box26, 6, 8),
  at(box27, 5, 8),
  at(box28, 5, 2),
  at(box29, 4, 1),
  at(box30, 7, 4),
  at(box31, 7, 6),
  at(box32, 2, 3),
  at(box33, 1, 3),
  at(box34, 7, 7),
  at(box35, 6, 3),
  at(box36, 6, 4),
  at(box37, 4, 3),
  at(box38, 8, 5),
  at(box39, 2, 8),
  at(box40, 3, 4),
  at(box41, 8, 4),
  at(box42, 6, 7),
  at(box43, 2, 6),
  at(box44, 3, 7),
  at(box45, 3, 3),
  at(box46, 7, 5),
  at(box47, 5, 5),
  at(box48, 2, 4),
  at(box49, 1, 4),
  at(box50, 4, 5),
  empty(1, 2),
  empty(1, 6),
  empty(1, 7),
  empty(1, 8),
  empty(3, 2),
  empty(3, 5),
  empty(3, 6),
  empty(4, 4),
  empty(4, 6),
  empty(4, 8),
  empty(5, 1),
  empty(6, 2),
  empty(7, 2),
  empty(7, 8)
], [
  at(box1, 3, 2),
  at(box2, 4, 8),
  at(box3, 2, 6),
  at(box4, 3, 1),
  at(box5, 6, 4),
  at(box6, 4, 4),
  at(box7, 7, 2),
  at(box8, 6, 1),
  at(box9, 7, 7),
  at(box10, 3, 4),
  at(box11, 4, 3),
  at(box12, 5, 1),
  at(box13, 4, 1),
  at(box14, 5, 5),
  at(box15, 3, 7),
  at(box16, 5, 3),
  at(box17, 5, 6),
  at(box18, 7, 6),
  at(box19, 6, 8),
  at(box20, 2, 7),
  at(box21, 3, 6),
  at(box22, 1, 2),
  at(box23, 8, 8),
  at(box24, 5, 7),
  at(box25, 2, 3),
  at(box26, 3, 5),
  at(box27, 7, 1),
  at(box28, 7, 3),
  at(box29, 1, 7),
  at(box30, 8, 6),
  at(box31, 6, 2),
  at(box32, 3, 3),
  at(box33, 1, 8),
  at(box34, 1, 3),
  at(box35, 2, 8),
  at(box36, 8, 3),
  at(box37, 8, 1),
  at(box38, 4, 6),
  at(box39, 4, 7),
  at(box40, 2, 4),
  at(box41, 4, 2),
  at(box42, 6, 6),
  at(box43, 1, 5),
  at(box44, 1, 1),
  at(box45, 2, 2),
  at(box46, 8, 2),
  at(box47, 7, 5),
  at(box48, 1, 4),
  at(box49, 6, 3),
  at(box50, 7, 8)
]).
