block(b1)).
