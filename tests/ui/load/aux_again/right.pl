:- include('shared.pl').
right.
