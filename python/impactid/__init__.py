"""impactid from Python: the command line's commands as functions, with NumPy and xarray results.

Every function runs the same C++ code as its command (`impactid simulate`, `compare`, `spectral`,
`run`) with the same parameter names (snake_case, as in plan files) and the same defaults, so a
call and the command with the same parameters give the same numbers, bit for bit. See
python/README.md.

    import impactid
    run = impactid.simulate("hht", alpha=-0.3, delta=0.45)
    run.eps_p, run.status              # indicators and status
    run.t, run.pressure, run.exact_pressure   # time histories (NumPy arrays)
    ds = impactid.run_plan("plans/hht-delta-alpha.toml", output="/tmp/h.h5")   # xarray.Dataset

Scenes and methods are names, files or plain dicts with the plan files' keys: a [scene] table
(`{"length": 20.0, "elements": 100}`, or `{"body": [...], "wall": {...}}` for a scene of
bodies), a [method] table (`{"name": "hht", "alpha": -0.3}`); a plan is a path or the dict that
`tomllib.load` gives for a plan file.

Errors are exceptions: a bad parameter raises ParameterError (a ValueError) naming the parameter
and its value with the command line's words; a bad plan or scene raises ValueError with the plan
reader's message (the command line's text, file:line:column: key = value: what is wrong).
"""

from __future__ import annotations

import inspect
import math
import numbers
import os
import tempfile
import threading
import typing

import tomli_w

from . import _impactid
from ._results import open_results
from ._plot import plot

__all__ = [
    "Run",
    "ParameterError",
    "simulate",
    "compare",
    "spectral",
    "run_plan",
    "open_results",
    "plot",
    "plan_text",
    "parameters",
    "kernels",
    "methods",
    "contact_laws",
]


class ParameterError(ValueError):
    """A parameter value that the settings refuse: `parameter = value: constraint`.

    The command line reports the same error as `impactid simulate: --parameter = value:
    constraint` (a dotted key of a scene of bodies keeps its dots there too).
    """

    def __init__(self, parameter: str, value: str, constraint: str):
        super().__init__(f"{parameter} = {value}: {constraint}")
        self.parameter = parameter
        self.value = value
        self.constraint = constraint


_impactid.set_parameter_error_class(ParameterError)

__version__ = _impactid.version()


def kernels() -> str:
    """Which batched kernels run and what the processor supports, as `impactid --version` says:
    for example "x86-64-v4 (processor supports x86-64-v4)". IMPACTID_KERNELS, set before the
    import, forces a level (baseline, x86-64-v3, x86-64-v4)."""
    return _impactid.kernels()

_INDICATORS = tuple(name for name in _impactid.indicators() if name != "wall_time_s")


def parameters() -> list[dict]:
    """Every parameter (name, group, kind, unit, description, choices, methods), in --help order."""
    return _impactid.parameters()


def methods() -> list[str]:
    """Every method's name, in the order `impactid compare` lists them."""
    return _impactid.methods()


def contact_laws() -> list[str]:
    """Every contact law's name (the values of `contact=`), in the order `impactid contact-laws`
    lists them; that command describes each with its parameters."""
    return _impactid.contact_laws()


class Run:
    """One simulation: what `impactid simulate --json` reports, and its --history columns.

    Attributes: method, parameters (every value the run used, derived ones included), status
    ("ok", "unstable" or "failed"), verdict (what the run is worth: "accurate", "oscillating",
    "inaccurate", "unverified", "unstable" or "failed", metrics/verdict.hpp) and verdict_reason,
    reference, reference_trusted and reference_error (the reference's estimated error, None
    when unknown), message, warning, dt, steps, planned_steps, wall_time_s,
    contact; the indicators (eps_p, eps_v, nop_p, nop_v, p_max, p_max_ratio, contact_episodes,
    energy_ratio, and with a far wall far_contact_episodes, impacts, max_penetration) as
    attributes and in `indicators`. An indicator is None when the run did not finish ("ok")
    or does not apply to the scene: a NaN is never given as a result. `episodes`: the primary
    contact's episodes beside the reference's, a dict each (start, end, impulse, peaks,
    contact_runs, energy_ratio and the reference's; metrics/episodes.hpp).

    The time histories are NumPy arrays by their column names: t, pressure, velocity,
    displacement, energy, and the reference's exact_pressure, exact_velocity,
    exact_displacement (a scene of bodies also has pressure.<contact>, ... and a user's model
    reference_pressure.<contact>, ...: in `history`). `units` and `descriptions` give each
    column's; `to_dataset()` gives them as an xarray.Dataset over t.
    """

    def __init__(self, data: dict):
        self._data = data
        self.history = {name: values for name, _, _, values in data["history"]}
        self.units = {name: units for name, units, _, _ in data["history"]}
        self.descriptions = {name: text for name, _, text, _ in data["history"]}
        for values in self.history.values():
            values.flags.writeable = False
        self.indicators = dict(data["indicators"])
        self.contacts = list(data["contacts"])

    @property
    def ok(self) -> bool:
        return self._data["status"] == "ok"

    def __getattr__(self, name: str):
        if name.startswith("_"):
            raise AttributeError(name)
        data = self.__dict__.get("_data")
        if data is None:
            raise AttributeError(name)
        if name in self.__dict__["history"]:
            return self.__dict__["history"][name]
        if name in _INDICATORS:
            return self.__dict__["indicators"].get(name)
        if name in data and name not in ("history", "indicators", "contacts"):
            return data[name]
        raise AttributeError(f"Run has no attribute or history column {name!r}")

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(self.history) | set(_INDICATORS)
                      | {k for k in self._data if k not in ("history",)})

    def to_dataset(self):
        """The time histories as an xarray.Dataset over t, with units and the run's values."""
        import xarray

        t = self.history["t"]
        variables = {
            name: ("t", values, {"units": self.units[name], "long_name": self.descriptions[name]})
            for name, values in self.history.items()
            if name != "t"
        }
        attrs = {"method": self.method, "status": self.status, "verdict": self.verdict}
        attrs.update({k: v for k, v in self.parameters.items()})
        attrs.update(self.indicators)
        return xarray.Dataset(
            variables,
            coords={"t": ("t", t, {"units": self.units["t"], "long_name": self.descriptions["t"]})},
            attrs=attrs,
        )

    def __repr__(self):
        shown = ", ".join(f"{k}={v:.4g}" for k, v in self.indicators.items()
                          if k in ("eps_p", "nop_p", "eps_v", "nop_v"))
        return (f"<impactid.Run {self.method} {self.status}"
                f"{': ' + shown if shown else ''}; {len(self.history['t'])} samples>")


# ---- arguments ----------------------------------------------------------------------------


def _value(name: str, value):
    """A parameter value as the settings take it: a word or a float (an int is a number)."""
    if isinstance(value, str):
        return value
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        return float(value)
    raise TypeError(f"{name} = {value!r}: must be a number or a word (str)")


def _params(params: dict) -> list[tuple[str, object]]:
    return [(name, _value(name, value)) for name, value in params.items()]


def _scene(scene):
    """(scene file, scene TOML text) from None, a path or a [scene] dict."""
    if scene is None:
        return None, None
    if isinstance(scene, (str, os.PathLike)):
        path = os.fspath(scene)
        if path in _impactid.methods() and not os.path.exists(path):
            raise ValueError(f"scene = {path!r}: is a method's name, not a scene file (a method is "
                             f"given as method={path!r}, or first: simulate({path!r}))")
        return path, None
    if isinstance(scene, dict):
        return None, tomli_w.dumps({"scene": _plain(scene)})
    raise TypeError(f"scene = {scene!r}: must be a scene file's path or a dict of [scene] keys")


def _method(method, params: dict) -> dict:
    """The method's keys merged into the parameters: a name, or a [method] dict with `name`."""
    if method is None:
        return params
    if isinstance(method, str):
        if method not in _impactid.methods() and (method.endswith(".toml")
                                                   or os.path.exists(method)):
            raise ValueError(f"method = {method!r}: is not a method's name but a file; a scene "
                             f"file is given as scene={method!r} (the first argument is the "
                             "method)")
        given = {"name": method}
    elif isinstance(method, dict):
        given = dict(method)
    elif isinstance(method, os.PathLike):
        raise TypeError(f"method = {method!r}: is a path; a scene file is given as scene= (the "
                        "first argument is the method)")
    else:
        raise TypeError(f"method = {method!r}: must be a method's name or a dict of [method] keys")
    merged = dict(params)
    for key, value in given.items():
        name = "method" if key == "name" else key
        if name in params:
            raise ValueError(f"{name} is given twice: in method and as a keyword argument")
        merged[name] = value
    return merged


def simulate(method=None, *, scene=None, set: dict | None = None, **params) -> Run:
    """`impactid simulate`: one scene, one method; returns the Run with its time histories.

    method: None (hht, the command line's default), a name (`simulate("hht")`), or a dict of
    [method] keys ({"name": "hht", "alpha": -0.3}).
    scene: None (the paper's rod), a scene file's path, or a dict of [scene] keys.
    set: dotted keys of a scene of bodies (`{"body.striker.velocity": 2000}`), as --set.
    The other keywords are the settings table's parameters, by their snake_case names (the
    options of `impactid simulate --help`): the scene's (elements=100, courant=0.5), the
    method's (alpha=-0.3), the output's (peak_prominence=1e-6); applied over scene and method.
    None, their default, leaves a parameter as the scene, the method or the defaults have it.
    """
    _check_keywords("simulate", params, _SIMULATE_KEYWORDS)
    params = _given(params)
    scene_file, scene_text = _scene(scene)
    given = _params(_method(method, params))
    return Run(_impactid.simulate(scene_file, scene_text, "scene", _params(set or {}), given))


def compare(scene=None, *, set: dict | None = None, **params) -> dict[str, Run]:
    """`impactid compare`: every method at its default parameters on one scene.

    Returns {method name: Run} in the command's order: by verdict, then by eps_p. The keywords
    are the scene's and the output's parameters (a method parameter is refused, as the command
    has no such option); None leaves one as the scene or the defaults have it.
    """
    for name in params:
        info = _PARAMETERS.get(name)
        if info is not None and info["group"] == "method":
            raise TypeError(f"compare() got the method parameter {name!r}: it runs every method "
                            "at its default parameters (use simulate)")
    _check_keywords("compare", params, _COMPARE_KEYWORDS)
    params = _given(params)
    scene_file, scene_text = _scene(scene)
    runs = _impactid.compare(scene_file, scene_text, "scene", _params(set or {}), _params(params))
    return {data["method"]: Run(data) for data in runs}


def _positive(name: str, value) -> float:
    v = _value(name, value)
    if isinstance(v, str) or not (v > 0.0 and math.isfinite(v)):
        raise ValueError(f"{name} = {value}: must be positive and finite")
    return v


def spectral(method=None, *, omega_dt=(), omega_max=None, match_damping=None, **params) -> dict:
    """`impactid spectral`: a method's spectral analysis on the undamped oscillator.

    Returns the dict `impactid spectral --json` prints: rho_inf, period_error_coefficient,
    stability, for HHT delta_min_period_error, and at the given omega_dt (a number or a
    sequence) NumPy arrays omega_dt, spectral_radius, damping_ratio, period_error, oscillatory
    (and HHT's delta_min). courant= or mass= set the stability scan's omega_max to the rod's
    highest mode; omega_max= sets it directly (not with them).

    match_damping=XI with one omega_dt=W: instead, for each one-parameter family the parameter
    whose algorithmic damping ratio at W is XI (the dict of `--match-damping XI --json`).
    """
    for name in params:
        info = _PARAMETERS.get(name)
        if info is not None and info["group"] != "method" and name not in ("courant", "mass"):
            raise TypeError(f"spectral() got the {info['group']} parameter {name!r}: only the "
                            "method's, courant and mass")
    _check_keywords("spectral", params, _SPECTRAL_KEYWORDS)
    params = _given(params)
    if isinstance(omega_dt, numbers.Real) and not isinstance(omega_dt, bool):
        omega_dt = [omega_dt]
    omegas = [_positive("omega_dt", w) for w in omega_dt]
    if match_damping is not None:
        given = _method(method, params)
        if given:
            name, value = next(iter(given.items()))
            raise ValueError(f"{name} = {value}: not used with match_damping (it matches every "
                             "method family)")
        if omega_max is not None:
            raise ValueError(f"omega_max = {omega_max}: not used with match_damping")
        target = _value("match_damping", match_damping)
        if isinstance(target, str) or not (target >= 0.0 and math.isfinite(target)):
            raise ValueError(f"match_damping = {match_damping}: must be >= 0 and finite")
        if len(omegas) != 1:
            raise ValueError(f"omega_dt = {len(omegas) or '(missing)'}"
                             f"{' values' if omegas else ''}: match_damping needs exactly one "
                             "omega_dt")
        return _impactid.match_damping(target, omegas[0])
    if omega_max is not None:
        if "courant" in params or "mass" in params:
            raise ValueError(f"omega_max = {omega_max}: cannot be given with courant or mass")
        omega_max = _positive("omega_max", omega_max)
    return _impactid.spectral(_params(_method(method, params)), omegas, omega_max)


# ---- signatures, from the settings table (the method registry's parameters included) -------

_PARAMETERS = {p["name"]: p for p in _impactid.parameters()}


def _annotation(info: dict):
    if info["kind"] == "choice":
        return typing.Optional[typing.Literal[tuple(info["choices"].split("|"))]]
    return typing.Optional[int if info["kind"] == "integer" else float]


def _keywords(names) -> list[inspect.Parameter]:
    return [inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=None,
                              annotation=_annotation(_PARAMETERS[name])) for name in names]


def _parameter_lines(names) -> str:
    lines = []
    for name in names:
        info = _PARAMETERS[name]
        unit = f" [{info['unit']}]" if info["unit"] else ""
        only = f" {{{info['methods']}}}" if info["methods"] else ""
        lines.append(f"    {name}{unit}: {info['description']}{only}")
    return "\n".join(lines)


def _generate_signature(function, leading: list[inspect.Parameter], names: list[str]) -> frozenset:
    """Gives `function` the signature `leading` + a keyword-only parameter (default None) per
    name of the settings table, so that help() and IDEs list them (its own **params would hide
    them), and appends their descriptions to its docstring. Returns the keywords it takes."""
    signature = inspect.signature(function)
    returns = signature.return_annotation
    function.__signature__ = inspect.Signature(leading + _keywords(names),
                                               return_annotation=returns)
    function.__doc__ = (inspect.cleandoc(function.__doc__) + "\n\nParameters from the settings "
                        "table (None: not given):\n" + _parameter_lines(names))
    return frozenset(p.name for p in leading) | frozenset(names)


def _edit_distance(a: str, b: str) -> int:
    """Insertions, deletions, substitutions and swaps of two neighbours ("alpah" -> "alpha": 1)."""
    d = [[i + j if i * j == 0 else 0 for j in range(len(b) + 1)] for i in range(len(a) + 1)]
    for i in range(1, len(a) + 1):
        for j in range(1, len(b) + 1):
            d[i][j] = min(d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] != b[j - 1]))
            if i > 1 and j > 1 and a[i - 1] == b[j - 2] and a[i - 2] == b[j - 1]:
                d[i][j] = min(d[i][j], d[i - 2][j - 2] + 1)
    return d[len(a)][len(b)]


def _nearest(word: str, candidates) -> list[str]:
    """The candidates nearest to `word` if near enough to be a typo of it, by the command line's
    rule (study/cli/cli_main.cpp): 1 edit in a word of up to 4 letters, 2 up to 8, 3 beyond; a
    candidate that begins with the word (3 letters or more) counts as 1."""
    limit = 1 if len(word) <= 4 else 2 if len(word) <= 8 else 3
    distance = {c: 1 if len(word) >= 3 and c.startswith(word) else _edit_distance(word, c)
                for c in candidates}
    best = min(distance.values(), default=limit + 1)
    return sorted(c for c, d in distance.items() if d == best <= limit)


def _check_keywords(function: str, given: dict, accepted: frozenset) -> None:
    """A keyword that is no parameter is refused as Python refuses one, with the nearest names."""
    for name in given:
        if name not in accepted:
            near = _nearest(name, accepted)
            hint = f"; did you mean {' or '.join(map(repr, near))}?" if near else ""
            raise TypeError(f"{function}() got an unexpected keyword argument {name!r}{hint}")


def _given(params: dict) -> dict:
    """The keywords that were given a value (None is a keyword's default: not given)."""
    return {name: value for name, value in params.items() if value is not None}


def _group(*groups: str) -> list[str]:
    return [name for name, info in _PARAMETERS.items()
            if info["group"] in groups and name != "method"]


_P = inspect.Parameter
_SIMULATE_KEYWORDS = _generate_signature(simulate, [
    _P("method", _P.POSITIONAL_OR_KEYWORD, default=None, annotation=str | dict | None),
    _P("scene", _P.KEYWORD_ONLY, default=None, annotation=str | os.PathLike | dict | None),
    _P("set", _P.KEYWORD_ONLY, default=None, annotation=dict | None),
], _group("scene", "method", "output"))
_COMPARE_KEYWORDS = _generate_signature(compare, [
    _P("scene", _P.POSITIONAL_OR_KEYWORD, default=None, annotation=str | os.PathLike | dict | None),
    _P("set", _P.KEYWORD_ONLY, default=None, annotation=dict | None),
], _group("scene", "output"))
_SPECTRAL_KEYWORDS = _generate_signature(spectral, [
    _P("method", _P.POSITIONAL_OR_KEYWORD, default=None, annotation=str | dict | None),
    _P("omega_dt", _P.KEYWORD_ONLY, default=()),
    _P("omega_max", _P.KEYWORD_ONLY, default=None, annotation=float | None),
    _P("match_damping", _P.KEYWORD_ONLY, default=None, annotation=float | None),
], _group("method") + ["courant", "mass"])
del _P


# ---- plans ---------------------------------------------------------------------------------


def _plain(value):
    """A dict's values as TOML writes them: NumPy arrays and tuples as lists, NumPy scalars as
    Python numbers."""
    if isinstance(value, dict):
        return {key: _plain(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(item) for item in value]
    if hasattr(value, "tolist") and hasattr(value, "dtype"):  # a NumPy array or scalar
        return _plain(value.tolist())
    return value


def _plan_dict(plan: dict) -> dict:
    """A plan dict with plain values; an axis given as a sequence (a list, a tuple, a NumPy
    array: `{"alpha": np.linspace(-0.3, 0, 7)}`) is the axis of those values."""
    plan = _plain(plan)
    study = plan.get("study")
    if isinstance(study, dict) and isinstance(study.get("axes"), dict):
        study["axes"] = {name: {"values": axis} if isinstance(axis, list) else axis
                         for name, axis in study["axes"].items()}
    return plan


def plan_text(plan: dict) -> str:
    """The TOML text a plan dict is run as (and stored as in its results file)."""
    return tomli_w.dumps(_plan_dict(plan))


class _Interrupted(KeyboardInterrupt):
    pass


# One plan at a time in a process: a run owns the SIGINT/SIGTERM handlers and the stop flag of
# the command it runs, and reports its errors on the process's std::cerr.
_run_lock = threading.Lock()


def run_plan(plan, *, threads: int | None = None, output=None, resume: bool = False):
    """`impactid run`: runs a plan and returns its results as an xarray.Dataset.

    plan: a plan file's path, or a plan as a dict (the TOML a plan file holds, as tomllib reads
    it; its name defaults to "plan", files it names are relative to the working folder). An
    axis of a dict may be a list or a NumPy array of its values:
    `{"alpha": np.linspace(-0.3, 0, 7)}` is `alpha = { values = [...] }`.
    threads: OpenMP threads (default: all cores, or OMP_NUM_THREADS).
    output: the results file to write. A plan file without it writes where `impactid run` does
    (its [output] file, or results/<plan name>.h5). A dict without it, and without an [output]
    file, writes no file: its results are only returned.
    resume: keep the points the file has, compute only the rest (needs a file).

    The file is the one `impactid run` writes. Progress goes to stderr as the command's does.
    Ctrl-C (SIGINT) or SIGTERM stops the run as it stops the command: what is finished is saved,
    then KeyboardInterrupt is raised; run again with resume=True to finish it. A bad plan raises
    ValueError with the command's message; a file that cannot be read or written, OSError.
    """
    if isinstance(plan, dict):
        path, text = "plan", plan_text(plan)
        table = plan.get("output")
        asked = output is not None or (isinstance(table, dict) and "file" in table)
    elif isinstance(plan, (str, os.PathLike)):
        path, text, asked = os.fspath(plan), "", True
    else:
        raise TypeError(f"plan = {plan!r}: must be a plan file's path or a dict of its keys")
    if threads is not None and (isinstance(threads, bool) or not isinstance(threads, int)
                                or threads < 1):
        raise ValueError(f"threads = {threads}: must be a positive integer")
    if asked:
        return _run_plan(path, text, os.fspath(output) if output is not None else "", threads,
                         resume, kept=True)
    if resume:
        raise ValueError("resume = True: this plan writes no file to resume (a dict without "
                         "output= or an [output] file); give output=")
    _impactid.plan_output(path, text, "")  # a bad plan is refused before a folder is made
    with tempfile.TemporaryDirectory(prefix="impactid-run-plan-") as folder:
        return _run_plan(path, text, os.path.join(folder, "results.h5"), threads, False,
                         kept=False)


def _run_plan(path: str, text: str, output: str, threads, resume: bool, kept: bool):
    target = _impactid.plan_output(path, text, output)
    with _run_lock:
        status, errors = _impactid.run_plan(path, text, output, threads or 0, bool(resume))
    message = "\n".join(line.removeprefix("impactid run: ")
                        for line in errors.strip().splitlines())
    if status == 130:
        if not kept:
            raise _Interrupted("interrupted: no file was asked for, so nothing is kept; give "
                               "output= to keep the finished points and resume")
        raise _Interrupted(f"interrupted: the finished points are saved in {target}; continue "
                           "with run_plan(..., resume=True)")
    if status == 2:
        raise ValueError(message)
    if status != 0:
        raise OSError(message or f"impactid run failed with status {status}")
    return open_results(target)
