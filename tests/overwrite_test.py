#!/usr/bin/python3
"""`impactid simulate --history FILE` replaces another run's histories, and nothing else without
--force; `impactid run --shard K/N --output FILE` does not replace another shard's file without
--force (issue 38, item 6: each replaced the earlier file without a word).

Usage: overwrite_test.py IMPACTID SOURCE_DIR
"""
import os
import subprocess
import sys
import tempfile


def run(*args):
    return subprocess.run(list(args), capture_output=True, text=True)


def main():
    impactid, source = sys.argv[1], sys.argv[2]
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        results = os.path.join(tmp, "demo.h5")
        made = run(impactid, "run", os.path.join(source, "plans", "demo.toml"), "--output", results)
        if made.returncode != 0:
            failures.append(f"run failed:\n{made.stderr[-2000:]}")
        notes = os.path.join(tmp, "notes.csv")
        with open(notes, "w") as f:
            f.write("my own notes\n")
        for victim in (results, notes):
            before = open(victim, "rb").read()
            refused = run(impactid, "simulate", "--history", victim)
            if refused.returncode != 1 or "exists and is not a time-history file" not in refused.stderr:
                failures.append(f"{victim}: not refused (exit {refused.returncode}):\n"
                                f"{refused.stderr[-2000:]}")
            if open(victim, "rb").read() != before:
                failures.append(f"{victim}: changed although refused")
            forced = run(impactid, "simulate", "--history", victim, "--force")
            if forced.returncode != 0 or open(victim, "rb").read() == before:
                failures.append(f"{victim}: --force did not replace it (exit {forced.returncode})")
        for history in (os.path.join(tmp, "h.h5"), os.path.join(tmp, "h.csv")):
            for attempt in (1, 2):  # the second replaces the first's histories without asking
                again = run(impactid, "simulate", "--history", history)
                if again.returncode != 0:
                    failures.append(f"{history} (run {attempt}): exit {again.returncode}:\n"
                                    f"{again.stderr[-2000:]}")
        # Three shards given one --output: the second must not replace the first's points.
        plan = os.path.join(source, "plans", "hht-delta-alpha.toml")
        shared = os.path.join(tmp, "med.h5")
        first = run(impactid, "run", plan, "--shard", "0/3", "--output", shared)
        if first.returncode != 0:
            failures.append(f"shard 0/3: exit {first.returncode}:\n{first.stderr[-2000:]}")
        else:
            before = open(shared, "rb").read()
            second = run(impactid, "run", plan, "--shard", "1/3", "--output", shared)
            if second.returncode != 1 or "holds shard 0/3, not shard 1/3" not in second.stderr:
                failures.append(f"shard 1/3 over 0/3's file: not refused (exit "
                                f"{second.returncode}):\n{second.stderr[-2000:]}")
            if open(shared, "rb").read() != before:
                failures.append("shard 1/3 changed shard 0/3's file although refused")
            same = run(impactid, "run", plan, "--shard", "0/3", "--output", shared)
            if same.returncode != 0:
                failures.append(f"shard 0/3 again over its own file: exit {same.returncode}")
            forced = run(impactid, "run", plan, "--shard", "1/3", "--output", shared, "--force")
            if forced.returncode != 0:
                failures.append(f"shard 1/3 --force: exit {forced.returncode}")
    for f in failures:
        print(f)
    print(f"overwrite_test: {len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
