% ui: kbc plan $CASE
% A domain with actions but no problem to plan.
action(switch_on(L), [light(L, off)], [], [], [], [del(light(L, off)), add(light(L, on))]).
