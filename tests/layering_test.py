#!/usr/bin/env python3
"""The layers of docs/architecture.md look only down: every #include "dir/..." of the project's
own sources names a file of the same layer or of a lower one.

    core < metrics < study/formats < study/plan < study/studies < study/io < study/cli

(tests, benchmarks, fuzzers and python/ sit on top and may include anything). A file in study/
outside the four layers, or an include of a file that does not exist, fails the test too: a
moved header must not leave a stale path behind.
"""
import pathlib
import re
import sys

LAYERS = ["core", "metrics", "study/formats", "study/plan", "study/studies", "study/io", "study/cli"]
# Generated into the build tree by CMake (study/version.hpp.in): the version, below every layer.
GENERATED = {"study/version.hpp"}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.MULTILINE)


def layer_of(path: str):
    for rank in range(len(LAYERS) - 1, -1, -1):
        if path.startswith(LAYERS[rank] + "/"):
            return rank
    return None


def main() -> int:
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    problems = []
    for top in ("core", "metrics", "study"):
        for source in sorted((root / top).rglob("*")):
            if source.suffix not in (".hpp", ".cpp"):
                continue
            name = source.relative_to(root).as_posix()
            rank = layer_of(name)
            if rank is None:
                problems.append(f"{name}: not in a layer ({', '.join(LAYERS)})")
                continue
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
    for p in problems:
        print(p, file=sys.stderr)
    print(f"layering: {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
