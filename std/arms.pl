% std/arms.pl: the arm-level actions the simulated arms provide (`kbc run --host sim`).
%
% Each arm is a base yaw joint and a two-link arm with a gripper that points down (see
% ARCHITECTURE.md, "Simulated arms"). A high-level action runs on the arms as the steps of its
% `mapping/2` (std/blocks.pl maps grip, move_block and release); a KB can map its own actions
% onto these steps the same way. The first argument of every step is the arm.
%
% The slots describe the gripper's state in `ll_` fluents; the simulator checks the physical
% truth behind them: a step fails when nothing is there to grip, the wrong block is on top, a
% point is out of the arm's reach, or two grippers come closer than the safety distance.
%
%   ll_above(A)        the gripper is at a safe height (above every stack)
%   ll_down(A)         the gripper has descended onto whatever stands under it
%   ll_holding(A, B)   the gripper holds block B

% reach(A, B): move the gripper above block B, wherever it stands, at a safe height.
ll_action(reach(A, _),
    [],
    [ll_holding(A, _)],
    [],
    [],
    [del(ll_down(A)), add(ll_above(A))]).
% move_over(A, X, Y): move the gripper (and what it holds) above cell (X, Y), at a safe height.
ll_action(move_over(A, _, _),
    [],
    [],
    [],
    [],
    [del(ll_down(A)), add(ll_above(A))]).
% descend(A): lower the gripper onto the top of what stands under it; holding a block, lower
% until the block rests on it.
ll_action(descend(A),
    [ll_above(A)],
    [],
    [],
    [],
    [del(ll_above(A)), add(ll_down(A))]).
% close(A, B): grip B, which must be the top block right under the gripper.
ll_action(close(A, B),
    [ll_down(A)],
    [ll_holding(A, _)],
    [],
    [],
    [add(ll_holding(A, B))]).
% lift(A): raise the gripper to a safe height.
ll_action(lift(A),
    [],
    [],
    [],
    [],
    [del(ll_down(A)), add(ll_above(A))]).
% open(A, B): let go of B.
ll_action(open(A, B),
    [ll_holding(A, B)],
    [],
    [],
    [],
    [del(ll_holding(A, B))]).
% home(A): move the gripper (and what it holds) to the arm's resting point beside the table,
% at a safe height: out of the way of the arms working on the table.
ll_action(home(A),
    [],
    [],
    [],
    [],
    [del(ll_down(A)), add(ll_above(A))]).
