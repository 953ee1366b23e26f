:- include('../include_cycle.pl').
