% The goals before `go` call `atom_concat/3` (through a rule), which kbc does not provide: the
% unknown predicate is the error (E0210), not "the goals before `go` fail" (in Prolog they
% succeed). A test whose goals fail for want of a fact is still E0215.
name_of(N, B) :- atom_concat(b, N, B).
test1 :- name_of(1, B), go([ontable(B, 1, 1), clear(B), available(a1)], [ontable(B, 2, 2)]).
test2 :- member(X, []), go([ontable(X, 1, 1), clear(X), available(a1)], [ontable(X, 2, 2)]).
