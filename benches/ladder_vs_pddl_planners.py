"""kbc against PDDL 2.1 temporal planners on the planner ladder, in one run.

    python3 benches/ladder_vs_pddl_planners.py [--timeout S] [--improve S] [--only build_b10 ...]

For each rung of `kbc bench --write` it times `kbc plan --schedule` (release build), exports
the problem with `kbc export pddl --no-negative-preconditions --durations min` (LPG has no
negative conditions and no duration inequalities; a makespan-minimising planner picks the
minimum anyway), runs LPG-td (the binary `up-lpg` ships, called directly, first plan, seed 1:
its local search is randomised, and its makespans vary from seed to seed) and
Kairos (first plan, one thread), maps their plans back to the KB through names.json, and
validates every plan with `kbc validate`. Wall-clock times include each tool's start-up and
parsing. With `--improve S`, kbc also runs with `kbc plan --improve S` (its anytime search for
a shorter makespan) and the table gains that run's time and makespan. Needs: `pip install 'setuptools<81' up-lpg kairos-planner`.
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
    """Runs `kbc plan --schedule`; returns (seconds, makespan or None)."""
    cmd = [KBC, "plan", kb, "--schedule", "--timeout", str(timeout)]
    if improve is not None:
        cmd += ["--improve", str(improve)]
    out, seconds = run(cmd, timeout + 5)
    makespan = None
    if out is not None and out.returncode == 0:
        m = re.search(r"makespan ([0-9.]+)", out.stdout)
        makespan = float(m.group(1)) if m else None
    return seconds, makespan


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--timeout", type=float, default=60.0)
    parser.add_argument("--only", nargs="*", default=None, help="rung name prefixes")
    parser.add_argument("--improve", type=float, default=None, help="also run kbc plan --improve S")
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
    print(f"timeout {args.timeout:.0f} s per planner and problem; makespans in KB time units; "
          "'invalid' = kbc validate rejects the plan")
    improved = f" {'kbc+i s':>7} {'kbc+i mk':>8}" if args.improve is not None else ""
    print(f"{'problem':<18} {'kbc s':>7} {'kbc mk':>7}{improved} {'LPG s':>7} {'LPG mk':>7} {'ratio':>6} "
          f"{'Kairos s':>8} {'K mk':>7} {'ratio':>6}")
    for rung in rungs:
        kb = os.path.join(work, rung + ".pl")
        kbc_time, kbc_mk = kbc_plan(kb, args.timeout)
        export_dir = os.path.join(work, rung)
        subprocess.run([KBC, "export", "pddl", kb, "-o", export_dir, "--no-negative-preconditions",
                        "--durations", "min", "--limit", "50000000"], capture_output=True)
        with open(os.path.join(export_dir, "names.json")) as f:
            names = json.load(f)
        results = []
        # LPG: first plan.
        if lpg:
            plan_file = os.path.join(export_dir, "lpg.out")
            out, t = run([lpg, "-o", "domain.pddl", "-f", "problem.pddl", "-n", "1", "-out", plan_file],
                         args.timeout, cwd=export_dir)
            text = open(plan_file).read() if os.path.exists(plan_file) else ""
            results.append((t, text))
        else:
            results.append((None, ""))
        out, t = run(["kairos", "domain.pddl", "problem.pddl", "--timeout", str(int(args.timeout)),
                      "--no-anytime", "--threads", "1"], args.timeout + 10, cwd=export_dir)
        results.append((t, out.stdout if out is not None else ""))
        cells = [f"{rung:<18}", f"{kbc_time:7.2f}", f"{kbc_mk:7.2f}" if kbc_mk else f"{'-':>7}"]
        if args.improve is not None:
            t, mk = kbc_plan(kb, args.timeout, args.improve)
            cells += [f"{t:7.2f}", f"{mk:8.2f}" if mk else f"{'-':>8}"]
        for i, (t, text) in enumerate(results):
            plan, mk = map_back(text, names)
            width = 7 if i == 0 else 8
            if t is None or not plan.strip():
                cells += [f"{'-':>{width}}", f"{'-':>7}", f"{'-':>6}"]
                continue
            ok = validate(kb, plan, export_dir, ["lpg", "kairos"][i])
            cells += [f"{t:{width}.2f}", f"{mk:7.2f}" if ok else f"{'invalid':>7}", f"{t / kbc_time:5.1f}x"]
        print(" ".join(cells), flush=True)


if __name__ == "__main__":
    main()
