% An arm-level start without its end is error E0204; a high-level one is W0019.
mapping(go_start, [grasp_start(a1, b1)]).
action(go_start, [], [], [], [], []).
action(go_end, [], [], [], [], []).
ll_action(grasp_start(A, B), [ll_free(A)], [], [], [], [del(ll_free(A)), add(ll_grasping(A, B))]).
