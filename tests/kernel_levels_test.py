#!/usr/bin/python3
"""Every kernel level the processor supports writes the same results files, bit for bit.

Runs each plan given with IMPACTID_KERNELS forced to each level (core/common/kernel_level.hpp) that
this processor and build have (`impactid --version` refuses the others), and compares every
level's file with the baseline level's (every run through the scalar stepper) by
scripts/compare-results. The plans are chosen to reach every batched kernel: the rod's
implicit, composite, Wilson-θ, Houbolt, explicit and KR-α kernels, and the chain of bodies.

Usage: kernel_levels_test.py --impactid EXE --compare SCRIPT PLAN...
"""
import argparse
import os
import subprocess
import sys
import tempfile

LEVELS = ("baseline", "x86-64-v3", "x86-64-v4")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--impactid", required=True)
    parser.add_argument("--compare", required=True)
    parser.add_argument("plans", nargs="+")
    args = parser.parse_args()

    available = []
    for level in LEVELS:
        env = dict(os.environ, IMPACTID_KERNELS=level)
        probe = subprocess.run([args.impactid, "--version"], env=env, capture_output=True,
                               text=True)
        if probe.returncode == 0:
            available.append(level)
        else:
            print(f"{level}: not run here ({probe.stderr.strip()})")
    if len(available) < 2:
        print("SKIPPED: one kernel level only: nothing to compare")
        return 77

    failures = 0
    with tempfile.TemporaryDirectory() as work:
        for plan in args.plans:
            name = os.path.splitext(os.path.basename(plan))[0]
            files = {}
            for level in available:
                out = os.path.join(work, f"{name}.{level}.h5")
                env = dict(os.environ, IMPACTID_KERNELS=level)
                run = subprocess.run([args.impactid, "run", plan, "--output", out], env=env,
                                     capture_output=True, text=True)
                if run.returncode != 0:
                    print(f"{name} at {level}: impactid run failed ({run.returncode}):\n"
                          f"{run.stderr}")
                    failures += 1
                    continue
                files[level] = out
            if "baseline" not in files:
                continue
            for level, path in files.items():
                if level == "baseline":
                    continue
                same = subprocess.run([sys.executable, args.compare, files["baseline"], path],
                                      capture_output=True, text=True)
                verdict = "identical" if same.returncode == 0 else "DIFFERENT"
                print(f"{name}: {level} against baseline: {verdict}")
                if same.returncode != 0:
                    print(same.stdout + same.stderr)
                    failures += 1
    print(f"levels {', '.join(available)}; {failures} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
