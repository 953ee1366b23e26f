action(switch(L), [light(L, off)], [], [], [], [del(light(L, off)), add(light(L, on))]).
test1 :- go([light(l1, off)], [light(l1, dimmed)]).
