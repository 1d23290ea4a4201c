#!/usr/bin/env python3
"""The layers of docs/architecture.md look only down, and no files include each other.

Every #include "dir/..." of the project's own sources names a file of the same layer or of a
lower one, lowest first:

    core/common < core/algebra < core/model < core/contact < core/methods < core/spectral
      < core/reference < core/run < core/batch
      < metrics < study/formats < study/plan < study/studies < study/io < study/cli

(tests, benchmarks, fuzzers and python/ sit on top and may include anything). A source file of
core/ or study/ outside these folders, or an include of a file that does not exist, fails the
test too: a moved header must not leave a stale path behind.

Within a layer, includes must not go round in a circle: a file's header and source (a.hpp,
a.cpp) count as one unit, and no unit may reach itself through the includes of others (a.cpp
includes b.hpp, which includes a.hpp, is such a circle).
"""
import pathlib
import re
import sys

LAYERS = ["core/common", "core/algebra", "core/model", "core/contact", "core/methods",
          "core/spectral", "core/reference", "core/run", "core/batch", "metrics",
          "study/formats", "study/plan", "study/studies", "study/io", "study/cli"]
# Generated into the build tree by CMake (study/version.hpp.in): the version, below every layer.
GENERATED = {"study/version.hpp"}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.MULTILINE)


def layer_of(path: str):
    for rank in range(len(LAYERS) - 1, -1, -1):
        if path.startswith(LAYERS[rank] + "/"):
            return rank
    return None


def unit_of(path: str) -> str:
    """a.hpp and a.cpp are one unit: the path without its suffix."""
    return path.rsplit(".", 1)[0]


def circles(graph):
    """The strongly connected components of more than one unit (Tarjan's algorithm)."""
    index, low, on_stack, stack, found = {}, {}, set(), [], []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def main() -> int:
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    sys.setrecursionlimit(10000)
    problems = []
    graph = {}
    for top in ("core", "metrics", "study"):
        for source in sorted((root / top).rglob("*")):
            if source.suffix not in (".hpp", ".cpp"):
                continue
            name = source.relative_to(root).as_posix()
            rank = layer_of(name)
            if rank is None:
                problems.append(f"{name}: not in a layer ({', '.join(LAYERS)})")
                continue
            unit = unit_of(name)
            graph.setdefault(unit, set())
            for included in INCLUDE.findall(source.read_text(encoding="utf-8")):
                if included in GENERATED:
                    continue
                if not (root / included).is_file():
                    problems.append(f"{name}: includes {included}, which does not exist")
                    continue
                target = layer_of(included)
                if target is not None and target > rank:
                    problems.append(f"{name} ({LAYERS[rank]}) includes {included} "
                                    f"({LAYERS[target]}): a layer may only look down")
                if target is not None and unit_of(included) != unit:
                    graph[unit].add(unit_of(included))
    for component in circles(graph):
        problems.append("these include each other, round in a circle: " + ", ".join(component))
    for p in problems:
        print(p, file=sys.stderr)
    print(f"layering: {len(graph)} units, {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
