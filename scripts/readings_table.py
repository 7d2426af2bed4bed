#!/usr/bin/env python3
"""The lab suite with sensors of other resolutions, gains and offsets: the table of
docs/lab-experiment.md ("Readings").

Runs `cimax arena --readings KIND --decide RULE --runs R --json` (the paper's six patterns and
the alternating experiment from each) for each kind of readings and both decision rules, and
prints a Markdown table: successful runs, and the median and 95th percentile of the time to
consensus in seconds and in mean cycles (55 s). Build first: `cargo build --release -p host-sim`.

    python3 scripts/readings_table.py [--runs 5] [--seed 1] [--cimax target/release/cimax]
"""
import argparse
import json
import subprocess
import sys

KINDS = [
    ("full", "levels (lit 200, dark 30, noise ±10)"),
    ("levels:16", "16 levels (lit 12, dark 1, noise ±0.6)"),
    ("levels:4", "4 levels (lit 3, dark 0)"),
    ("binary", "binary, the paper's g ∈ {0, 1}, no noise"),
    ("gain:0.25,offset:150", "gain 0.25, offset 150 (lit 200, dark 157)"),
]
CYCLE_S = 55.0


def quantile(xs, q):
    """Nearest rank, as the campaign's tables."""
    if not xs:
        return None
    xs = sorted(xs)
    k = max(0, min(len(xs) - 1, int(round(q * len(xs) + 0.5)) - 1))
    return xs[k]


def cell(t):
    return "-" if t is None else f"{t:.0f} ({t / CYCLE_S:.1f})"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--cimax", default="target/release/cimax")
    a = ap.parse_args()
    print("| readings | rule | success | consensus s (cycles): median | p95 |")
    print("|---|---|---:|---:|---:|")
    for kind, text in KINDS:
        for rule in ("fixed", "adaptive"):
            out = subprocess.run(
                [a.cimax, "arena", "--readings", kind, "--decide", rule, "--runs", str(a.runs),
                 "--seed", str(a.seed), "--json"],
                capture_output=True, text=True, check=False)
            if out.returncode not in (0, 1):
                sys.exit(f"cimax failed on {kind} {rule}: {out.stderr}")
            d = json.loads(out.stdout)
            # From the start, or from the mirroring; not the 0 s of LEDs that kept their state
            # through the mirroring (the border in the middle).
            t = [r["consensus_s"] for r in d["runs"]
                 if r["consensus_s"] is not None and r["consensus_s"] > 0]
            s = d["summary"]
            print(f"| {text} (`{kind}`) | {rule} | {s['successes']}/{s['runs']} | "
                  f"{cell(quantile(t, 0.5))} | {cell(quantile(t, 0.95))} |", flush=True)


if __name__ == "__main__":
    main()
