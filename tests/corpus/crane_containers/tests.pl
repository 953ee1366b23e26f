test1(Actions, Times) :- go([crane_free(c1), top(k1, s1), top(k2, s2)], [top(k1, s3)], Actions, Times).
test2(Actions, Times) :- go([crane_free(c1), crane_free(c2), top(k1, s1), top(k2, s2)],
                            [top(k1, s2), top(k2, s1)], Actions, Times).
testCase(A, T) :- test1(A, T).
testTrace :- leash(-all), trace, testCase(_, _).
