% args: --plan ../../../examples/06_partial_order/plan.txt
% The paper's partial-order example (examples/06_partial_order), scheduled from the total
% order of its table of achievers; the `pop` pass after it.
:- include('../../../examples/06_partial_order/kb.pl').
