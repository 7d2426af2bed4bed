#!/usr/bin/env python3
"""Issue 22's house rules, measured: files over 800 lines (outside tests) and functions over 80
lines in host-sim and hal-emu (or the crates given).

    python3 scripts/house.py [CRATE_DIR ...]

A function is counted from its `fn` line to the line that closes its body (brace matching on
code with strings, chars and comments stripped); `#[cfg(test)]` modules and files under tests/
are left out. Exit code 1 if any rule is broken, so it can guard CI once the house is clean.
"""
import pathlib
import re
import sys

FILE_MAX, FN_MAX = 800, 80
STRIP = re.compile(r'//.*|"(?:\\.|[^"\\])*"|\'(?:\\.|[^\'\\])\'')
FN = re.compile(r'^\s*(pub(\([^)]*\))?\s+)?(const\s+)?(async\s+)?(unsafe\s+)?fn\s+(\w+)')


def code_lines(path):
    """The file's lines up to its `#[cfg(test)]` module, strings and comments stripped."""
    out = []
    for line in path.read_text().splitlines():
        if line.strip() == "#[cfg(test)]":
            break
        out.append(STRIP.sub('""', line))
    return out


def functions(lines):
    """(name, first line, length) of every function with a body."""
    found = []
    for i, line in enumerate(lines):
        m = FN.match(line)
        if not m:
            continue
        depth, opened = 0, False
        for j in range(i, len(lines)):
            for c in lines[j]:
                if c == "{":
                    depth, opened = depth + 1, True
                elif c == "}":
                    depth -= 1
            if opened and depth == 0:
                found.append((m.group(6), i + 1, j - i + 1))
                break
            if not opened and lines[j].rstrip().endswith(";"):
                break
    return found


def main():
    roots = [pathlib.Path(a) for a in sys.argv[1:]] or [pathlib.Path("host-sim"), pathlib.Path("hal-emu")]
    long_files, long_fns = [], []
    for root in roots:
        for path in sorted((root / "src").rglob("*.rs")):
            total = len(path.read_text().splitlines())
            lines = code_lines(path)
            if len(lines) > FILE_MAX:
                long_files.append((len(lines), total, path))
            long_fns += [(n, name, path, at) for name, at, n in functions(lines) if n > FN_MAX]
    print(f"files over {FILE_MAX} lines (without their tests; with them):")
    for n, total, path in sorted(long_files, reverse=True):
        print(f"  {n:5} ({total:5})  {path}")
    print(f"functions over {FN_MAX} lines:")
    for n, name, path, at in sorted(long_fns, reverse=True):
        print(f"  {n:5}  {path}:{at} {name}")
    print(f"{len(long_files)} files, {len(long_fns)} functions")
    return 1 if long_files or long_fns else 0


if __name__ == "__main__":
    sys.exit(main())
