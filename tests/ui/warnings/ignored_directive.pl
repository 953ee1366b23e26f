:- initialization(main).
:- use_module(library(lists)).
block(b1).
