:- include(library(lists)).
