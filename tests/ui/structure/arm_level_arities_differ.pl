% Arm-level pairs must agree (E0205); high-level ones that do not are W0011.
% (B is bound by a mapping, as arm-level names are.)
mapping(go_start, [grasp_start(a1, b1)]).
action(go_start, [], [], [], [], []).
action(go_end, [], [], [], [], []).
ll_action(grasp_start(A, B), [ll_free(A)], [], [], [], [del(ll_free(A)), add(ll_grasping(A, B))]).
ll_action(grasp_end(A), [ll_grasping(A, _)], [], [], [], [add(ll_free(A))]).
