#!/usr/bin/python3
"""The kernel level objects (core/batch/kernel_target.hpp) hold no function that another object may
also define with the level's instructions.

A kernel file is compiled once per level with that level's target. A function that the linker
may take from any object that defines it (a template or inline function instantiated in
several objects: a weak symbol) and that the level object compiled with AVX2 or AVX-512
instructions would run on every processor if the linker kept that copy, and fault where the
instructions are missing. So: every global or weak function defined by a level object either
lives in that level's namespace (kernels_x86_64_v3 / v4, only ever called at that level), or
uses no 256- or 512-bit register (ymm, zmm) nor mask register (k0-k7).

Usage: kernel_objects_test.py OBJECT...
"""
import re
import subprocess
import sys

LEVEL_NAMESPACE = re.compile(r"kernels_x86_64_v[34]")
WIDE = re.compile(r"%(?:ymm|zmm)\d+|%k[0-7]\b")


def defined_functions(path):
    """{mangled name: binding letter} of the global and weak code symbols an object defines."""
    out = subprocess.run(["nm", "--defined-only", path], check=True, capture_output=True,
                         text=True).stdout
    symbols = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[1] in ("T", "W"):
            symbols[parts[2]] = parts[1]
    return symbols


def wide_functions(path):
    """{mangled name: first wide instruction} of the functions that use wide registers."""
    out = subprocess.run(["objdump", "-d", "--no-show-raw-insn", path], check=True,
                         capture_output=True, text=True).stdout
    found, current = {}, None
    for line in out.splitlines():
        header = re.match(r"^[0-9a-f]+ <(.+)>:$", line)
        if header:
            current = header.group(1)
            continue
        if current and current not in found and WIDE.search(line):
            found[current] = line.strip()
    return found


def demangle(name):
    return subprocess.run(["c++filt", name], capture_output=True, text=True).stdout.strip()


def main(paths):
    if not paths:
        print("kernel_objects_test.py: no object files given", file=sys.stderr)
        return 2
    errors, checked = [], 0
    for path in paths:
        wide = wide_functions(path)
        for name, binding in defined_functions(path).items():
            checked += 1
            if LEVEL_NAMESPACE.search(demangle(name)):
                continue
            if name in wide:
                errors.append(f"{path}: {demangle(name)} ({'weak' if binding == 'W' else 'global'}"
                              f") is outside the level's namespace and uses {wide[name]}")
    for e in errors:
        print(e)
    print(f"{len(paths)} objects, {checked} global or weak functions, {len(errors)} with the "
          "level's instructions outside its namespace")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
