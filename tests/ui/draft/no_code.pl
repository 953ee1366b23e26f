% ui: kbc draft check $CASE
I am sorry, but I cannot write that test case.
