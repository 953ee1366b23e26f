stack(s1, [b1, b2)).
