"""kbc against PDDL 2.1 temporal planners on the planner ladder, in one run.

    python3 benches/ladder_vs_pddl_planners.py [--timeout S] [--seeds N] [--share F] [--only build_b10 ...]

For each rung of `kbc bench --write` it exports the problem with `kbc export pddl
--no-negative-preconditions --durations min` (LPG has no negative conditions and no duration
inequalities; a makespan-minimising planner picks the minimum anyway) and runs:

- LPG-td (the binary `up-lpg` ships, called directly, first plan) once per seed 1..N: its
  local search is randomised, so its makespans vary from seed to seed; the table gives the
  fastest of its times and the best and median of its makespans;
- kbc's default (`kbc plan --schedule`: the first plan, rearranged by the `reassign` pass),
  run as many times as LPG (N): the fastest time, as for LPG, and the longest makespan;
- kbc with `--improve`, given F (default 0.17) of LPG's fastest time as its whole budget (the
  improvement phase, which counts from the search's start, gets that minus one and a half
  times what the default run spent outside its search: start-up, front end, scheduling): the
  question the issue asks is whether kbc, five times faster, is as good. The ratio column is
  measured, not assumed: with F = 0.2 the improvement deadline (checked between expansions)
  and start-up left kbc 4.6-4.9x faster on 12 of 24 rungs, with 0.17 every rung was >= 5.2x.
  Also run N times: the fastest time and the longest makespan (its restarts depend on time);
- Kairos (first plan, one thread).

Their plans are mapped back to the KB through names.json and every plan is validated with
`kbc validate`. Wall-clock times include each tool's start-up and parsing. Needs:
`pip install 'setuptools<81' up-lpg kairos-planner`.
"""

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
KBC = os.path.join(ROOT, "target", "release", "kbc")


def lpg_binary():
    try:
        import up_lpg
    except ImportError:
        return None
    path = os.path.join(os.path.dirname(up_lpg.__file__), "lpg")
    return path if os.path.exists(path) else None


def run(cmd, timeout, cwd=None):
    started = time.perf_counter()
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, cwd=cwd)
        return out, time.perf_counter() - started
    except subprocess.TimeoutExpired:
        return None, time.perf_counter() - started


PLAN_LINE = re.compile(r"^\s*([0-9.]+):\s*\(([^)]*)\)\s*\[([0-9.]+)\]")


def map_back(plan_text, names):
    """A PDDL timed plan in the KB's terms; returns (text, makespan).

    LPG separates happenings by 0.0002-0.0003, below kbc's resolution of a thousandth, so the
    plan is replayed with each happening moved later by a thousandth per distinct earlier
    happening: the order of happenings is kept, durations grow by a few thousandths (the KB's
    bounds are still checked), and the makespan reported is the planner's own."""
    steps, makespan = [], 0.0
    for line in plan_text.splitlines():
        m = PLAN_LINE.match(line)
        if not m:
            continue
        start, action, duration = float(m.group(1)), m.group(2).lower().split(), float(m.group(3))
        entry = names["actions"][action[0]]
        params = entry["parameters"]
        template = entry.get("start") or entry["instant"]
        functor, _, args = template.partition("(")
        functor = functor[: -len("_start")] if functor.endswith("_start") else functor
        words = [functor]
        for arg in [a.strip() for a in args.rstrip(")").split(",") if a.strip()]:
            words.append(names["objects"][action[1 + params.index(arg)]])
        steps.append((start, start + duration, " ".join(words)))
        makespan = max(makespan, start + duration)
    happenings = sorted({round(t, 6) for s, e, _ in steps for t in (s, e)})
    rank = {t: i for i, t in enumerate(happenings)}
    moved = lambda t: t + 0.001 * rank[round(t, 6)]
    lines = [f"{moved(s):.3f}: ({w}) [{moved(e) - moved(s):.3f}]" for s, e, w in steps]
    return "\n".join(lines) + "\n", makespan


def validate(kb, text, directory, tag):
    path = os.path.join(directory, f"{tag}.plan")
    with open(path, "w") as f:
        f.write(text)
    out = subprocess.run([KBC, "validate", kb, path], capture_output=True, text=True)
    return out.returncode == 0


def kbc_plan(kb, timeout, improve=None):
    """Runs `kbc plan --schedule`; returns (seconds, makespan or None, the search's seconds)."""
    cmd = [KBC, "plan", kb, "--schedule", "--timeout", str(timeout)]
    if improve is not None:
        cmd += ["--improve", f"{improve:.3f}"]
    out, seconds = run(cmd, timeout + 5)
    makespan, searching = None, 0.0
    if out is not None and out.returncode == 0:
        m = re.search(r"makespan ([0-9.]+)", out.stdout)
        makespan = float(m.group(1)) if m else None
        m = re.search(r"; ([0-9.]+) s;", out.stdout)
        searching = float(m.group(1)) if m else 0.0
    return seconds, makespan, searching


def repeated(run_kbc, times):
    """`run_kbc` (a `kbc_plan` call) `times` times: the fastest time, the longest makespan (None
    if any run failed) and the search's seconds of the fastest run. LPG's time is its fastest
    over its seeds; timing kbc once against that measured the machine's noise as much as kbc
    (reverse_b06_a3_s1: 0.05 s in one run of this script, 0.02-0.04 s in eleven more by hand)."""
    runs = [run_kbc() for _ in range(max(1, times))]
    fastest = min(runs, key=lambda r: r[0])
    makespans = [mk for _, mk, _ in runs]
    longest = None if any(mk is None for mk in makespans) else max(makespans)
    return fastest[0], longest, fastest[2]


def cell(value, width, digits=2):
    return f"{value:{width}.{digits}f}" if value is not None else f"{'-':>{width}}"


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--timeout", type=float, default=60.0)
    parser.add_argument("--only", nargs="*", default=None, help="rung name prefixes")
    parser.add_argument("--seeds", type=int, default=5, help="LPG runs per rung, seeds 1..N")
    parser.add_argument("--share", type=float, default=0.17,
                        help="kbc --improve's budget as a share of LPG's fastest time")
    args = parser.parse_args()
    if not os.path.exists(KBC):
        sys.exit("build kbc first: cargo build --release")
    lpg = lpg_binary()
    work = tempfile.mkdtemp(prefix="kbc-vs-pddl-")
    subprocess.run([KBC, "bench", "--write", work], check=True, capture_output=True)
    rungs = sorted(f[:-3] for f in os.listdir(work) if f.endswith(".pl"))
    rungs.sort(key=lambda r: (r.split("_")[0], int(r.split("_")[1][1:])))
    if args.only:
        rungs = [r for r in rungs if any(r.startswith(p) for p in args.only)]
    print(f"timeout {args.timeout:.0f} s per planner and problem; LPG seeds 1..{args.seeds}; kbc+i gets "
          f"{args.share:g} of LPG's fastest time; makespans in KB time units; 'invalid' = kbc validate rejects the plan")
    print(f"{'problem':<18} {'kbc s':>6} {'kbc mk':>7} {'kbc+i s':>7} {'kbc+i mk':>8} {'LPG s':>6} {'LPG best':>8} "
          f"{'LPG med':>7} {'LPG/kbc+i':>9} {'Kairos s':>8} {'K mk':>7}")
    for rung in rungs:
        kb = os.path.join(work, rung + ".pl")
        # kbc as often as LPG runs (its time the fastest, as LPG's is; its makespan the
        # longest, though the default run gives the same plan every time).
        kbc_time, kbc_mk, kbc_search = repeated(lambda: kbc_plan(kb, args.timeout), args.seeds)
        export_dir = os.path.join(work, rung)
        # (The export grounds the KB's static conditions; on the 75- and 100-block rungs that
        # takes minutes and gigabytes, and neither planner would parse the result in time.)
        out, _ = run([KBC, "export", "pddl", kb, "-o", export_dir, "--no-negative-preconditions",
                      "--durations", "min", "--limit", "50000000"], args.timeout)
        if out is None or out.returncode != 0:
            print(" ".join([f"{rung:<18}", cell(kbc_time, 6), cell(kbc_mk, 7)])
                  + f"  (no PDDL export within {args.timeout:.0f} s: the planners are not run)", flush=True)
            continue
        with open(os.path.join(export_dir, "names.json")) as f:
            names = json.load(f)
        # LPG: first plan, once per seed; only valid plans count.
        lpg_runs = []
        for seed in range(1, args.seeds + 1) if lpg else []:
            plan_file = os.path.join(export_dir, f"lpg{seed}.out")
            out, t = run([lpg, "-o", "domain.pddl", "-f", "problem.pddl", "-n", "1", "-seed", str(seed),
                          "-out", plan_file], args.timeout, cwd=export_dir)
            text = open(plan_file).read() if os.path.exists(plan_file) else ""
            plan, mk = map_back(text, names)
            if out is not None and plan.strip():
                valid = validate(kb, plan, export_dir, f"lpg{seed}")
                lpg_runs.append((t, mk if valid else None))
        lpg_valid = sorted(mk for _, mk in lpg_runs if mk is not None)
        lpg_fastest = min((t for t, mk in lpg_runs if mk is not None), default=None)
        lpg_best = lpg_valid[0] if lpg_valid else None
        lpg_median = lpg_valid[len(lpg_valid) // 2] if lpg_valid else None
        invalid = any(mk is None for _, mk in lpg_runs)
        # kbc with a share of LPG's fastest time (or of the timeout when LPG found nothing).
        budget = args.share * (lpg_fastest if lpg_fastest is not None else args.timeout)
        # (`--improve` counts from the search's start; the start-up and front end before it
        # and the scheduling after it take about what the default run spent outside its
        # search, which is taken off with a margin.)
        overhead = max(0.0, kbc_time - kbc_search)
        improve_budget = max(0.0, budget - 1.5 * overhead)
        improve_time, improve_mk, _ = repeated(lambda: kbc_plan(kb, args.timeout, improve_budget), args.seeds)
        out, t = run(["kairos", "domain.pddl", "problem.pddl", "--timeout", str(int(args.timeout)),
                      "--no-anytime", "--threads", "1"], args.timeout + 10, cwd=export_dir)
        k_plan, k_mk = map_back(out.stdout if out is not None else "", names)
        k_time = t if out is not None and k_plan.strip() else None
        if k_time is None or not validate(kb, k_plan, export_dir, "kairos"):
            k_mk = None
        ratio = f"{lpg_fastest / improve_time:8.1f}x" if lpg_fastest is not None else f"{'-':>9}"
        print(" ".join([f"{rung:<18}", cell(kbc_time, 6), cell(kbc_mk, 7), cell(improve_time, 7), cell(improve_mk, 8),
                        cell(lpg_fastest, 6), cell(lpg_best, 8), cell(lpg_median, 7), ratio, cell(k_time, 8),
                        cell(k_mk, 7)]) + ("  (an LPG plan is invalid)" if invalid else ""), flush=True)


if __name__ == "__main__":
    main()
