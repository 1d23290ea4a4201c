#!/usr/bin/python3
"""scripts/compare-results: identical files pass; a changed value fails; a dataset or root
attribute that only the second file has fails, unless --added-ok, which still fails a changed
value; --core-paths reads a source moved into a layer folder of core/ as the same path, and
nothing else. Files made here with h5py, with a dimension scale as impactid attaches them.

Usage: compare_results_test.py SCRIPT
"""
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np


def write(path, eps_p, extra=False, source="core/indicators.hpp"):
    with h5py.File(path, "w") as f:
        f.attrs["kind"] = "grid"
        alpha = f.create_dataset("alpha", data=np.array([-0.3, -0.1]))
        alpha.make_scale("alpha")
        d = f.create_dataset("eps_p", data=np.array(eps_p))
        d.attrs["definition"] = f"relative error of the pressure ({source})"
        d.dims[0].attach_scale(alpha)
        if extra:
            f.attrs["verdict_thresholds"] = "eps_p <= 0.03"
            v = f.create_dataset("verdict", data=np.array([0, 2], dtype=np.int8))
            v.dims[0].attach_scale(alpha)


def run(script, *args):
    return subprocess.run([sys.executable, script, *args], capture_output=True, text=True)


def main():
    script = sys.argv[1]
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        old, same, added, changed = (os.path.join(tmp, n) for n in ("a.h5", "b.h5", "c.h5", "d.h5"))
        write(old, [0.01, 0.2])
        write(same, [0.01, 0.2])
        write(added, [0.01, 0.2], extra=True)
        write(changed, [0.01, 0.2000001], extra=True)
        moved, renamed = (os.path.join(tmp, n) for n in ("e.h5", "f.h5"))
        write(moved, [0.01, 0.2], source="core/reference/indicators.hpp")
        write(renamed, [0.01, 0.2], source="core/reference/indicator.hpp")
        cases = [((old, same), 0), ((old, added), 1), (("--added-ok", old, added), 0),
                 (("--added-ok", old, changed), 1), ((old, moved), 1),
                 (("--core-paths", old, moved), 0), (("--core-paths", old, renamed), 1)]
        for args, expected in cases:
            result = run(script, *args)
            if result.returncode != expected:
                failures.append(f"{args}: exit {result.returncode}, expected {expected}:\n"
                                f"{result.stdout}{result.stderr}")
        listed = run(script, "--added-ok", old, added).stdout
        if "dataset verdict" not in listed or "root attribute verdict_thresholds" not in listed:
            failures.append(f"--added-ok does not list what was added:\n{listed}")
    for f in failures:
        print(f)
    print(f"compare_results_test: {len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
