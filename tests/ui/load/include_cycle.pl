:- include('aux/cycle_b.pl').
