:- discontiguous block/1.
block(b1).
cell(1, 1).
block(b2).
