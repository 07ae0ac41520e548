#!/usr/bin/env python3
"""Lists the import loops between the modules (files) of each crate under crates/*/src.

A module A depends on B when a path in A (a `use` line or an inline `crate::`/`super::` path)
names B or an item defined in B; a `pub use` in a module is followed to where the item lives, so
re-exports do not count as dependencies of their own. `mod x;` declarations are not dependencies.
Every strongly connected component of more than one module is a loop. Exit status 1 if any.

    python3 tools/import_cycles.py            # all crates
    python3 tools/import_cycles.py -v         # also print each edge of each loop
"""

import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def module_of(src: Path, f: Path) -> tuple:
    rel = f.relative_to(src).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] in ("mod", "lib", "main"):
        parts = parts[:-1]
    return tuple(parts)


def strip_comments(text: str) -> str:
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    text = re.sub(r"//[^\n]*", "", text)
    text = re.sub(r'"(\\.|[^"\\])*"', '""', text)
    return text


def fold_inline_modules(text: str) -> str:
    """Inside an inline `mod x { ... }` (such as `mod tests`), `super::` is the file's own
    module: rewrite it as `self::` so that paths resolve against the file."""
    out, i = [], 0
    for m in re.finditer(r"\bmod\s+\w+\s*\{", text):
        if m.start() < i:
            continue
        depth, j = 0, m.end() - 1
        while j < len(text):
            if text[j] == "{":
                depth += 1
            elif text[j] == "}":
                depth -= 1
                if depth == 0:
                    break
            j += 1
        out.append(text[i : m.end()])
        out.append(re.sub(r"\bsuper::", "self::", text[m.end() : j]))
        i = j
    out.append(text[i:])
    return "".join(out)


def expand_use(tree: str) -> list:
    """`a::{b, c::{d, e as f}}` -> [[a, b], [a, c, d], [a, c, e]]"""
    tree = tree.strip()
    out = []
    depth = 0
    # split top level on "::{"
    i = tree.find("{")
    if i < 0:
        p = tree.split(" as ")[0].strip()
        return [[s for s in p.split("::") if s]]
    prefix = [s for s in tree[:i].rstrip(":").split("::") if s]
    inner = tree[i + 1 : tree.rfind("}")]
    items, cur = [], ""
    for ch in inner:
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
        if ch == "," and depth == 0:
            items.append(cur)
            cur = ""
        else:
            cur += ch
    items.append(cur)
    for it in items:
        if it.strip():
            for p in expand_use(it):
                out.append(prefix + p)
    return out


def analyse(src: Path, verbose: bool) -> int:
    files = {module_of(src, f): f for f in src.rglob("*.rs")}
    texts = {m: fold_inline_modules(strip_comments(f.read_text())) for m, f in files.items()}
    # children declared by `mod x;` or `mod x {` (inline modules are folded into their file)
    children = {m: set(re.findall(r"\bmod\s+(\w+)\s*[;{]", t)) for m, t in texts.items()}

    def absolute(m: tuple, path: list):
        if not path:
            return None
        head = path[0]
        if head == "crate":
            return list(path[1:])
        if head == "self":
            return list(m) + path[1:]
        if head == "super":
            base = list(m)
            while path and path[0] == "super":
                base = base[:-1]
                path = path[1:]
            return base + list(path)
        if head in children.get(m, ()):
            return list(m) + list(path)
        return None  # external crate or std

    reexports = {}
    for m, t in texts.items():
        table = {}
        for body in re.findall(r"\bpub(?:\([^)]*\))?\s+use\s+([^;]+);", t):
            for p in expand_use(body):
                a = absolute(m, p)
                if a:
                    name = p[-1]
                    alias = re.search(r"\b" + re.escape(name) + r"\s+as\s+(\w+)", body)
                    table[alias.group(1) if alias else name] = a
        reexports[m] = table

    def resolve(path: list, depth=0):
        """Longest module prefix of an absolute path, following re-exports."""
        k = len(path)
        while k > 0 and tuple(path[:k]) not in files:
            k -= 1
        mod = tuple(path[:k])
        rest = path[k:]
        if rest and depth < 20 and rest[0] in reexports.get(mod, {}):
            target = reexports[mod][rest[0]] + rest[1:]
            if target != path:
                return resolve(target, depth + 1)
        return mod

    edges = {m: set() for m in files}
    why = {}
    for m, t in texts.items():
        paths = []
        for body in re.findall(r"\buse\s+([^;]+);", t):
            paths += expand_use(body)
        for inline in re.findall(r"\b((?:crate|super|self)(?:::\w+)+)(?!\w|::)", t):
            paths.append(inline.split("::"))
        for p in paths:
            a = absolute(m, p)
            if a is None:
                continue
            target = resolve(a)
            if target != m and target in files:
                edges[m].add(target)
                why.setdefault((m, target), "::".join(p))

    # Tarjan's strongly connected components
    index, low, stack, on, sccs = {}, {}, [], set(), []
    counter = [0]

    def strong(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                strong(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                sccs.append(comp)

    sys.setrecursionlimit(10000)
    for v in sorted(files):
        if v not in index:
            strong(v)

    name = lambda m: "::".join(m) or "(root)"
    for comp in sccs:
        print(f"{src.parent.name}: loop among {', '.join(sorted(name(m) for m in comp))}")
        if verbose:
            for a in comp:
                for b in edges[a]:
                    if b in comp:
                        print(f"    {name(a)} -> {name(b)}   ({why[(a, b)]})")
    return len(sccs)


def main():
    verbose = "-v" in sys.argv
    total = sum(analyse(src, verbose) for src in sorted(ROOT.glob("crates/*/src")))
    print(f"{total} import loop(s)")
    sys.exit(1 if total else 0)


if __name__ == "__main__":
    main()
