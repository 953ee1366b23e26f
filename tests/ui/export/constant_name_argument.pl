% ui: kbc export pddl $CASE -o target/ui-export-never-written
% The start and the end of a PDDL durative action share one parameter list: a name argument
% that is a constant cannot be one.
action(turn_start(a1, D), [facing(a1, _)], [], [], [dir(D)], [add(turning(a1, D))]).
action(turn_end(a1, D), [turning(a1, D)], [], [], [], [del(turning(a1, D)), add(facing(a1, D))]).
dir(north).
dir(south).
demo :- go([facing(a1, north)], [facing(a1, south)]).
