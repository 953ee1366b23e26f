% The KB the drafting cases extend: its test cases, the paper's test1, test2 and test3 with
% their comments, are the examples of the prompt (the paper's Figure "Example of message used
% to query the LLM"), and the cases are planned in the standard blocks world (std/blocks.pl).
:- include('../01_paper_tests/tests.pl').
