#!/usr/bin/python3
"""A results file that cannot be written (issue 38, items 1 and 2): a full disk or a file size
limit ends `impactid run`, `impactid simulate --history` (HDF5 or CSV) and `impactid export` with
exit status 1 and a message
naming the file and the system's reason, no temporary file left behind, and the file that was
there before intact. Before, HDF5 crashed in H5Fclose (SIGSEGV) and every computed point was
lost; a failed checkpoint inside the parallel sweep aborted the program (SIGABRT).

Two ways to make writes fail:
  - a file size limit (RLIMIT_FSIZE, `ulimit -f`), which needs no privilege: writes past it fail
    with EFBIG ("File too large"; impactid ignores SIGXFSZ);
  - where the test may mount (root with CAP_SYS_ADMIN), a small tmpfs: "No space left on
    device", and a checkpoint that fits once but not twice (the previous one intact).

Usage: disk_full_test.py IMPACTID SOURCE_DIR
"""
import os
import resource
import shutil
import subprocess
import sys
import tempfile

LIMIT = 16 * 1024  # bytes: plans/demo.toml's results file takes about 26 KB


def limited(limit):
    def apply():
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, resource.RLIM_INFINITY))
    return apply


def run(args, limit=None):
    return subprocess.run(args, capture_output=True, text=True,
                          preexec_fn=limited(limit) if limit else None)


def expect_failed_write(result, target, reasons, failures, what):
    if result.returncode != 1:
        failures.append(f"{what}: exit {result.returncode}, expected 1:\n{result.stderr[-2000:]}")
        return
    if f"{target}: cannot write" not in result.stderr or not any(r in result.stderr for r in reasons):
        failures.append(f"{what}: the message does not name {target} and the reason:\n"
                        f"{result.stderr[-2000:]}")
    if os.path.exists(target + ".tmp"):
        failures.append(f"{what}: {target}.tmp left behind")


def try_mount(folder, size):
    if os.geteuid() != 0:
        return False
    return subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", folder],
                          capture_output=True).returncode == 0


def main():
    impactid, source = sys.argv[1], sys.argv[2]
    demo = os.path.join(source, "plans", "demo.toml")
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        # 1. The final save of a run, past a file size limit: the earlier file stays.
        target = os.path.join(tmp, "demo.h5")
        first = run([impactid, "run", demo, "--output", target])
        if first.returncode != 0:
            failures.append(f"the unlimited run failed:\n{first.stderr[-2000:]}")
        else:
            before = open(target, "rb").read()
            again = run([impactid, "run", demo, "--output", target], limit=LIMIT)
            expect_failed_write(again, target, ["File too large"], failures, "run, size limit")
            if open(target, "rb").read() != before:
                failures.append("run, size limit: the earlier results file changed")

        # 2. Time histories past the limit.
        history = os.path.join(tmp, "history.h5")
        result = run([impactid, "simulate", "--history", history], limit=LIMIT)
        expect_failed_write(result, history, ["File too large"], failures, "simulate --history")
        history_csv = os.path.join(tmp, "history.csv")
        result = run([impactid, "simulate", "--history", history_csv], limit=LIMIT)
        expect_failed_write(result, history_csv, ["File too large"], failures,
                            "simulate --history as CSV")

        # 3. A CSV export past the limit (before: "points.csv: write failed", no reason).
        big = os.path.join(tmp, "big.h5")
        plan = os.path.join(source, "plans", "hht-delta-alpha.toml")
        if run([impactid, "run", plan, "--output", big]).returncode == 0:
            points = os.path.join(tmp, "csv", "points.csv")
            result = run([impactid, "export", big, "--csv", os.path.join(tmp, "csv")], limit=LIMIT)
            expect_failed_write(result, points, ["File too large"], failures, "export")
        else:
            failures.append(f"the run of {plan} failed")

        # 4. A full disk, and a checkpoint that fits once but not twice.
        disk = os.path.join(tmp, "disk")
        os.mkdir(disk)
        if try_mount(disk, "200k"):
            try:
                plan = os.path.join(tmp, "checkpointed.toml")
                text = open(os.path.join(source, "plans", "hht-delta-alpha.toml")).read()
                with open(plan, "w") as f:  # a checkpoint after every window of points
                    f.write(text.replace("[output]", "[output]\ncheckpoint_seconds = 1e-9", 1)
                            if "[output]" in text else text + "\n[output]\ncheckpoint_seconds = 1e-9\n")
                target = os.path.join(disk, "full.h5")
                result = run([impactid, "run", plan, "--output", target, "--threads", "2"])
                expect_failed_write(result, target, ["No space left on device"], failures,
                                    "run, full disk")
                if not os.path.exists(target):
                    failures.append("run, full disk: the checkpoint written before is gone")
                else:  # --resume continues from it, elsewhere
                    rest = os.path.join(tmp, "rest.h5")
                    shutil.copyfile(target, rest)
                    resumed = run([impactid, "run", plan, "--output", rest, "--resume"])
                    output = resumed.stdout + resumed.stderr
                    if resumed.returncode != 0 or " 0 reused" in output or "reused" not in output:
                        failures.append(f"run, full disk: the checkpoint does not resume:\n"
                                        f"{output[-2000:]}")
            finally:
                subprocess.run(["umount", disk])
            # 5. A read-only file system (before: "H5Fcreate failed", no reason).
            readonly = os.path.join(tmp, "readonly")
            os.mkdir(readonly)
            if try_mount(readonly, "64k,ro"):
                try:
                    target = os.path.join(readonly, "demo.h5")
                    result = run([impactid, "run", demo, "--output", target])
                    expect_failed_write(result, target, ["Read-only file system"], failures,
                                        "run, read-only file system")
                finally:
                    subprocess.run(["umount", readonly])
        else:
            print("disk_full_test: cannot mount a tmpfs here (not root, or no CAP_SYS_ADMIN): "
                  "the full-disk case is not checked; the size-limit cases are")
    for f in failures:
        print(f)
    print(f"disk_full_test: {len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
