% expect: plan shift length 2
% expect: arm shift length 2
% Two agents at the high level, but the arm level knows only `a1`: a high-level plan that
% gives the job to `a2` does not refine, and the planner looks for another high-level plan
% that does (kbc notes which).
agent(a2). agent(a1).
action(shift_start(A, B), [free(A), at(B, left)], [], [], [agent(A)],
    [del(free(A)), del(at(B, left)), add(shifting(A, B))]).
action(shift_end(A, B), [shifting(A, B)], [], [], [], [del(shifting(A, B)), add(at(B, right)), add(free(A))]).
duration(shift(_, _), 2, 2).
ll_action(ll_push(A, B), [ll_ready(A)], [], [], [], [add(ll_pushed(B))]).
mapping(shift_start(A, B), [ll_push(A, B)]).
mapping(shift_end(A, _), [ll_push(A, done)]).
shift :- go([free(a2), free(a1), at(box, left)], [at(box, right)]).
ll_init([ll_ready(a1)]).
