% args: --level arm
% The quay crane of the corpus (tests/corpus/crane_two_level.pl): each unload's start and end
% refine into four arm-level steps; the last step of the end's mapping leaves the hoist's
% direction open and the `ll_hoist` clause whose Valid list holds chooses it.
:- include('../../corpus/crane_two_level.pl').
