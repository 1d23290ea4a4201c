"""The functions' signatures come from the settings table and the method registry: every
parameter is a keyword that help() shows and an IDE completes; the method comes first; a keyword
that is no parameter is refused with the nearest names."""

import inspect
import json
import pydoc
import re
import subprocess

import pytest

import impactid

KEYWORD_ONLY = inspect.Parameter.KEYWORD_ONLY


def registry(executable):
    """Every method and its parameters, as the program lists them (`impactid methods --json`)."""
    done = subprocess.run([executable, "methods", "--json"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def options(executable, command):
    """The parameters among a command's options, as snake_case names (`impactid CMD --help`)."""
    done = subprocess.run([executable, command, "--help"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return {name.replace("-", "_") for name in re.findall(r"^\s+--([a-z0-9-]+)", done.stdout,
                                                            re.MULTILINE)}


def test_every_registry_parameter_is_a_keyword_of_simulate_and_spectral(executable):
    methods = registry(executable)
    assert len(methods) == len(impactid.methods()) > 10
    for function in (impactid.simulate, impactid.spectral):
        parameters = inspect.signature(function).parameters
        for method in methods:
            for p in method["parameters"]:
                assert p["name"] in parameters, (function.__name__, method["name"], p["name"])
                assert parameters[p["name"]].kind == KEYWORD_ONLY
                assert parameters[p["name"]].default is None
        assert list(parameters)[0] == "method"
        assert "params" not in parameters  # nothing hidden behind **params


def test_every_option_of_the_commands_is_a_keyword(executable):
    # --history and its --force write a file; Python returns the histories instead.
    not_parameters = {"help", "json", "history", "force", "scene", "set", "method"}
    simulate = inspect.signature(impactid.simulate).parameters
    for name in options(executable, "simulate") - not_parameters:
        assert name in simulate and simulate[name].kind == KEYWORD_ONLY, name
    compare = inspect.signature(impactid.compare).parameters
    for name in options(executable, "compare") - not_parameters:
        assert name in compare and compare[name].kind == KEYWORD_ONLY, name
    # compare runs every method at its defaults: no method parameter.
    assert "alpha" not in compare and "method" not in compare


def test_help_shows_the_keywords_with_their_descriptions():
    text = pydoc.render_doc(impactid.simulate, renderer=pydoc.plaintext)
    assert "alpha: Optional[float] = None" in text, text[:2000]
    assert "elements: Optional[int] = None" in text
    assert "contact: Optional[Literal[" in text
    for name, info in ((p["name"], p) for p in impactid.parameters() if p["name"] != "method"):
        assert f"    {name}" in text and info["description"] in text, name
    assert "**params" not in str(inspect.signature(impactid.simulate))


def test_the_method_comes_first():
    run = impactid.simulate("newmark", delta=0.3, elements=40)
    assert run.method == "newmark"
    assert run.eps_p == impactid.simulate(method="newmark", delta=0.3, elements=40).eps_p
    assert impactid.spectral("hht", alpha=-0.2, omega_dt=1)["parameters"]["alpha"] == -0.2


def test_a_scene_file_given_as_the_method_is_refused_with_the_fix(source_dir):
    scene = str(source_dir / "plans" / "hopkinson.toml")
    with pytest.raises(ValueError, match=r"scene=.*hopkinson\.toml"):
        impactid.simulate(scene)
    with pytest.raises(TypeError, match="scene="):
        impactid.simulate(source_dir / "plans" / "hopkinson.toml")
    # ... and a method's name given as compare's scene.
    with pytest.raises(ValueError, match=r"scene = 'hht': is a method's name"):
        impactid.compare("hht")


def test_none_leaves_a_parameter_unset():
    assert (impactid.simulate("hht", alpha=None, elements=40).eps_p
            == impactid.simulate("hht", elements=40).eps_p)


@pytest.mark.parametrize("function, keyword, suggestion", [
    (impactid.simulate, "alpah", "'alpha'"),
    (impactid.simulate, "element", "'elements'"),
    (impactid.compare, "courrant", "'courant'"),
    (impactid.spectral, "rho_infty", "'rho_inf'"),
])
def test_an_unknown_keyword_is_refused_with_a_suggestion(function, keyword, suggestion):
    with pytest.raises(TypeError) as raised:
        function(**{keyword: 1.0})
    assert str(raised.value) == (f"{function.__name__}() got an unexpected keyword argument "
                                 f"{keyword!r}; did you mean {suggestion}?")


def test_an_unknown_keyword_without_a_near_name():
    with pytest.raises(TypeError, match=r"unexpected keyword argument 'zzzz'$"):
        impactid.simulate(zzzz=1)


def test_contact_laws_are_the_programs_and_every_law_parameter_a_keyword(executable):
    done = subprocess.run([executable, "contact-laws", "--json"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    laws = json.loads(done.stdout)
    assert impactid.contact_laws() == [law["name"] for law in laws]
    info = {p["name"]: p for p in impactid.parameters()}
    assert info["contact"]["choices"].split("|") == impactid.contact_laws()
    simulate = inspect.signature(impactid.simulate).parameters
    for law in laws:
        for p in law["parameters"]:
            assert p["name"] in simulate, (law["name"], p["name"])
            assert info[p["name"]]["kind"] == p["kind"]
            assert info[p["name"]]["unit"] == p["unit"]
