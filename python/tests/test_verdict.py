"""A run's verdict (metrics/verdict.hpp) in Python: the command's, compare's order, the results."""

import json
import subprocess

import numpy as np

import impactid

# The order of severity, as `impactid compare` sorts by it and results files code it.
VERDICTS = ["accurate", "oscillating", "inaccurate", "unverified", "unstable", "failed"]


def test_simulate_has_the_commands_verdict(executable):
    for method in ("bathe", "hht", "newmark"):
        done = subprocess.run([executable, "simulate", "--method", method, "--elements", "60",
                               "--json"], capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        expected = json.loads(done.stdout)
        run = impactid.simulate(method=method, elements=60)
        assert run.verdict == expected["verdict"], method
        assert run.verdict_reason == expected["verdict_reason"], method
        assert run.reference_trusted is True
    # The Bathe at its defaults: ok, but far from accurate.
    bathe = impactid.simulate(method="bathe")
    assert bathe.status == "ok" and bathe.verdict == "inaccurate"
    assert impactid.simulate(method="bathe", verdict_eps_p=10, verdict_eps_v=10,
                             verdict_nop_p=1e4, verdict_nop_v=1e4).verdict == "accurate"


def test_compare_is_in_order_of_verdict_then_eps_p():
    runs = list(impactid.compare(elements=40, courant=1).values())
    keys = [(VERDICTS.index(r.verdict), r.eps_p if r.eps_p is not None else np.inf) for r in runs]
    assert keys == sorted(keys)
    assert len({r.verdict for r in runs}) > 1  # the test sorts something


def test_a_results_file_holds_each_points_verdict(tmp_path):
    plan = {"name": "verdicts", "scene": {"elements": 40}, "method": {"name": "newmark"},
            "study": {"kind": "grid", "axes": {"delta": {"values": [0.0, 0.3, 1.0]}}}}
    ds = impactid.run_plan(plan, output=str(tmp_path / "v.h5"))
    assert ds.attrs["verdict_thresholds"] == "eps_p <= 0.03, nop_p <= 15, eps_v <= 0.06, nop_v <= 15"
    for k, delta in enumerate(ds["delta"].values):
        run = impactid.simulate(method={"name": "newmark", "delta": float(delta)}, elements=40)
        assert VERDICTS[int(ds["verdict"].values[k])] == run.verdict, delta
