% expect: plan unload length 4
% expect: arm unload length 16
% expect: warn W0009
% A quay crane in the two-level style. The end of `unload` names the container only in its
% head (it takes the start's value). At the arm level the trolley's position is unknown at
% first (`ll_trolley(c1, _)`), and the last step of the end's mapping leaves the hoist's
% direction open: the `ll_hoist` clause whose Valid list holds chooses it.
crane(c1).
container(k1). container(k2).
action(unload_start(C, K), [idle(C), on_ship(K)], [], [], [crane(C), container(K)],
    [del(idle(C)), del(on_ship(K)), add(lifting(C))]).
action(unload_end(C, K), [lifting(C)], [], [], [],
    [del(lifting(C)), add(on_quay(K)), add(idle(C))]).
duration(unload(_, _), 3, 6).

ll_action(ll_trolley_to(C, P), [ll_trolley(C, _)], [], [], [], [del(ll_trolley(C, _)), add(ll_trolley(C, P))]).
ll_action(ll_hoist(C, down), [ll_hook(C, up)], [], [], [], [del(ll_hook(C, up)), add(ll_hook(C, down))]).
ll_action(ll_hoist(C, up), [ll_hook(C, down)], [], [], [], [del(ll_hook(C, down)), add(ll_hook(C, up))]).
ll_action(ll_latch(C, K), [ll_hook(C, down), ll_trolley(C, ship)], [ll_carrying(C, _)], [], [],
    [add(ll_carrying(C, K))]).
ll_action(ll_unlatch(C, K), [ll_carrying(C, K), ll_trolley(C, quay), ll_hook(C, down)], [], [], [],
    [del(ll_carrying(C, K))]).

mapping(unload_start(C, K), [ll_trolley_to(C, ship), ll_hoist(C, down), ll_latch(C, K), ll_hoist(C, up)]).
mapping(unload_end(C, K), [ll_trolley_to(C, quay), ll_hoist(C, down), ll_unlatch(C, K), ll_hoist(C, _Dir)]).

unload :- go([idle(c1), on_ship(k1), on_ship(k2)], [on_quay(k1), on_quay(k2)]).
ll_init([ll_trolley(c1, _), ll_hook(c1, up)]).
ll_goal([ll_hook(c1, up)]).
