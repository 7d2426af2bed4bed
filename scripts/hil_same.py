#!/usr/bin/env python3
"""Checks that two `cimax arena --json` outputs of the same command are the same run, bit for
bit, but for the fields that measure wall time (`wall_s`, `hello_ms`, and any key holding
`wall`), and that every run was right (issue 35, docs/hil.md "Time").

    python3 scripts/hil_same.py A.json B.json [--runs N]

Exit code 1, with the first difference's path, if they differ, if a run failed, or if there are
not N runs.
"""
import json
import sys

WALL = ("wall_s", "hello_ms")


def strip(v):
    """`v` without its wall-time fields."""
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items() if k not in WALL and "wall" not in k}
    if isinstance(v, list):
        return [strip(x) for x in v]
    return v


def first_difference(a, b, path="$"):
    """The path of the first place where `a` and `b` differ, or None."""
    if type(a) is not type(b):
        return path
    if isinstance(a, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                return f"{path}.{k}"
            d = first_difference(a[k], b[k], f"{path}.{k}")
            if d:
                return d
        return None
    if isinstance(a, list):
        if len(a) != len(b):
            return f"{path} (length {len(a)} against {len(b)})"
        for i, (x, y) in enumerate(zip(a, b)):
            d = first_difference(x, y, f"{path}[{i}]")
            if d:
                return d
        return None
    return None if a == b else f"{path}: {a!r} against {b!r}"


def main():
    args = sys.argv[1:]
    want = None
    if "--runs" in args:
        i = args.index("--runs")
        want = int(args[i + 1])
        del args[i : i + 2]
    if len(args) != 2:
        sys.exit(__doc__)
    a, b = (strip(json.load(open(p))) for p in args)
    d = first_difference(a, b)
    if d:
        print(f"the two runs differ at {d}")
        sys.exit(1)
    runs = a.get("runs", [])
    bad = [r for r in runs if not r.get("success")]
    if bad:
        print(f"{len(bad)} of {len(runs)} runs failed: {[(r.get('lights'), r.get('seed')) for r in bad]}")
        sys.exit(1)
    if want is not None and len(runs) != want:
        print(f"{len(runs)} runs, expected {want}")
        sys.exit(1)
    print(f"same: {len(runs)} runs, every one right, identical but for wall time")


if __name__ == "__main__":
    main()
