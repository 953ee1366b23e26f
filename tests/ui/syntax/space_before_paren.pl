block (b1).
