:- include('shared.pl').
left.
