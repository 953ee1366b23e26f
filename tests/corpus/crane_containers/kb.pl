stack(s1). stack(s2). stack(s3).
duration(lift(_, _, _, _), 3, 5).
