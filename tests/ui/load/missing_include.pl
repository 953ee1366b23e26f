:- include('actions.pl').
block(b1).
