% Pick and place, in the style of a language model's KB: 100 boxes on a grid of 121 pos/2 cells, 10
% agent/1 agents, free/1 and no resources/1; an agent picks a box from its cell and places it on
% an empty one, two durative actions. (kbc plan pick_place_domain.pl pick_place_b100_a10_c121.pl --schedule)
agent(r1).
agent(r2).
agent(r3).
agent(r4).
agent(r5).
agent(r6).
agent(r7).
agent(r8).
agent(r9).
agent(r10).
pos(1,1).
pos(1,2).
pos(1,3).
pos(1,4).
pos(1,5).
pos(1,6).
pos(1,7).
pos(1,8).
pos(1,9).
pos(1,10).
pos(1,11).
pos(2,1).
pos(2,2).
pos(2,3).
pos(2,4).
pos(2,5).
pos(2,6).
pos(2,7).
pos(2,8).
pos(2,9).
pos(2,10).
pos(2,11).
pos(3,1).
pos(3,2).
pos(3,3).
pos(3,4).
pos(3,5).
pos(3,6).
pos(3,7).
pos(3,8).
pos(3,9).
pos(3,10).
pos(3,11).
pos(4,1).
pos(4,2).
pos(4,3).
pos(4,4).
pos(4,5).
pos(4,6).
pos(4,7).
pos(4,8).
pos(4,9).
pos(4,10).
pos(4,11).
pos(5,1).
pos(5,2).
pos(5,3).
pos(5,4).
pos(5,5).
pos(5,6).
pos(5,7).
pos(5,8).
pos(5,9).
pos(5,10).
pos(5,11).
pos(6,1).
pos(6,2).
pos(6,3).
pos(6,4).
pos(6,5).
pos(6,6).
pos(6,7).
pos(6,8).
pos(6,9).
pos(6,10).
pos(6,11).
pos(7,1).
pos(7,2).
pos(7,3).
pos(7,4).
pos(7,5).
pos(7,6).
pos(7,7).
pos(7,8).
pos(7,9).
pos(7,10).
pos(7,11).
pos(8,1).
pos(8,2).
pos(8,3).
pos(8,4).
pos(8,5).
pos(8,6).
pos(8,7).
pos(8,8).
pos(8,9).
pos(8,10).
pos(8,11).
pos(9,1).
pos(9,2).
pos(9,3).
pos(9,4).
pos(9,5).
pos(9,6).
pos(9,7).
pos(9,8).
pos(9,9).
pos(9,10).
pos(9,11).
pos(10,1).
pos(10,2).
pos(10,3).
pos(10,4).
pos(10,5).
pos(10,6).
pos(10,7).
pos(10,8).
pos(10,9).
pos(10,10).
pos(10,11).
pos(11,1).
pos(11,2).
pos(11,3).
pos(11,4).
pos(11,5).
pos(11,6).
pos(11,7).
pos(11,8).
pos(11,9).
pos(11,10).
pos(11,11).
test1 :- go([
  free(r1),
  free(r2),
  free(r3),
  free(r4),
  free(r5),
  free(r6),
  free(r7),
  free(r8),
  free(r9),
  free(r10),
  at(box1, 3, 9),
  at(box2, 4, 6),
  at(box3, 2, 3),
  at(box4, 9, 5),
  at(box5, 5, 7),
  at(box6, 6, 7),
  at(box7, 2, 9),
  at(box8, 2, 1),
  at(box9, 1, 9),
  at(box10, 1, 3),
  at(box11, 5, 8),
  at(box12, 7, 5),
  at(box13, 4, 5),
  at(box14, 10, 4),
  at(box15, 9, 10),
  at(box16, 1, 8),
  at(box17, 3, 7),
  at(box18, 7, 1),
  at(box19, 7, 3),
  at(box20, 5, 3),
  at(box21, 4, 3),
  at(box22, 10, 1),
  at(box23, 3, 1),
  at(box24, 11, 9),
  at(box25, 4, 1),
  at(box26, 3, 6),
  at(box27, 1, 4),
  at(box28, 8, 6),
  at(box29, 9, 9),
  at(box30, 4, 2),
  at(box31, 3, 3),
  at(box32, 2, 11),
  at(box33, 4, 7),
  at(box34, 10, 10),
  at(box35, 8, 4),
  at(box36, 5, 4),
  at(box37, 11, 4),
  at(box38, 8, 1),
  at(box39, 4, 11),
  at(box40, 5, 6),
  at(box41, 6, 10),
  at(box42, 3, 10),
  at(box43, 9, 11),
  at(box44, 8, 3),
  at(box45, 6, 6),
  at(box46, 10, 2),
  at(box47, 8, 8),
  at(box48, 10, 11),
  at(box49, 11, 10),
  at(box50, 1, 1),
  at(box51, 8, 11),
  at(box52, 9, 1),
  at(box53, 6, 11),
  at(box54, 9, 3),
  at(box55, 5, 9),
  at(box56, 5, 11),
  at(box57, 4, 4),
  at(box58, 6, 1),
  at(box59, 10, 6),
  at(box60, 1, 11),
  at(box61, 2, 4),
  at(box62, 11, 5),
  at(box63, 2, 6),
  at(box64, 10, 5),
  at(box65, 11, 1),
  at(box66, 11, 2),
  at(box67, 1, 6),
  at(box68, 6, 9),
  at(box69, 3, 8),
  at(box70, 4, 8),
  at(box71, 2, 7),
  at(box72, 11, 8),
  at(box73, 9, 4),
  at(box74, 4, 9),
  at(box75, 11, 11),
  at(box76, 5, 1),
  at(box77, 9, 2),
  at(box78, 1, 10),
  at(box79, 2, 2),
  at(box80, 1, 5),
  at(box81, 3, 5),
  at(box82, 4, 10),
  at(box83, 6, 8),
  at(box84, 11, 7),
  at(box85, 7, 9),
  at(box86, 8, 2),
  at(box87, 9, 8),
  at(box88, 2, 10),
  at(box89, 7, 4),
  at(box90, 8, 5),
  at(box91, 9, 7),
  at(box92, 6, 2),
  at(box93, 1, 2),
  at(box94, 7, 10),
  at(box95, 10, 7),
  at(box96, 11, 3),
  at(box97, 7, 2),
  at(box98, 2, 8),
  at(box99, 6, 5),
  at(box100, 6, 3),
  empty(1, 7),
  empty(2, 5),
  empty(3, 2),
  empty(3, 4),
  empty(3, 11),
  empty(5, 2),
  empty(5, 5),
  empty(5, 10),
  empty(6, 4),
  empty(7, 6),
  empty(7, 7),
  empty(7, 8),
  empty(7, 11),
  empty(8, 7),
  empty(8, 9),
  empty(8, 10),
  empty(9, 6),
  empty(10, 3),
  empty(10, 8),
  empty(10, 9),
  empty(11, 6)
], [
  at(box1, 2, 5),
  at(box2, 4, 10),
  at(box3, 3, 1),
  at(box4, 4, 5),
  at(box5, 6, 4),
  at(box6, 1, 4),
  at(box7, 1, 6),
  at(box8, 5, 2),
  at(box9, 9, 2),
  at(box10, 1, 11),
  at(box11, 4, 4),
  at(box12, 9, 7),
  at(box13, 8, 10),
  at(box14, 4, 9),
  at(box15, 1, 3),
  at(box16, 10, 9),
  at(box17, 11, 1),
  at(box18, 10, 7),
  at(box19, 2, 9),
  at(box20, 10, 1),
  at(box21, 8, 7),
  at(box22, 5, 9),
  at(box23, 8, 3),
  at(box24, 8, 11),
  at(box25, 1, 10),
  at(box26, 11, 8),
  at(box27, 9, 11),
  at(box28, 3, 3),
  at(box29, 6, 2),
  at(box30, 9, 8),
  at(box31, 2, 7),
  at(box32, 3, 11),
  at(box33, 5, 5),
  at(box34, 7, 11),
  at(box35, 2, 10),
  at(box36, 11, 10),
  at(box37, 7, 8),
  at(box38, 1, 2),
  at(box39, 5, 3),
  at(box40, 11, 5),
  at(box41, 11, 7),
  at(box42, 2, 11),
  at(box43, 8, 6),
  at(box44, 8, 2),
  at(box45, 9, 4),
  at(box46, 8, 8),
  at(box47, 2, 2),
  at(box48, 9, 5),
  at(box49, 3, 5),
  at(box50, 5, 11),
  at(box51, 7, 7),
  at(box52, 2, 4),
  at(box53, 1, 8),
  at(box54, 7, 3),
  at(box55, 7, 2),
  at(box56, 10, 11),
  at(box57, 10, 4),
  at(box58, 8, 5),
  at(box59, 4, 2),
  at(box60, 3, 10),
  at(box61, 9, 10),
  at(box62, 11, 11),
  at(box63, 10, 10),
  at(box64, 10, 8),
  at(box65, 7, 1),
  at(box66, 5, 10),
  at(box67, 4, 1),
  at(box68, 2, 8),
  at(box69, 5, 6),
  at(box70, 7, 5),
  at(box71, 10, 5),
  at(box72, 7, 9),
  at(box73, 3, 9),
  at(box74, 10, 3),
  at(box75, 6, 5),
  at(box76, 3, 7),
  at(box77, 5, 8),
  at(box78, 6, 7),
  at(box79, 6, 3),
  at(box80, 7, 4),
  at(box81, 5, 1),
  at(box82, 11, 4),
  at(box83, 8, 1),
  at(box84, 3, 6),
  at(box85, 2, 3),
  at(box86, 4, 11),
  at(box87, 5, 4),
  at(box88, 8, 9),
  at(box89, 7, 6),
  at(box90, 2, 6),
  at(box91, 1, 9),
  at(box92, 7, 10),
  at(box93, 4, 3),
  at(box94, 1, 7),
  at(box95, 9, 6),
  at(box96, 3, 8),
  at(box97, 10, 6),
  at(box98, 9, 1),
  at(box99, 1, 5),
  at(box100, 11, 2)
]).
