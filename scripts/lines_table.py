#!/usr/bin/env python3
"""Swarm-wide agreement in long lines: the table of docs/lab-experiment.md ("Long lines").

Runs `cimax arena --lights P --runs R --json` for lines of 8, 16, 32 and 64 robots with the
border at three positions (and the exact tie), at 0 % and 10 % frame loss, and prints a
Markdown table of successful runs. Build first: `cargo build --release -p host-sim`.

    python3 scripts/lines_table.py [--runs 50] [--seed 1] [--cimax target/release/cimax]

With `--grid`, the table of docs/lab-experiment.md ("Ties, flickers and time"): ties and
non-ties of 4 to 64 robots; full, binary and 3-level readings; 0 % and 10 % loss; both rules;
`--runs` seeds each (100 in the docs). Each cell: runs right, robots that flickered (changed
their LEDs after showing their side), median and 95th percentile of the time to consensus. Runs
two `cimax` processes at a time (`--jobs`).

With `--sweep`, every line of 2 to 64 robots in the list below, every border whose majority is
at least 55 % and the exact tie, lit on either side, `--runs` seeds each (docs: `--sweep --runs 5
--seed 7000`, once with `--loss 0` and once with `--loss 0.1`); prints the totals and each
failing run. `--readings KIND` passes `cimax arena --readings` (full, binary, levels:N,
gain:G,offset:B); `--decide` the decision rule.
"""
import argparse
import concurrent.futures
import json
import subprocess
import sys

from readings_table import quantile  # nearest rank, as the campaign's tables

LINES = {8: (1, 2, 3), 16: (2, 4, 7), 32: (4, 8, 14), 64: (8, 16, 28)}
SWEEP = (2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 16, 17, 20, 24, 31, 32, 40, 48, 63, 64)


def sweep(a):
    ok = total = 0
    for n in SWEEP:
        for b in range(1, n):
            if max(b, n - b) / n < 0.55 and b * 2 != n:
                continue
            for pattern in ("1" * b + "0" * (n - b), "0" * b + "1" * (n - b)):
                good, runs, failed = run(a.cimax, pattern, a.runs, a.seed, a.loss)
                ok, total = ok + good, total + runs
                for s in failed:
                    print(f"FAILED: cimax arena --lights {pattern} --seed {s} --runs 1 "
                          f"--loss {a.loss} --decide {DECIDE} --readings {READINGS}")
        print(f"up to {n} robots: {ok}/{total}", flush=True)
    print(f"total: {ok}/{total} successful runs at loss {a.loss}")


DECIDE = "fixed"
READINGS = "full"


def run(cimax, pattern, runs, seed, loss):
    out = subprocess.run(
        [cimax, "arena", "--lights", pattern, "--runs", str(runs), "--seed", str(seed),
         "--loss", str(loss), "--decide", DECIDE, "--readings", READINGS, "--json"],
        capture_output=True, text=True, check=False)
    if out.returncode not in (0, 1):
        sys.exit(f"cimax failed on {pattern}: {out.stderr}")
    d = json.loads(out.stdout)
    failed = [r["seed"] for r in d["runs"] if not r["success"]]
    times = sorted(r["consensus_s"] for r in d["runs"] if r["consensus_s"] is not None)
    if times:
        TIMES.setdefault(loss, []).extend(times)
    return d["summary"]["successes"], d["summary"]["runs"], failed


TIMES = {}

# --grid: (robots, lit) per row; ties first, then the border nearest the middle that is no tie
# (and the 13/20 and 9/40).
GRID_TIES = ((4, 2), (8, 4), (10, 5), (16, 8), (20, 10), (32, 16), (64, 32))
GRID_MAJORITIES = ((4, 1), (8, 3), (16, 7), (20, 13), (32, 14), (40, 9), (64, 28))
GRID_READINGS = ("full", "binary", "levels:3")


def grid_cell(cimax, pattern, runs, seed, loss, rule, readings):
    """One cell: (right, flickers, times, failing seeds) of `runs` seeds."""
    out = subprocess.run(
        [cimax, "arena", "--lights", pattern, "--runs", str(runs), "--seed", str(seed),
         "--loss", str(loss), "--decide", rule, "--readings", readings, "--json"],
        capture_output=True, text=True, check=False)
    if out.returncode not in (0, 1):
        sys.exit(f"cimax failed on {pattern}: {out.stderr}")
    d = json.loads(out.stdout)
    right = sum(1 for r in d["runs"] if r["success"])
    flickers = sum(r.get("flickers", 0) for r in d["runs"])
    times = [r["consensus_s"] for r in d["runs"] if r["consensus_s"] is not None]
    failed = [r["seed"] for r in d["runs"] if not r["success"]]
    return right, len(d["runs"]), flickers, times, failed


def grid(a):
    rows = [(n, b, True) for n, b in GRID_TIES] + [(n, b, False) for n, b in GRID_MAJORITIES]
    rules = (a.decide,) if a.only_rule else ("fixed", "adaptive")
    jobs = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
        for n, b, _ in rows:
            pattern = "1" * b + "0" * (n - b)
            for readings in GRID_READINGS:
                for loss in (0.0, 0.1):
                    for rule in rules:
                        key = (n, b, readings, loss, rule)
                        jobs[key] = pool.submit(grid_cell, a.cimax, pattern, a.runs, a.seed,
                                                loss, rule, readings)
    fmt = lambda t: "-" if t is None else f"{t:.0f}"
    head = " | ".join(f"{r}: right | flickers | median s | p95 s" for r in rules)
    print(f"| robots | lit | readings | loss | {head} |")
    print("|---:|---:|---|---:|" + "---:|---:|---:|---:|" * len(rules))
    fails = []
    for n, b, _ in rows:
        pattern = "1" * b + "0" * (n - b)
        tie = " (tie)" if 2 * b == n else ""
        for readings in GRID_READINGS:
            for loss in (0.0, 0.1):
                cells = []
                for rule in rules:
                    right, total, flickers, times, failed = jobs[(n, b, readings, loss, rule)].result()
                    cells.append(f"{right}/{total} | {flickers} | {fmt(quantile(times, 0.5))} | "
                                 f"{fmt(quantile(times, 0.95))}")
                    fails += [f"cimax arena --lights {pattern} --seed {s} --runs 1 --loss {loss} "
                              f"--decide {rule} --readings {readings}" for s in failed]
                print(f"| {n} | {b}{tie} | {readings} | {loss:.0%} | {' | '.join(cells)} |")
    for f in fails:
        print(f"FAILED: {f}", file=sys.stderr)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=50)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--cimax", default="target/release/cimax")
    ap.add_argument("--sweep", action="store_true")
    ap.add_argument("--grid", action="store_true", help="the ties, flickers and time table")
    ap.add_argument("--jobs", type=int, default=2, help="with --grid: cimax processes at once")
    ap.add_argument("--only-rule", action="store_true",
                    help="with --grid: only the rule of --decide")
    ap.add_argument("--loss", type=float, default=0.0, help="with --sweep")
    ap.add_argument("--decide", choices=["fixed", "adaptive"], default="fixed",
                    help="the robots' decision rule (cimax arena --decide)")
    ap.add_argument("--readings", default="full",
                    help="what the sensors report (cimax arena --readings)")
    a = ap.parse_args()
    global DECIDE, READINGS
    DECIDE = a.decide
    READINGS = a.readings
    if a.grid:
        grid(a)
        return
    if a.sweep:
        sweep(a)
        return
    print("| robots | lit (border after) | majority | 0 % loss | 10 % loss |")
    print("|---:|---:|---|---:|---:|")
    failures = []
    for n, borders in LINES.items():
        for b in borders + (n // 2,):
            pattern = "1" * b + "0" * (n - b)
            big = max(b, n - b)
            majority = "tie: each half toward the border" if b * 2 == n else \
                f"{big}/{n} = {100 * big / n:.0f} % prefer {'left' if n - b > b else 'right'}"
            cells = []
            for loss in (0.0, 0.1):
                ok, total, failed = run(a.cimax, pattern, a.runs, a.seed, loss)
                cells.append(f"{ok}/{total}")
                failures += [(pattern, s, loss) for s in failed]
            print(f"| {n} | {b} | {majority} | {cells[0]} | {cells[1]} |", flush=True)
    for loss, t in sorted(TIMES.items()):
        t.sort()
        print(f"\ntime to consensus at {loss:.0%} loss over every line: median "
              f"{t[len(t) // 2]:.0f} s, p95 {t[min(len(t) - 1, int(0.95 * len(t)))]:.0f} s")
    for pattern, s, loss in failures:
        print(f"FAILED: cimax arena --lights {pattern} --seed {s} --runs 1 --loss {loss} "
              f"--decide {DECIDE} --readings {READINGS}", file=sys.stderr)


if __name__ == "__main__":
    main()
