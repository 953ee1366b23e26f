action(Name, [available(a1)], [], [], [], [add(done(Name))]).
