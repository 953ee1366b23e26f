"""Validates PDDL 2.1 timed plans with unified-planning's own validator.

Usage: python3 up_validate.py DOMAIN PROBLEM PLAN [DOMAIN PROBLEM PLAN ...]
Prints one verdict per triple, "VALID", "INVALID <reason>" or "UNREADABLE <why>", and exits
0 when every plan is valid, 1 when some plan is not, and 2 when some files cannot be read.
(One process for many plans: importing unified-planning takes a second.)
"""
import sys

from unified_planning.engines.plan_validator import TimeTriggeredPlanValidator
from unified_planning.io import PDDLReader
from unified_planning.shortcuts import get_environment

get_environment().credits_stream = None

status = 0
args = sys.argv[1:]
for domain, problem_file, plan_file in zip(args[0::3], args[1::3], args[2::3]):
    reader = PDDLReader()
    try:
        problem = reader.parse_problem(domain, problem_file)
        plan = reader.parse_plan(problem, plan_file)
    except Exception as error:  # any failure to read is the answer
        print(f"UNREADABLE {type(error).__name__}: {error}".replace("\n", " "))
        status = 2
        continue
    validator = TimeTriggeredPlanValidator()
    if not validator.supports(problem.kind):
        print(f"UNREADABLE unsupported problem kind: {problem.kind}".replace("\n", " "))
        status = 2
        continue
    result = validator.validate(problem, plan)
    if result.status.name == "VALID":
        print("VALID")
    else:
        action = getattr(result, "inapplicable_action", None)
        print(f"INVALID {result.reason.name if result.reason else ''} {action or ''}".strip())
        status = max(status, 1)
sys.exit(status)
