"""Bad arguments raise, with the command line's message; nothing crashes."""

import subprocess

import pytest

import impactid


def cli_error(executable, *args):
    done = subprocess.run([executable, *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 2, done.stderr
    return done.stderr.strip()


@pytest.mark.parametrize("name, value", [
    ("elements", -5),
    ("elements", 10.5),
    ("youngs_modulus", 0),
    ("alpha", -0.7),
    ("courant", float("nan")),
    ("mass", "heavy"),
])
def test_a_bad_parameter_raises_the_commands_message(executable, name, value):
    with pytest.raises(impactid.ParameterError) as raised:
        impactid.simulate(method="hht", **{name: value})
    e = raised.value
    assert isinstance(e, ValueError)
    assert e.parameter == name
    assert str(e) == f"{name} = {e.value}: {e.constraint}"
    option = "--" + name.replace("_", "-")
    assert cli_error(executable, "simulate", "--method", "hht", option, value) == (
        f"impactid simulate: {option} = {e.value}: {e.constraint}")


def test_a_parameter_the_method_does_not_take(executable):
    with pytest.raises(impactid.ParameterError) as raised:
        impactid.simulate(method="cdm", alpha=-0.3)
    assert cli_error(executable, "simulate", "--method", "cdm", "--alpha", "-0.3") == (
        "impactid simulate: --alpha = -0.3: " + raised.value.constraint)
    assert "cdm" in str(raised.value)


def test_an_unknown_method(executable):
    with pytest.raises(impactid.ParameterError) as raised:
        impactid.simulate(method={"name": "euler"})
    assert cli_error(executable, "simulate", "--method", "euler") == (
        "impactid simulate: --method = euler: " + raised.value.constraint)


def test_a_bad_scene_key_names_it():
    with pytest.raises(ValueError, match=r"scene\.length = -1\.0: "):
        impactid.simulate(scene={"length": -1.0})
    with pytest.raises(impactid.ParameterError, match=r"^body\.nobody\.velocity = "):
        impactid.simulate(scene={"body": [{"name": "a", "velocity": 1000.0}, {"name": "b"}]},
                          set={"body.nobody.velocity": 1.0})


def test_wrong_types_raise_type_error():
    with pytest.raises(TypeError, match="elements"):
        impactid.simulate(elements=True)
    with pytest.raises(TypeError, match="scene"):
        impactid.simulate(scene=42)
    with pytest.raises(TypeError, match="method parameter 'alpha'"):
        impactid.compare(alpha=-0.3)


def test_a_bad_plan_file_raises_the_commands_message(executable, tmp_path):
    plan = tmp_path / "bad.toml"
    plan.write_text('[method]\nname = "hht"\n[study]\nkind = "grid"\n'
                    '[study.axes]\nalpha = { from = -0.9, to = 0.0, partitions = 2 }\n')
    with pytest.raises(ValueError) as raised:
        impactid.run_plan(plan, output=tmp_path / "out.h5")
    assert cli_error(executable, "run", plan, "--output", tmp_path / "out.h5") == str(raised.value)
    assert str(raised.value).startswith(f"{plan}:6:")
    assert not (tmp_path / "out.h5").exists()


def test_a_bad_plan_dict_names_the_key():
    plan = {"study": {"kind": "grid", "axes": {"delta": {"from": 0, "to": 1, "partitions": 0}}}}
    with pytest.raises(ValueError, match=r"study\.axes\.delta\.partitions = 0: "):
        impactid.run_plan(plan, output="/nonexistent/never-written.h5")


def test_resume_of_another_plans_file_is_refused(tmp_path):
    out = tmp_path / "r.h5"
    plan = {"scene": {"elements": 20}, "method": {"name": "newmark"},
            "study": {"kind": "grid", "axes": {"delta": {"values": [0.3, 0.5]}}}}
    impactid.run_plan(plan, output=out, threads=1)
    plan["study"]["axes"]["delta"]["values"] = [0.3, 0.6]
    before = out.read_bytes()
    with pytest.raises(ValueError, match="different plan"):
        impactid.run_plan(plan, output=out, threads=1, resume=True)
    assert out.read_bytes() == before


def test_spectral_arguments():
    with pytest.raises(ValueError, match=r"^omega_dt = -1: must be positive and finite$"):
        impactid.spectral("hht", omega_dt=[-1])
    with pytest.raises(ValueError, match="cannot be given with courant or mass"):
        impactid.spectral("hht", omega_max=10, courant=1)
    with pytest.raises(ValueError, match="needs exactly one omega_dt"):
        impactid.spectral(match_damping=0.1, omega_dt=[1, 2])


def test_a_modified_mass_is_refused_by_a_method_that_does_not_step_it(executable):
    """mass = redistributed|singular leave the rod's contact node massless (docs/remedies.md):
    the methods that step it run, the others are refused by name, as on the command line."""
    run = impactid.simulate("hht", mass="redistributed")
    assert run.status == "ok"
    assert run.pressure.min() >= 0.0
    with pytest.raises(impactid.ParameterError) as raised:
        impactid.simulate(method="wilson-theta", mass="singular")
    e = raised.value
    assert e.parameter == "mass" and e.value == "singular"
    assert e.constraint.startswith("method wilson-theta does not step a mass matrix with massless")
    assert cli_error(executable, "simulate", "--method", "wilson-theta", "--mass", "singular") == (
        f"impactid simulate: --mass = singular: {e.constraint}")
