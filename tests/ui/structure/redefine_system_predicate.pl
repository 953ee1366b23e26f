% SWI-Prolog refuses these clauses too: length/2 and atom/1 are system predicates. A library
% predicate such as append/3 may be defined (the KB's own replaces the library's).
length([], 0).
atom(b1).
append([], L, L).
