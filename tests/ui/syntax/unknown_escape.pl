label(b1, 'red\qblock').
