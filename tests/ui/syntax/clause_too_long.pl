% ui: KBC_MAX_CLAUSE_TOKENS=20 kbc check $CASE
% A clause longer than the limit (lowered here) is skipped with E0115; the next is read.
cells([c(1, 1), c(1, 2), c(1, 3), c(2, 1), c(2, 2), c(2, 3)]).
cell(1, 1).
