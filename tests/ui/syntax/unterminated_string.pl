label(b1, "red block).
