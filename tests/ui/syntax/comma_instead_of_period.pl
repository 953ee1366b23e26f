block(b1),
block(b2).
