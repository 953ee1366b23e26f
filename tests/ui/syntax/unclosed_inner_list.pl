stack(s1, [b1, b2, [b3, b4]).
