#!/usr/bin/env python3
"""Checks that two parts of the same sharded job (`cimax ... --shard I/N --out DIR`) hold the same
units, bit for bit: the same results in the same order, whatever the robots in the loop ran on
(issue 35, docs/hil.md "Conformance": the campaign with QEMU robots against the same campaign with
their host twins). The header (which names the robots in the loop) and the end line (wall time)
are not compared.

    python3 scripts/parts_same.py A.jsonl B.jsonl [--units N]

Exit code 1, with the first unit that differs, if they differ or if either has not N units; 2,
naming the path, if a file cannot be read as a part.
"""
import json
import sys


def units(path):
    """The part's units, in order, as parsed JSON; exits 2 naming the path if it cannot."""
    out = []
    try:
        with open(path) as f:
            for n, line in enumerate(f, 1):
                v = json.loads(line)
                if "unit" in v:
                    out.append(v)
    except OSError as e:
        print(f"{path}: {e.strerror}", file=sys.stderr)
        sys.exit(2)
    except (json.JSONDecodeError, TypeError) as e:
        print(f"{path}:{n}: not a part ({e})", file=sys.stderr)
        sys.exit(2)
    return out


def main():
    args = sys.argv[1:]
    want = None
    if "--units" in args:
        i = args.index("--units")
        want = int(args[i + 1])
        del args[i : i + 2]
    if len(args) != 2:
        sys.exit(__doc__)
    a, b = (units(p) for p in args)
    for name, u in zip(args, (a, b)):
        if want is not None and len(u) != want:
            print(f"{name}: {len(u)} units, not {want}")
            sys.exit(1)
    if len(a) != len(b):
        print(f"{len(a)} units against {len(b)}")
        sys.exit(1)
    for x, y in zip(a, b):
        if x != y:
            print(f"unit {x.get('unit')} differs:\n  {json.dumps(x)[:400]}\n  {json.dumps(y)[:400]}")
            sys.exit(1)
    print(f"same: {len(a)} units, identical")


if __name__ == "__main__":
    main()
