#!/usr/bin/env python3
"""How close the adaptive rule decides to the floor: the table of docs/lab-experiment.md ("Ties,
flickers and time").

The floor of a run is the first moment every robot *could* know its side: a robot knows the
count only once it knows that nothing lies beyond either end of the line, and an end robot
knows that only when it has heard nothing from outside for a whole longest cycle
(`cycle + cycle_spread` = 70 s on the robots, counted from its start; `docs/protocol.md` §5.4).
So the floor is the first instant at which every robot has heard, through a chain of frames
of that very run (any frame received intact, relayed or not), from both end robots at or after
their 70 s. It is a lower bound for any rule over the same frames: it ignores that a robot
must also learn the others' votes.

For each of the paper's six lab patterns and `--runs` seeds, runs `cimax arena --lights P
--seed S --runs 1 --decide RULE --readings R --trace T --json` (the same runs as `cimax arena
--lights P --runs N --seed 1`, seed by seed) and prints the median and 95th percentile of the
time to consensus and of the floor, and of their difference, run by run.

    python3 scripts/floor_table.py [--runs 100] [--readings full] [--cimax target/release/cimax]
"""
import argparse
import json
import os
import subprocess
import sys

from readings_table import quantile  # nearest rank, as the campaign's tables
import tempfile

PATTERNS = ("1000", "0111", "0001", "1110", "1100", "0011")
LONGEST_S = 70.0


def floor_of(trace_path, robots):
    """The floor of one traced run, in seconds (None if never reached)."""
    ends = (0, robots - 1)
    # know[i][e]: robot i has heard from end e at or after its closure.
    know = [[False, False] for _ in range(robots)]
    last_sent = {}
    with open(trace_path) as f:
        next(f)
        for line in f:
            e = json.loads(line)
            t = e["t_ms"] / 1000.0
            if t >= LONGEST_S:
                for j, end in enumerate(ends):
                    know[end][j] = True
            if e["event"] == "sent":
                last_sent[e["robot"]] = list(know[e["robot"]])
            elif e["event"] == "received" and not e["garbled"] and e.get("corrupted", 0) == 0:
                snap = last_sent.get(e["from"])
                if snap is not None:
                    mine = know[e["robot"]]
                    for j in range(2):
                        mine[j] = mine[j] or snap[j]
            if t >= LONGEST_S and all(all(k) for k in know):
                return t
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=100)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--decide", default="adaptive")
    ap.add_argument("--readings", default="full")
    ap.add_argument("--cimax", default="target/release/cimax")
    a = ap.parse_args()
    times, floors, gaps, wrong = [], [], [], 0
    with tempfile.TemporaryDirectory() as d:
        trace = os.path.join(d, "t.jsonl")
        for p in PATTERNS:
            for s in range(a.seed, a.seed + a.runs):
                out = subprocess.run(
                    [a.cimax, "arena", "--lights", p, "--seed", str(s), "--runs", "1",
                     "--decide", a.decide, "--readings", a.readings, "--trace", trace, "--json"],
                    capture_output=True, text=True, check=False)
                if out.returncode not in (0, 1):
                    sys.exit(f"cimax failed on {p} seed {s}: {out.stderr}")
                run = json.loads(out.stdout)["runs"][0]
                f = floor_of(trace, len(p))
                c = run["consensus_s"]
                if not run["success"] or c is None or f is None:
                    wrong += 1
                    continue
                times.append(c)
                floors.append(f)
                gaps.append(c - f)
    n = len(times)
    print(f"{a.decide} rule, {a.readings} readings: {n} runs judged right of "
          f"{n + wrong}")
    for name, xs in (("consensus", times), ("floor", floors), ("consensus - floor", gaps)):
        print(f"  {name}: median {quantile(xs, 0.5):.1f} s, p95 {quantile(xs, 0.95):.1f} s")


if __name__ == "__main__":
    main()
