% ui: kbc plan $CASE
% An OnKB goal that needs a cyclic term: kbc unifies with the occurs check, so `X = f(X)`
% fails (SWI-Prolog would build a rational tree), the action never applies, and the goal it
% alone adds is unreachable. No stack overflow, no hang.
cyclic :- X = f(X), Y = f(Y), X == Y.
action(go, [], [], [], [cyclic], [add(done)]).
t :- go([], [done]).
