action(push(A), [available(A)], [], [], [], [add(pushed(A))]) :- arm(A).
arm(a1).
