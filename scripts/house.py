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
DEFAULT_CRATES = ["hal-emu", "swarm-sim", "reproduce", "report", "viewer", "lab", "pages", "host-sim"]
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


CFG_TEST = re.compile(r"#\[cfg\((?:test|all\(test\b[^\]]*\))\)\]")


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


PATH_IN_CODE = re.compile(r"(?<![\w:])(\w+(?:\s*::\s*\w+)+)")
USE = re.compile(r"(?<![\w:])use\s+([^;]+);")


def module_files(src):
    """{module path (a tuple of names; the crate root is ()): file} of the crate at `src`.
    Binaries under src/bin/ are crate roots of their own and left out."""
    mods = {}
    for path in sorted(src.rglob("*.rs")):
        parts = path.relative_to(src).with_suffix("").parts
        if parts[0] == "bin":
            continue
        if parts in (("lib",), ("main",)):
            parts = ()
        elif parts[-1] == "mod":
            parts = parts[:-1]
        mods.setdefault(parts, path)
    return mods


def use_paths(tree):
    """Every full path a `use` tree names, as lists of segments (`self` in a group dropped)."""
    tree = re.sub(r"\s+as\s+\w+", "", tree)
    tree = re.sub(r"\s+", "", tree)

    def expand(text):
        out, depth, start, items = [], 0, 0, []
        for i, c in enumerate(text):
            if c == "{":
                depth += 1
            elif c == "}":
                depth -= 1
            elif c == "," and depth == 0:
                items.append(text[start:i])
                start = i + 1
        items.append(text[start:])
        for item in filter(None, items):
            if "{" in item:
                head = item[: item.index("{")].rstrip(":").split("::")
                inner = item[item.index("{") + 1 : item.rindex("}")]
                for sub in expand(inner):
                    out.append([s for s in head if s] + [s for s in sub if s != "self"])
            else:
                out.append([s for s in item.split("::") if s and s != "*"])
        return out

    return expand(tree.lstrip(":"))


def resolve(mods, here, segs):
    """The deepest module file a path from module `here` names, or None (not this crate's)."""
    if not segs:
        return None
    first = segs[0]
    if first == "crate":
        base, rest = (), segs[1:]
    elif first == "self":
        base, rest = here, segs[1:]
    elif first == "super":
        base, rest = here, segs
        while rest and rest[0] == "super":
            base, rest = base[:-1], rest[1:]
    elif here + (first,) in mods:
        base, rest = here, segs
    else:
        return None
    for seg in rest:
        if base + (seg,) not in mods:
            break
        base = base + (seg,)
    return base


def file_edges(root):
    """{(from file, to file): first place}: module A names a module B of the same crate that is
    neither A nor one of its ancestors (a child sees its parent's items; the parent declares
    it), through `use` trees or paths in code (`crate::`, `self::`, `super::` chains, child
    module names). Comments, strings and test-only items are left out."""
    src = root / "src"
    mods = module_files(src)
    edges = {}
    for here, path in mods.items():
        code = without_tests(strip_code(path.read_text()))
        found = []
        for m in USE.finditer(code):
            found += [(p, m.start()) for p in use_paths(m.group(1))]
        code = USE.sub(lambda m: "\n" * m.group(0).count("\n"), code)
        for m in PATH_IN_CODE.finditer(code):
            found.append((re.sub(r"\s+", "", m.group(1)).split("::"), m.start()))
        for segs, at in found:
            to = resolve(mods, here, segs)
            if to is None or to == here or here[: len(to)] == to:
                continue
            key = (str(path.relative_to(src)), str(mods[to].relative_to(src)))
            edges.setdefault(key, f"{path}:{code.count(chr(10), 0, at) + 1}")
    return edges


def circles(edges):
    """The strongly connected sets of more than one file (Tarjan), each with one cycle."""
    nexts = {}
    for a, b in edges:
        nexts.setdefault(a, set()).add(b)
        nexts.setdefault(b, set())
    index, low, stack, on, sccs = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(nexts[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            scc = []
            while True:
                w = stack.pop()
                on.discard(w)
                scc.append(w)
                if w == v:
                    break
            if len(scc) > 1:
                sccs.append(sorted(scc))

    for v in sorted(nexts):
        if v not in index:
            visit(v)
    found = []
    for scc in sorted(sccs):
        start, inside = scc[0], set(scc)
        prev, queue = {start: None}, [start]
        cycle = None
        while queue and cycle is None:
            v = queue.pop(0)
            for w in sorted(nexts[v] & inside):
                if w == start:
                    cycle = [v]
                    break
                if w not in prev:
                    prev[w] = v
                    queue.append(w)
        while cycle[-1] != start:
            cycle.append(prev[cycle[-1]])
        found.append((scc, list(reversed(cycle)) + [start]))
    return found


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
    print("import circles between the files of a crate (every crate with a src/):")
    files = 0
    for root in sorted(p.parent for p in pathlib.Path(".").glob("*/src") if (p.parent / "Cargo.toml").exists()):
        edges = file_edges(root)
        for scc, cycle in circles(edges):
            files += 1
            print(f"  {root.name}: {len(scc)} files: {', '.join(scc)}")
            for a, b in zip(cycle, cycle[1:]):
                print(f"      {a} -> {b}  {edges[(a, b)]}")
    print(f"{files} circles")
    return 1 if long_files or long_fns or found or files else 0


if __name__ == "__main__":
    sys.exit(main())
