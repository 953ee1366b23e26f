% A KB split over several files. `include` splices a file's clauses in at the directive, with
% paths relative to this file; `ensure_loaded` does the same but loads a file only once.

:- include('parts/table.pl').
:- ensure_loaded('parts/actions').

% The arms are the agent/1 facts; the planner treats them as renewable resources.
resources(agent(_)).
agent(r1).
agent(r2).
