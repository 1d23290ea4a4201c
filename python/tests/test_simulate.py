"""simulate, compare and spectral against their commands: the same numbers, bit for bit."""

import json
import subprocess

import h5py
import numpy as np
import pytest

import impactid


def cli(executable, *args):
    done = subprocess.run([executable, *map(str, args)], capture_output=True, text=True)
    return done


def history_file(executable, tmp_path, *args):
    path = tmp_path / "history.h5"
    done = cli(executable, "simulate", *args, "--history", path)
    assert done.returncode == 0, done.stderr
    with h5py.File(path, "r") as f:
        return {name: f[name][...] for name in f}


def assert_same_columns(run, columns):
    assert list(run.history) == list(columns) or set(run.history) == set(columns)
    for name, values in columns.items():
        np.testing.assert_array_equal(run.history[name], values, err_msg=name)
        # bit for bit, NaN included (assert_array_equal treats NaN as equal to NaN)
        assert run.history[name].tobytes() == values.tobytes(), name


def test_rod_history_equals_the_commands_history_file(executable, tmp_path):
    columns = history_file(executable, tmp_path, "--method", "hht", "--alpha", "-0.3",
                           "--delta", "0.45", "--elements", "60")
    run = impactid.simulate(method="hht", alpha=-0.3, delta=0.45, elements=60)
    assert_same_columns(run, columns)
    assert run.t.shape == run.pressure.shape == run.exact_pressure.shape
    assert run.t[0] > 0 and np.all(np.diff(run.t) > 0)
    # The exact reference is not the numerical solution: a test of the right columns.
    assert not np.array_equal(run.pressure, run.exact_pressure)


def test_indicators_equal_the_commands_json(executable):
    done = cli(executable, "simulate", "--method", "newmark", "--delta", "0.3", "--elements", "80",
               "--courant", "0.7", "--json")
    assert done.returncode == 0, done.stderr
    expected = json.loads(done.stdout)
    run = impactid.simulate(method={"name": "newmark", "delta": 0.3}, elements=80, courant=0.7)
    assert run.status == expected["status"] == "ok"
    for name in ("eps_p", "eps_v", "nop_p", "nop_v", "p_max", "p_max_ratio", "contact_episodes",
                 "energy_ratio"):
        assert getattr(run, name) == expected[name], name
    assert run.parameters["beta"] == expected["parameters"]["beta"]
    assert run.dt == expected["dt"] and run.steps == expected["steps"]
    # The contact episodes likewise; the energy after one only with the histories, which the
    # module records and the command (without --history) does not.
    assert len(run.episodes) == len(expected["episodes"]) == 1
    for mine, theirs in zip(run.episodes, expected["episodes"]):
        for key in ("start", "reference_start", "end", "reference_end", "impulse",
                    "reference_impulse", "peaks", "contact_runs"):
            assert mine[key] == theirs[key], key
        assert theirs["energy_ratio"] is None and 0.0 < mine["energy_ratio"] < 1.0


def test_scene_of_bodies_from_a_dict_equals_the_scene_file(executable, tmp_path):
    scene = {
        "body": [
            {"name": "striker", "velocity": 1000.0, "length": 10.0, "elements": 40},
            {"name": "bar", "gap": 0.01, "length": 30.0, "elements": 120},
        ],
    }
    path = tmp_path / "scene.toml"
    path.write_text(impactid.plan_text({"scene": scene}))
    columns = history_file(executable, tmp_path, "--scene", path, "--method", "hht",
                           "--set", "body.striker.velocity=1500")
    run = impactid.simulate(scene=scene, method="hht", set={"body.striker.velocity": 1500})
    assert_same_columns(run, columns)
    assert run.primary_contact == "striker-bar"
    assert [c["name"] for c in run.contacts] == ["striker-bar"]
    # The same scene from its file.
    again = impactid.simulate(scene=path, method="hht", set={"body.striker.velocity": 1500})
    assert again.eps_p == run.eps_p


def test_a_users_model_equals_the_commands_history_file(executable, source_dir, tmp_path):
    scene = source_dir / "examples" / "rod" / "scene.toml"
    columns = history_file(executable, tmp_path, "--scene", scene, "--method", "newmark",
                           "--delta", "0.3")
    run = impactid.simulate(scene=scene, method={"name": "newmark", "delta": 0.3})
    assert_same_columns(run, columns)
    assert run.primary_contact == "wall" and run.reference.startswith("supplied")
    assert "reference_pressure.wall" in run.history


def test_an_unstable_run_has_a_status_and_no_indicators():
    run = impactid.simulate(method="cdm", courant=1.5, elements=40)
    assert run.status == "unstable" and not run.ok
    assert run.eps_p is None and run.indicators == {}
    assert run.message


def test_to_dataset_keeps_units():
    ds = impactid.simulate(elements=40).to_dataset()
    assert ds["pressure"].attrs["units"] == "MPa"
    assert ds["pressure"].dims == ("t",)


def test_compare_runs_every_method_as_simulate_does():
    runs = impactid.compare(elements=40)
    assert sorted(runs) == sorted(impactid.methods())
    for name in ("hht", "newmark", "cdm"):
        assert runs[name].eps_p == impactid.simulate(method=name, elements=40).eps_p


def test_spectral_equals_the_commands_json(executable):
    done = cli(executable, "spectral", "--method", "hht", "--alpha", "-0.2", "--omega-dt",
               "0.1,1,10", "--courant", "2", "--json")
    assert done.returncode == 0, done.stderr
    expected = json.loads(done.stdout)
    got = impactid.spectral("hht", alpha=-0.2, omega_dt=[0.1, 1, 10], courant=2)
    assert got["rho_inf"] == expected["rho_inf"]
    assert got["stability"] == expected["stability"]
    assert got["delta_min_period_error"] == expected["delta_min_period_error"]
    for k, row in enumerate(expected["omega_dt"]):
        for key in ("spectral_radius", "damping_ratio", "period_error"):
            assert got[key][k] == row[key], key


def test_match_damping_equals_the_commands_json(executable):
    done = cli(executable, "spectral", "--match-damping", "0.05", "--omega-dt", "1", "--json")
    assert done.returncode == 0, done.stderr
    expected = json.loads(done.stdout)
    got = impactid.spectral(match_damping=0.05, omega_dt=1)
    for g, e in zip(got["matches"], expected["matches"]):
        assert (g["family"], g["value"], g["parameters"]) == (e["family"], e["value"],
                                                              e["parameters"])
    assert got["fixed"] == {f["method"]: f["damping_ratio"] for f in expected["fixed"]}
