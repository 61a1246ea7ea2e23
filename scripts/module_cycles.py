#!/usr/bin/env python3
"""Import circles between the library's modules.

Reads the `crate::` and `super::` paths (in `use` lines and inline) of every file under
`crates/crestline/src`, test code left out (`#[cfg(test)]` modules and `tests.rs` files), and
builds the dependency graph level by level: at each level of the module tree, the siblings
under one parent are the nodes (a sibling stands for its whole subtree), and A -> B when a file
of A's subtree names something of B's. A module may use its parent and its children; two
siblings must not use each other, directly or through others. Prints each cycle found and
exits with 1 if there is any.

    python3 scripts/module_cycles.py [crates/crestline/src]
"""

import re
import sys
from collections import defaultdict
from pathlib import Path


def module_of(src: Path, file: Path) -> tuple:
    parts = list(file.relative_to(src).with_suffix("").parts)
    if parts[-1] in ("mod", "lib"):
        parts.pop()
    return tuple(parts)


def code_without_tests_and_comments(text: str) -> str:
    # Test modules sit at the bottom of a file.
    m = re.search(r"^\s*#\[cfg\(test\)\]\s*\n\s*(pub(\(\w+\))?\s+)?mod\s+\w+", text, re.M)
    if m:
        text = text[: m.start()]
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    text = re.sub(r"//[^\n]*", "", text)
    text = re.sub(r'"(\\.|[^"\\])*"', '""', text)
    return text


def crate_paths(code: str, module: tuple):
    """Every path that starts at `crate::` or `super::` (resolved from `module`), as a path
    from the crate root, `use` groups expanded one level."""
    pattern = r"\b(crate::|(?:super::)+)((?:\w+::)*)(\{[^;]*?\}|\w+)"
    for m in re.finditer(pattern, code, re.S):
        start, prefix, tail = m.group(1), m.group(2), m.group(3)
        if start == "crate::":
            root = []
        else:
            ups = start.count("super::")
            if ups > len(module):
                continue
            root = list(module[: len(module) - ups])
        base = "::".join(root + [prefix.rstrip(":")] if prefix else root)
        base = base + "::" if base else ""
        if tail.startswith("{"):
            for item in re.split(r",(?![^{]*\})", tail[1:-1]):
                item = item.strip()
                if item:
                    yield (base + item).split("::")
        else:
            yield (base + tail).split("::")


def main() -> int:
    src = Path(sys.argv[1] if len(sys.argv) > 1 else "crates/crestline/src")
    files = [f for f in src.rglob("*.rs") if f.name != "tests.rs"]
    modules = {module_of(src, f) for f in files}
    # A module's path: the longest prefix of the named path that is a module.
    edges = set()
    for f in files:
        user = module_of(src, f)
        for path in crate_paths(code_without_tests_and_comments(f.read_text()), user):
            path = [p.strip("{} \n") for p in path if p.strip("{} \n")]
            target = ()
            for i in range(1, len(path) + 1):
                if tuple(path[:i]) in modules:
                    target = tuple(path[:i])
            if target:
                edges.add((user, target))
    # Level by level: siblings under a common parent.
    graphs = defaultdict(lambda: defaultdict(set))
    for a, b in edges:
        common = 0
        while common < min(len(a), len(b)) and a[common] == b[common]:
            common += 1
        if common == len(a) or common == len(b):
            continue  # a module and its ancestor or descendant
        parent = a[:common]
        graphs[parent][a[common]].add(b[common])
    cycles = []
    for parent, graph in sorted(graphs.items()):
        for cycle in strongly_connected(graph):
            if len(cycle) > 1:
                cycles.append((parent, cycle))
    for parent, cycle in cycles:
        where = "::".join(("crate",) + parent)
        print(f"cycle under {where}: {' <-> '.join(sorted(cycle))}")
        for a, b in sorted(edges):
            if a[: len(parent)] == parent and b[: len(parent)] == parent:
                if len(a) > len(parent) and len(b) > len(parent):
                    if a[len(parent)] in cycle and b[len(parent)] in cycle and a[len(parent)] != b[len(parent)]:
                        print(f"  {'::'.join(a)} -> {'::'.join(b)}")
    if not cycles:
        print(f"no import cycle among the modules of {src}")
    return 1 if cycles else 0


def strongly_connected(graph):
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]
    nodes = set(graph) | {b for bs in graph.values() for b in bs}

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = set()
            while True:
                w = stack.pop()
                on.discard(w)
                comp.add(w)
                if w == v:
                    break
            out.append(comp)

    for v in sorted(nodes):
        if v not in index:
            visit(v)
    return out


if __name__ == "__main__":
    sys.exit(main())
