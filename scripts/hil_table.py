#!/usr/bin/env python3
"""Robots in the loop: how far the cycle can shrink before decisions suffer (docs/hil.md,
"Numbers").

For each cycle, runs the paper's six lab patterns with four QEMU robots
(`cimax arena --hil qemu:4 --hil-clock wall --lights P --cycle C --runs R --json`, in real time, one run after the
other) and the same with four virtual robots (`--runs 20`, virtual time), and prints a Markdown
table: right runs with QEMU robots and with virtual ones, the median time to consensus in cycles,
and the link's heartbeat round trip (mean and worst) and traffic. Build first:
`cargo build --release -p host-sim` and `cargo hil-image`; needs qemu-system-arm.

    python3 scripts/hil_table.py [--cycles 2,1,0.5,0.25,0.125] [--runs 1] [--cimax target/release/cimax]

With --from DIR it reads the JSON files a previous run left there (cyc-C-P.json) instead of
running QEMU again.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

PATTERNS = ["1000", "1100", "1110", "0001", "0011", "0111"]


def arena(cimax, args):
    out = subprocess.run([cimax, "arena", *args, "--json"], capture_output=True, text=True)
    if not out.stdout.strip():
        sys.exit(f"cimax arena {' '.join(args)} failed: {out.stderr.strip()}")
    return json.loads(out.stdout)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cycles", default="2,1,0.5,0.25,0.125")
    ap.add_argument("--runs", type=int, default=1)
    ap.add_argument("--cimax", default="target/release/cimax")
    ap.add_argument("--from", dest="source", help="read cyc-C-P.json files from this folder")
    a = ap.parse_args()
    print("| cycle | right, 4 QEMU robots | right, 4 virtual robots | consensus, cycles (median, QEMU) "
          "| heartbeat round trip, mean / worst | link traffic per robot, to / from it |")
    print("|---:|---:|---:|---:|---:|---:|")
    for c in a.cycles.split(","):
        runs, virtual_ok, virtual_n = [], 0, 0
        for p in PATTERNS:
            if a.source:
                with open(os.path.join(a.source, f"cyc-{c}-{p}.json")) as f:
                    d = json.load(f)
            else:
                d = arena(a.cimax, ["--hil", "qemu:4", "--hil-clock", "wall", "--lights", p, "--cycle", c,
                                    "--runs", str(a.runs)])
            runs += d["runs"]
            v = arena(a.cimax, ["--lights", p, "--cycle", c, "--runs", "20"])["summary"]
            virtual_ok += v["successes"]
            virtual_n += v["runs"]
        ok = sum(r["success"] for r in runs)
        cyc = [r["consensus_s"] / float(c) for r in runs if r.get("consensus_s") is not None]
        links = [h for r in runs for h in r.get("hil", [])]
        trips = sum(h["round_trips"] for h in links)
        mean_rtt = sum(h["rtt_mean_us"] * h["round_trips"] for h in links) / max(trips, 1) / 1000
        worst = max((h["rtt_max_us"] for h in links), default=0) / 1000
        wall = sum(r["wall_s"] for r in runs) or 1.0
        to_robot = sum(h["bytes_sent"] for h in links) / wall / 4
        from_robot = sum(h["bytes_received"] for h in links) / wall / 4
        med = f"{statistics.median(cyc):.1f}" if cyc else "-"
        print(f"| {c} s | {ok}/{len(runs)} | {virtual_ok}/{virtual_n} | {med} "
              f"| {mean_rtt:.2f} / {worst:.1f} ms | {to_robot:,.0f} / {from_robot:,.0f} B/s |")


if __name__ == "__main__":
    main()
