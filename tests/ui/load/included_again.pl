% Two parts of a KB include the same file: it is loaded once, with a warning at the second
% include; a third include of the same file through ensure_loaded is silent.
:- include('aux_again/left.pl').
:- include('aux_again/right.pl').
:- ensure_loaded('aux_again/shared.pl').
t :- go([shared(1), left, right], [shared(1)]).
