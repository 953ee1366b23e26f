% ui: kbc plan $CASE
% `use_module/1` of a file of the KB's own loads it, as SWI-Prolog does; its `module/2`
% directive is a note (kbc reads every file's clauses as one KB).
:- use_module(aux_module/pushing).
p1 :- go([free(r1), at(box, 1)], [at(box, 3)]).
