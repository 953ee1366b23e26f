action(wait(A), [available(A)], [], [], [], [add(rested(A))]).
action(wait(Arm), [available(Arm)], [], [], [], [add(rested(Arm))]).
