shared(1).
