"""run_plan writes the file `impactid run` writes; Ctrl-C stops it as it stops the command, and
the partial file resumes to the uninterrupted one."""

import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import impactid

# Measured values and the time of the run: the only things two runs of a plan may differ in.
TIMING_VARIABLES = {"wall_time_s"}
TIMING_ATTRIBUTES = {"date", "run_wall_time_s", "wall_time_s", "threads"}

GRID = {
    "name": "python-grid",
    "scene": {"elements": 50},
    "method": {"name": "hht"},
    "study": {
        "kind": "grid",
        "axes": {
            "alpha": {"from": -0.5, "to": 0.0, "partitions": 4},
            "delta": {"from": 0.0, "to": 1.0, "partitions": 5},
        },
    },
}


def assert_same_results(a, b):
    assert list(a.dims) == list(b.dims)
    assert set(a.variables) == set(b.variables)
    for name in a.variables:
        if name in TIMING_VARIABLES:
            continue
        x, y = a[name].values, b[name].values
        assert x.dtype == y.dtype and x.shape == y.shape, name
        assert x.tobytes() == y.tobytes(), name
        assert a[name].attrs.keys() == b[name].attrs.keys(), name
    for key in set(a.attrs) | set(b.attrs):
        if key in TIMING_ATTRIBUTES:
            continue
        assert np.array_equal(a.attrs[key], b.attrs[key]), key


def test_a_plan_dict_writes_the_file_the_command_writes(executable, tmp_path):
    plan_file = tmp_path / "grid.toml"
    plan_file.write_text(impactid.plan_text(GRID))
    done = subprocess.run([executable, "run", str(plan_file), "--threads", "2", "--output",
                           str(tmp_path / "cli.h5")], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    ds = impactid.run_plan(GRID, threads=1, output=tmp_path / "python.h5")
    assert_same_results(ds, impactid.open_results(tmp_path / "cli.h5"))
    assert ds["eps_p"].dims == ("alpha", "delta")
    assert ds.attrs["plan"] == plan_file.read_text()
    assert ds.attrs["plan_name"] == "python-grid"
    assert int((ds["status"] == 0).sum()) > 0


def test_a_plan_file_and_its_tomllib_dict_agree(source_dir, tmp_path):
    import tomllib

    path = source_dir / "plans" / "list-methods.toml"
    from_file = impactid.run_plan(path, output=tmp_path / "file.h5")
    with open(path, "rb") as f:
        from_dict = impactid.run_plan(tomllib.load(f), output=tmp_path / "dict.h5")
    for name in from_file.data_vars:
        if name not in TIMING_VARIABLES:
            np.testing.assert_array_equal(from_file[name], from_dict[name], err_msg=name)


SLOW_GRID = dict(GRID, name="python-interrupt", scene={"elements": 300},
                 output={"checkpoint_seconds": 0.05})
SLOW_GRID["study"] = {"kind": "grid", "axes": {
    "alpha": {"from": -0.5, "to": 0.0, "partitions": 30},
    "delta": {"from": 0.0, "to": 1.0, "partitions": 30},
}}

# Runs the plan; on KeyboardInterrupt checks that Python's own SIGINT handler is back (a second
# SIGINT is an ordinary KeyboardInterrupt, not the default action nor the run's handler) and exits
# with 130.
CHILD = """
import os, signal, sys, time, impactid
try:
    impactid.run_plan(eval(sys.argv[1]), threads=1, output=sys.argv[2])
except KeyboardInterrupt as e:
    print("run_plan raised KeyboardInterrupt:", e, file=sys.stderr)
    try:
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(10)
        sys.exit(3)
    except KeyboardInterrupt:
        sys.exit(130)
"""


def test_sigint_stops_a_sweep_and_resume_ends_with_the_uninterrupted_file(tmp_path, child_env):
    reference = impactid.run_plan(SLOW_GRID, threads=2, output=tmp_path / "reference.h5")
    total = reference["status"].size
    out = tmp_path / "interrupted.h5"
    child = subprocess.Popen([sys.executable, "-c", CHILD, repr(SLOW_GRID), str(out)],
                             stderr=subprocess.PIPE, text=True, env=child_env)
    # The first checkpoint is written once the sweep runs, inside run_plan: then Ctrl-C.
    start = time.monotonic()
    while not out.exists() and child.poll() is None and time.monotonic() - start < 60:
        time.sleep(0.005)
    child.send_signal(signal.SIGINT)
    _, stderr = child.communicate(timeout=60)
    partial = impactid.open_results(out)
    done = int((partial["status"] >= 0).sum())
    if done == total:
        pytest.skip("the sweep finished before the signal arrived")
    assert child.returncode == 130, stderr
    assert "run_plan raised KeyboardInterrupt" in stderr and "resume=True" in stderr, stderr
    assert done < total
    resumed = impactid.run_plan(SLOW_GRID, threads=2, output=out, resume=True)
    assert_same_results(resumed, reference)
