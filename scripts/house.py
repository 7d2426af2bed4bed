#!/usr/bin/env python3
"""Issue 22's house rules, measured: files over 800 lines (outside tests), functions over 80
lines, and import cycles between a crate's top-level modules, in hal-emu and the host crates (or
the crates given).

    python3 scripts/house.py [CRATE_DIR ...]

A function is counted from its `fn` line to the line that closes its body (brace matching on
code with strings, chars and comments stripped); `#[cfg(test)]` modules and files under tests/
are left out.

The import graph has one node per top-level module (a file or directory directly under src/,
lib.rs and main.rs left out) and an edge A -> B when code in A names `crate::B` (in a `use` line
or a path, grouped `crate::{B, ..}` and `super::` chains that reach the crate root included).
Comments, doc comments, strings and `#[cfg(test)]` items are left out. Every elementary cycle
is printed once, starting at its alphabetically first module, with one place for each edge.

Exit code 1 if any rule is broken, so it can guard CI once the house is clean.
"""
import pathlib
import re
import sys

FILE_MAX, FN_MAX = 800, 80
# hal-emu and the host tools, one crate per layer (issue 37).
DEFAULT_CRATES = ["hal-emu", "swarm-sim", "report", "viewer", "lab", "pages", "host-sim"]
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


def strip_code(text):
    """The text with comments, strings and char literals blanked; newlines kept (line numbers)."""
    out, i, n = [], 0, len(text)
    char = re.compile(r"'(\\u\{[0-9a-fA-F]+\}|\\.|[^\\'\n])'")
    raw = re.compile(r'b?r(#*)"')
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            depth, j = 0, i
            while j < n:
                if text.startswith("/*", j):
                    depth, j = depth + 1, j + 2
                elif text.startswith("*/", j):
                    depth, j = depth - 1, j + 2
                    if depth == 0:
                        break
                else:
                    j += 1
            out.append("\n" * text.count("\n", i, j))
            i = j
        elif (m := raw.match(text, i)) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            end = text.find('"' + m.group(1), m.end())
            end = n if end < 0 else end + 1 + len(m.group(1))
            out.append('""' + "\n" * text.count("\n", i, end))
            i = end
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            out.append('""' + "\n" * text.count("\n", i, j))
            i = j + 1
        elif c == "'" and (m := char.match(text, i)):
            out.append("' '")
            i = m.end()
        else:
            out.append(c)
            i += 1
    return "".join(out)


CFG_TEST = re.compile(r"#\[cfg\(test\)\]")


def without_tests(code):
    """The stripped code with every `#[cfg(test)]` item blanked (newlines kept)."""
    while m := CFG_TEST.search(code):
        i, depth = m.end(), 0
        while i < len(code):
            c = code[i]
            if c == "{":
                depth += 1
            elif c == "}":
                depth -= 1
                if depth == 0:
                    i += 1
                    break
            elif c == ";" and depth == 0:
                i += 1
                break
            i += 1
        code = code[: m.start()] + "\n" * code.count("\n", m.start(), i) + code[i:]
    return code


PATH = re.compile(r"(?<![\w:])((?:crate|(?:super\s*::\s*)*super)\s*::\s*)(\w+|\{)")


def group_heads(code, at):
    """The first segment of each path in the `{...}` group opening at `at`."""
    heads, depth, start = [], 0, at + 1
    for j in range(at, len(code)):
        if code[j] == "{":
            depth += 1
        elif code[j] == "}":
            depth -= 1
        if (code[j] == "," and depth == 1) or depth == 0:
            head = re.match(r"\s*(\w+)", code[start:j])
            if head:
                heads.append(head.group(1))
            start = j + 1
        if depth == 0:
            break
    return heads


def module_of(src, path):
    """(top-level module, depth of the file's own module below the crate root)."""
    parts = list(path.relative_to(src).with_suffix("").parts)
    if parts[-1] == "mod":
        parts.pop()
    return parts[0], len(parts)


def import_edges(root):
    """{(from, to): first place} between the top-level modules of the crate at `root`."""
    src = root / "src"
    tops = {p.stem if p.is_file() else p.name for p in src.iterdir()
            if (p.is_dir() or p.suffix == ".rs") and p.name not in ("lib.rs", "main.rs")}
    edges = {}
    for path in sorted(src.rglob("*.rs")):
        if path.parent == src and path.name in ("lib.rs", "main.rs"):
            continue
        here, depth = module_of(src, path)
        code = without_tests(strip_code(path.read_text()))
        for m in PATH.finditer(code):
            supers = m.group(1).count("super")
            if supers and supers != depth:
                continue  # stays inside a top-level module (or is not a path to the root)
            heads = group_heads(code, m.start(2)) if m.group(2) == "{" else [m.group(2)]
            line = code.count("\n", 0, m.start()) + 1
            for head in heads:
                if head in tops and head != here:
                    edges.setdefault((here, head), f"{path}:{line}")
    return edges


def cycles(edges):
    """Every elementary cycle of the graph, each once, starting at its smallest node."""
    nexts = {}
    for a, b in edges:
        nexts.setdefault(a, []).append(b)
    found = []

    def walk(start, path):
        for b in sorted(nexts.get(path[-1], [])):
            if b == start:
                found.append(path + [start])
            elif b > start and b not in path:
                walk(start, path + [b])

    for start in sorted(nexts):
        walk(start, [start])
    return found


def main():
    roots = [pathlib.Path(a) for a in sys.argv[1:]] or [pathlib.Path(c) for c in DEFAULT_CRATES]
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
    print("import cycles between top-level modules:")
    found = 0
    for root in roots:
        edges = import_edges(root)
        for cycle in cycles(edges):
            found += 1
            print(f"  {root.name}: {' -> '.join(cycle)}")
            for a, b in zip(cycle, cycle[1:]):
                print(f"      {a} -> {b}  {edges[(a, b)]}")
    print(f"{found} cycles")
    return 1 if long_files or long_fns or found else 0


if __name__ == "__main__":
    sys.exit(main())
