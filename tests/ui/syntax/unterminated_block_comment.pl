block(b1).
/* the blocks of the second table
block(b2).
