% ui: kbc plan $CASE
% The goal wants arm a2 idle, but a2 is no arm of the initial state: units of a resource are
% never created, so the search stops at once instead of exploring every state.
two_arms :- go([available(a1), ontable(b1, 1, 1), clear(b1)],
               [available(a1), available(a2), ontable(b1, 2, 2)]).
