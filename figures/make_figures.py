#!/usr/bin/python3
"""Regenerate every figure of impactid from its HDF5 results.

    figures/make_figures.py [--results DIR] [--out DIR]

reads the results files of the plans in plans/ and examples/block/ (layout: results/README.md)
from DIR (default results/) and writes one PNG per figure to --out (default DIR/figures/). It prints one line per
figure: `wrote PATH` or `skipped NAME: WHY`, where WHY names the missing file and the command
that produces it. The exit status is 0 unless a figure failed with an unexpected error (1) or
the arguments are wrong (2). What each figure shows: figures/README.md.

Needs Debian's python3 with python3-matplotlib (>= 3.6), python3-h5py and numpy; no other
package. Run it as /usr/bin/python3, or through scripts/figures.
"""

import argparse
import math
import sys
import tomllib
import traceback
from pathlib import Path

import numpy as np

try:
    import h5py
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib import colors as mcolors
    from matplotlib import patheffects as mpatheffects
    from matplotlib import ticker as mticker
    from matplotlib import transforms as mtransforms
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch, Rectangle
except ImportError as error:  # pragma: no cover - environment problem
    sys.exit(
        f"make_figures.py: {error}. Run it with Debian's /usr/bin/python3 (python3-matplotlib,"
        " python3-h5py), e.g. through scripts/figures."
    )

PROJECT_ROOT = Path(__file__).resolve().parent.parent
DPI = 150
RUN = "build/study/impactid run {}"  # how a results file is produced (project root)
# The plans that are not plans/<name>.toml: the shipped models' (examples/<model>/), by the
# results file they write (their `name`).
PLAN_FILES = {
    "block-hht-delta-alpha": "examples/block/hht-delta-alpha.toml",
    "block-identical-dissipation": "examples/block/identical-dissipation.toml",
    "block-work-precision": "examples/block/work-precision.toml",
}


def run_command(name):
    """The command that produces results/<name>.h5, from the project root."""
    return RUN.format(PLAN_FILES.get(name, f"plans/{name}.toml"))

# ---------------------------------------------------------------------------------------------
# Style: one colour per method in every figure (Okabe & Ito's colour-blind-safe palette).
# ---------------------------------------------------------------------------------------------

METHODS = {
    # plan name: (label, colour)
    "cdm": ("central difference", "#E69F00"),
    "backward-euler": ("backward Euler", "#56B4E9"),
    "newmark": ("Newmark", "#009E73"),
    "hht": ("HHT-α", "#0072B2"),
    "generalized-alpha": ("generalized-α", "#CC79A7"),
    "bathe": ("Bathe", "#44AA99"),
    "rho-bathe": ("ρ∞-Bathe", "#882255"),
    "tr-bdf2": ("TR-BDF2", "#332288"),
    "houbolt": ("Houbolt", "#999933"),
    "wilson-theta": ("Wilson-θ", "#AA4499"),
    "noh-bathe": ("Noh–Bathe explicit", "#661100"),
}
UNKNOWN_COLORS = ["#999999", "#F0E442", "#000000"]
EXACT_COLOR = "black"
NOT_OK_COLOR = "0.15"  # near black: points that are not ok (grey hatching on maps)
CHATTER_COLOR = "#B00000"  # not ok although the spectral analysis predicts stability
PRACTICAL_COLOR = "#D55E00"
PAPER_COLOR = "0.35"
CMAP = "viridis"

STATUS_TEXT = {
    -1: "not done",
    1: "not ok: unstable (energy growth)",
    2: "not ok: failed (singular matrix)",
}

# The default scene (README.md "simulate options"): a plan's [scene] overrides these.
DEFAULT_SCENE = {
    "length": 20.0,
    "elements": 200,
    "youngs_modulus": 90.0,
    "density": 7.85e-9,
    "area": 1.0,
    "velocity": 1000.0,
    "gap": 0.01,
    "mass": "lumped",
    "rayleigh_mass": 0.0,
    "rayleigh_stiffness": 0.0,
    "courant": 0.5,
}

IDENTICAL_DISSIPATION = (
    r"Identical dissipation: equal algorithmic damping ratio $\bar\xi$ at Ω = ω·Δt = 1, matched to "
    "HHT-α with α = −0.3, δ = 0.45; central difference and backward Euler at their own."
)

plt.rcParams.update(
    {
        "font.size": 9.5,
        "axes.titlesize": 10,
        "axes.labelsize": 10,
        "legend.fontsize": 8.5,
        "figure.titlesize": 11,
        "axes.grid": True,
        "grid.alpha": 0.3,
        "grid.linewidth": 0.6,
        "savefig.dpi": DPI,
    }
)


INDICATOR_SYMBOLS = {"eps_p": "ε_p", "eps_v": "ε_v", "nop_p": "NoP_p", "nop_v": "NoP_v", "p_max": "p_max",
                     "p_max_ratio": "p_max/(ρcv0)", "contact_episodes": "contact episodes", "energy_ratio": "energy ratio"}


class Skip(Exception):
    """A figure that cannot be drawn from the results at hand; the message says why."""


# ---------------------------------------------------------------------------------------------
# Reading results files
# ---------------------------------------------------------------------------------------------


def text(value):
    """An HDF5 attribute or string element as str."""
    if isinstance(value, bytes):
        return value.decode("utf-8")
    if isinstance(value, np.ndarray) and value.shape == ():
        return text(value[()])
    return str(value)


def texts(value):
    """A string attribute or dataset that may be a scalar or 1-D: a list of str."""
    if isinstance(value, (str, bytes)):
        return [text(value)]
    return [text(v) for v in np.atleast_1d(value)]


def num(s):
    """A number for a label: 4 significant digits, a true minus sign."""
    if isinstance(s, str):
        return s
    s = float(s)
    if s == int(s) and abs(s) < 1e6:
        out = str(int(s))
    else:
        out = f"{s:.4g}"
    return out.replace("-", "−")


class Results:
    """An impactid-results-1 file read into memory."""

    def __init__(self, path):
        self.path = Path(path)
        with h5py.File(self.path, "r") as f:
            self.attrs = {k: f.attrs[k] for k in f.attrs}
            self.data = {}
            self.meta = {}
            for name, ds in f.items():
                if not isinstance(ds, h5py.Dataset):
                    continue
                value = ds[()]
                if ds.dtype.kind in ("S", "O", "U"):
                    value = np.array(texts(value), dtype=object)
                self.data[name] = value
                self.meta[name] = {k: ds.attrs[k] for k in ds.attrs if k not in ("DIMENSION_LIST", "REFERENCE_LIST")}
            self.dims = []
            if "status" in f:
                for dim in f["status"].dims:
                    if len(dim):
                        self.dims.append(dim[0].name.lstrip("/"))
        fmt = text(self.attrs.get("format", ""))
        if fmt != "impactid-results-1":
            raise Skip(f"{self.path}: format is {fmt!r}, not 'impactid-results-1'")
        try:
            self.plan = tomllib.loads(text(self.attrs.get("plan", "")))
        except tomllib.TOMLDecodeError:
            self.plan = {}
        self.status = np.asarray(self.data.get("status"), dtype=int)

    def attr(self, name, default=None):
        return self.attrs[name] if name in self.attrs else default

    def has(self, name):
        return name in self.data

    def param_varies(self, name):
        if name not in self.data:
            return False
        v = np.asarray(self.data[name], dtype=float)
        v = v[np.isfinite(v)]
        return v.size > 1 and np.ptp(v) > 0


def load(results_dir, name):
    path = Path(results_dir) / f"{name}.h5"
    if not path.exists():
        raise Skip(f"{path} not found; produce it with: {run_command(name)}")
    r = Results(path)
    if r.status is None or r.status.size == 0:
        raise Skip(f"{path} holds no points")
    if np.all(r.status == -1):
        raise Skip(f"{path}: no point is done yet (status −1 everywhere); finish it with: {run_command(name)} --resume")
    return r


# ---------------------------------------------------------------------------------------------
# Labels: the scene and the methods
# ---------------------------------------------------------------------------------------------


def scene_text(scene, varying=()):
    """'rod L = 20 mm, n = 200, Courant 0.5, v0 = 1000 mm/s' plus whatever is not the default;
    a scene of bodies ([[scene.body]]) as bodies_scene_text describes it."""
    if is_scene_of_bodies(scene):
        return bodies_scene_text(scene, varying)
    s = dict(DEFAULT_SCENE)
    s.update({k: v for k, v in scene.items() if v is not None})
    parts = []
    if "length" not in varying:
        parts.append(f"rod L = {num(s['length'])} mm")
    if "elements" not in varying:
        parts.append(f"n = {num(s['elements'])}")
    if "dt" in scene and "courant" not in scene and "dt" not in varying:
        parts.append(f"Δt = {float(s['dt']):.3g} s")
    elif "courant" not in varying and "dt" not in varying:
        parts.append(f"Courant {num(s['courant'])}")
    if "velocity" not in varying:
        parts.append(f"v0 = {num(s['velocity'])} mm/s")
    extras = [
        ("youngs_modulus", "E = {} MPa"),
        ("density", "ρ = {} t/mm³"),
        ("area", "A = {} mm²"),
        ("gap", "gap {} mm"),
        ("rayleigh_mass", "a0 = {} 1/s"),
        ("rayleigh_stiffness", "a1 = {} s"),
    ]
    for key, template in extras:
        if key in varying:
            continue
        if not math.isclose(float(s[key]), float(DEFAULT_SCENE[key]), rel_tol=1e-12):
            parts.append(template.format(num(s[key])))
    if "mass" not in varying and text(s["mass"]) != "lumped":
        parts.append(f"{text(s['mass'])} mass")
    return ", ".join(parts)


def results_scene(r):
    """The scene of a results file: the plan's [scene] table, minus the parameters that vary
    (for a scene of bodies also its dotted keys, such as 'body.striker.velocity'); a user's
    model as model_scene_text describes it."""
    names = list(DEFAULT_SCENE) + ["dt"] + [d for d in r.dims if "." in d]
    varying = {name for name in names if r.param_varies(name)}
    if is_model_results(r):
        return model_scene_text(r, varying)
    scene = dict(r.plan.get("scene", {}))
    return scene_text(scene, varying)


# ---------------------------------------------------------------------------------------------
# User models ([scene] kind = "matrices", often a plan's `scene = "FILE.toml"`; examples/block)
# ---------------------------------------------------------------------------------------------


def is_model_results(r):
    """Whether a results file is a user model's: impactid writes the model_* root attributes."""
    return "model_dofs" in r.attrs or "model_files" in r.attrs or \
        isinstance(r.plan.get("scene"), str) or text(r.plan.get("scene", {}).get("kind", "")) == "matrices"


def project_path(path):
    """A path as the user would write it: relative to the project root when it is inside it."""
    path = Path(path)
    try:
        return str(path.resolve().relative_to(PROJECT_ROOT))
    except (ValueError, OSError):
        return str(path)


def model_files(r):
    """The model's matrix files of a results file (root attribute model_files), as Paths."""
    return [Path(f.strip()) for f in text(r.attr("model_files", "")).split(",") if f.strip()]


def model_scene(r):
    """The [scene] table of a user model's results file and the scene file it came from, as
    (table, path); path is None for a plan's inline [scene]. A plan's `scene = "FILE.toml"` is
    relative to the plan, which the results file does not name, so the file is looked for beside
    the plan of PLAN_FILES of that name, and beside the model's matrices (model_files, relative to
    where impactid ran: the project root, the results folder's parent or the current folder).
    ({}, None) if it is not found."""
    scene = r.plan.get("scene", {})
    if isinstance(scene, dict):
        return scene, None
    name = Path(text(scene))
    roots = [PROJECT_ROOT, r.path.resolve().parent.parent, Path.cwd()]
    candidates = [name] if name.is_absolute() else []
    plan = PLAN_FILES.get(text(r.attr("plan_name", r.plan.get("name", ""))))
    if plan and not name.is_absolute():
        candidates.append(PROJECT_ROOT / Path(plan).parent / name)
    for folder in [f.parent for f in model_files(r)]:
        for c in (folder / name, folder / name.name):
            candidates += [c] if c.is_absolute() else [root / c for root in roots]
    for c in candidates:
        if c.is_file():
            try:
                root = tomllib.loads(c.read_text())
            except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
                continue
            return root.get("scene", root), c
    return {}, None


def model_units(r):
    """The model's units (root attribute model_units, 'N, mm, s, t') as (force, length, time)."""
    u = [x.strip() for x in text(r.attr("model_units", "N, mm, s, t")).split(",")]
    return tuple((u + ["N", "mm", "s"][len(u):])[:3])


def pressure_unit(force, length):
    return "MPa" if (force, length) == ("N", "mm") else "Pa" if (force, length) == ("N", "m") else f"{force}/{length}²"


def model_scene_text(r, varying=()):
    """A user's model in one line: 'model examples/block (1722 DOFs, 41 contacts bottom_0 …
    bottom_40), Δt = 4.23e-08 s, to t = 6.13e-06 s, v0 = −1000 mm/s on all_y', from the results
    file's model_* attributes and the model's scene file; what varies in the study is left out."""
    scene, path = model_scene(r)
    force, length, time = model_units(r)
    files = model_files(r)
    where = project_path(path.parent) if path else project_path(files[0].parent) if files else "(model)"
    inside = []
    dofs = r.attr("model_dofs")
    if dofs is None and r.has("elements") and np.asarray(r.data["elements"]).size == 1:
        dofs = np.asarray(r.data["elements"]).item()  # a work-precision study: its one 'mesh'
    if dofs is not None:
        inside.append(f"{num(float(dofs))} DOFs")
    contacts = [str(c.get("name", f"contact {k}")) for k, c in enumerate(scene.get("contact", []))]
    if len(contacts) > 3:
        inside.append(f"{len(contacts)} contacts {contacts[0]} … {contacts[-1]}")
    elif contacts:
        inside.append(("contact " if len(contacts) == 1 else "contacts ") + ", ".join(contacts))
    parts = [f"model {where}" + (f" ({', '.join(inside)})" if inside else "")]
    if not varying & {"dt", "courant"}:
        if "courant" in scene:
            parts.append(f"Courant {num(scene['courant'])}")
        elif "dt" in scene:
            parts.append(f"Δt = {float(scene['dt']):.3g} {time}")
    if "t_end" in scene:
        parts.append(f"to t = {float(scene['t_end']):.3g} {time}")
    v = scene.get("initial", {}).get("velocity")
    if isinstance(v, dict) and "value" in v:
        parts.append(f"v0 = {num(v['value'])} {length}/{time}" + (f" on {v['dofs']}" if "dofs" in v else ""))
    return ", ".join(parts)


def model_contact_areas(r):
    """{contact name: area} of a user model's scene (contacts without an area: 1)."""
    scene, _ = model_scene(r)
    return {str(c["name"]): float(c.get("area", 1.0)) for c in scene.get("contact", []) if "name" in c}


def middle_contact_text(r, contact):
    """', the middle one of the 41' when `contact` is the middle one of the model's contacts
    (in the scene's order: bottom_20 of bottom_0 … bottom_40 of the block); '' otherwise."""
    names = list(model_contact_areas(r))
    if len(names) > 2 and len(names) % 2 == 1 and contact in names and names.index(contact) == len(names) // 2:
        return f", the middle one of the {len(names)}"
    return ""


def model_primary_contact(r):
    """A user model's primary contact: the scene's primary_contact, or its only contact; None."""
    scene, _ = model_scene(r)
    if scene.get("primary_contact"):
        return str(scene["primary_contact"])
    contacts = scene.get("contact", [])
    return str(contacts[0].get("name")) if len(contacts) == 1 else None


def mass_is_diagonal(r):
    """Whether the model's mass matrix (the scene's matrices.mass, a Matrix Market file) is
    diagonal; None if it cannot be read."""
    scene, path = model_scene(r)
    mass = scene.get("matrices", {}).get("mass")
    files = model_files(r)
    if mass and path:
        f = path.parent / mass
    elif files:  # model_files names the mass first
        f = files[0] if files[0].is_absolute() else PROJECT_ROOT / files[0]
    else:
        return None
    try:
        with open(f) as fh:
            header = True
            for line in fh:
                if line.startswith("%") or not line.strip():
                    continue
                if header:  # the size line
                    header = False
                    continue
                i, j = line.split()[:2]
                if i != j:
                    return False
        return True
    except (OSError, ValueError):
        return None


def model_reference_text(r):
    """What a user model's indicators are measured against, from the reference_* columns: its
    converged numerical solution (core/model_reference.hpp: central difference when M is diagonal,
    else HHT-α), at Δt/2^k, or the reference history supplied with the model."""
    how = {True: "central-difference", False: "HHT-α (α = −0.3)"}.get(mass_is_diagonal(r), "numerical")
    if not r.has("reference_refinements"):  # a work-precision study: a reference for each point's Δt
        return f"the model's converged {how} solution at Δt/2^k of each point's Δt, not an exact solution"
    ok = r.status == 0
    k = np.asarray(r.data["reference_refinements"], dtype=float)[ok]
    k = k[np.isfinite(k)]
    if k.size and np.all(k == -1):
        return "the reference history supplied with the model (not an exact solution)"
    if not k.size:
        return "the model's converged numerical solution (not an exact solution)"
    ks = sorted({int(v) for v in k})
    steps = " or ".join(f"Δt/{2 ** v}" for v in ks)
    change = ""
    if r.has("reference_change"):
        c = np.asarray(r.data["reference_change"], dtype=float)[ok]
        c = c[np.isfinite(c)]
        if c.size:
            change = f", changed by {100 * c.max():.2g} % at its last halving"
    return f"the model's converged {how} solution ({steps}{change}), not an exact solution"


# ---------------------------------------------------------------------------------------------
# Scenes of several bodies ([[scene.body]] in a plan's [scene]; plans/README.md)
# ---------------------------------------------------------------------------------------------

SEGMENT_KEYS = ("length", "elements", "youngs_modulus", "density", "area")


def is_scene_of_bodies(scene):
    """Whether a [scene] table describes a scene of bodies (it has `body` or `wall`), as
    study/scene_file.hpp decides."""
    return "body" in scene or "wall" in scene


def scene_bodies(scene):
    """The bodies of a scene of bodies, left to right, each as {name, velocity, gap, segments},
    a segment being a dict of SEGMENT_KEYS with the one-body defaults filled in."""
    bodies = []
    for k, b in enumerate(scene.get("body", [])):
        segments = b.get("segment") or [{key: b[key] for key in SEGMENT_KEYS if key in b}]
        segments = [{key: seg.get(key, DEFAULT_SCENE[key]) for key in SEGMENT_KEYS} for seg in segments]
        bodies.append({"name": str(b.get("name", f"body{k + 1}")), "velocity": float(b.get("velocity", 0.0)),
                       "gap": float(b.get("gap", 0.0)), "segments": segments})
    return bodies


def scene_contacts(scene):
    """The contacts of a scene of bodies, left to right, as core/scene.cpp names them:
    [(name, gap, dotted keys of the gap)] with 'wall_left', '<left>-<right>' and 'wall_right'."""
    bodies = scene_bodies(scene)
    walls = scene.get("wall", {})
    out = []
    if "left" in walls and bodies:
        out.append(("wall_left", float(walls["left"].get("gap", bodies[0]["gap"])),
                    ("wall.left.gap", f"body.{bodies[0]['name']}.gap", "body.1.gap")))
    for k, (left, right) in enumerate(zip(bodies, bodies[1:])):
        out.append((f"{left['name']}-{right['name']}", right["gap"], (f"body.{right['name']}.gap", f"body.{k + 2}.gap")))
    if "right" in walls:
        out.append(("wall_right", float(walls["right"].get("gap", 0.0)), ("wall.right.gap",)))
    return out


def primary_contact(scene, data=None):
    """The name of a scene's primary contact, whose indicators are stored unsuffixed: the plan's
    `primary_contact`, the only contact, or the contact whose `eps_p.<contact>` equals `eps_p`
    in `data` (a results file's datasets); None if that does not tell."""
    if scene.get("primary_contact"):
        return str(scene["primary_contact"])
    contacts = [name for name, *_ in scene_contacts(scene)]
    if len(contacts) == 1:
        return contacts[0]
    if data is not None and "eps_p" in data:
        same = [c for c in contacts if f"eps_p.{c}" in data and
                np.array_equal(np.asarray(data[f"eps_p.{c}"]), np.asarray(data["eps_p"]), equal_nan=True)]
        if len(same) == 1:
            return same[0]
    return None


def contact_text(name):
    """'striker-bar' -> 'striker–bar contact'; 'wall_right' -> 'right wall'."""
    if name is None:
        return "primary contact"
    if name.startswith("wall_"):
        return f"{name[5:]} wall"
    return f"{name.replace('-', '–')} contact"


def bodies_scene_text(scene, varying=()):
    """A scene of bodies in one line: 'striker 10 mm + bar 60 mm, n = 100 + 600, gap 0.01 mm,
    Courant 0.5, v0 = 1000 mm/s (striker)'; a body of several segments as
    'rod (10 mm, A = 4 mm² | 10 mm, A = 1 mm²)', a wall as 'on the right wall'. Material values
    are named where they differ from the paper's rod; keys that vary in the study are left out."""
    bodies = scene_bodies(scene)
    walls = scene.get("wall", {})

    def varies(body, k, key):
        return any(v in varying for v in (f"body.{body['name']}.{key}", f"body.{k + 1}.{key}"))

    def segment_text(seg, several):
        parts = [f"{num(seg['length'])} mm"]
        if several or not math.isclose(float(seg["area"]), float(DEFAULT_SCENE["area"])):
            parts.append(f"A = {num(seg['area'])} mm²")
        for key, template in (("youngs_modulus", "E = {} MPa"), ("density", "ρ = {} t/mm³")):
            if not math.isclose(float(seg[key]), float(DEFAULT_SCENE[key]), rel_tol=1e-12):
                parts.append(template.format(num(seg[key])))
        return ", ".join(parts)

    names = []
    for b in bodies:
        segs = b["segments"]
        if len(segs) == 1:
            t = segment_text(segs[0], False)
            names.append(f"{b['name']} {t}" if "," not in t else f"{b['name']} ({t})")
        else:
            names.append(f"{b['name']} (" + " | ".join(segment_text(g, True) for g in segs) + ")")
    line = " + ".join(names)
    if "left" in walls and "right" in walls:
        line = f"{line} between two walls"
    elif "left" in walls:
        line = f"left wall, {line}"
    elif "right" in walls:
        line = f"{line} on the right wall"
    parts = [line]
    n = [num(seg["elements"]) for b in bodies for seg in b["segments"]]
    parts.append(f"n = {' + '.join(n)}")
    gaps = [(name, g) for name, g, keys in scene_contacts(scene) if not any(k in varying for k in keys)]
    if gaps and len({g for _, g in gaps}) == 1:
        what = "gap" if len(gaps) == 1 else "gaps"
        parts.append(f"{what} {num(gaps[0][1])} mm")
    else:
        parts += [f"gap {contact_text(name)} {num(g)} mm" for name, g in gaps]
    if "dt" in scene and "courant" not in scene and "dt" not in varying:
        parts.append(f"Δt = {float(scene['dt']):.3g} s")
    elif "courant" not in varying and "dt" not in varying:
        parts.append(f"Courant {num(scene.get('courant', DEFAULT_SCENE['courant']))}")
    moving = [(k, b) for k, b in enumerate(bodies) if b["velocity"] != 0 and not varies(b, k, "velocity")]
    if len(bodies) == 1 and moving:
        parts.append(f"v0 = {num(moving[0][1]['velocity'])} mm/s")
    elif moving:
        parts.append("v0 = " + ", ".join(f"{num(b['velocity'])} mm/s ({b['name']})" for _, b in moving))
    for key, template in (("rayleigh_mass", "a0 = {} 1/s"), ("rayleigh_stiffness", "a1 = {} s")):
        if key not in varying and key in scene and float(scene[key]) != float(DEFAULT_SCENE[key]):
            parts.append(template.format(num(scene[key])))
    if "mass" not in varying and text(scene.get("mass", "lumped")) != "lumped":
        parts.append(f"{text(scene['mass'])} mass")
    return ", ".join(parts)


def method_info(method):
    method = text(method).strip().lower()
    if method in METHODS:
        return METHODS[method]
    for key, value in METHODS.items():  # a label such as "HHT-α (…)" or "hht, eq. 15"
        if method.startswith(key):
            return value
    return (method, UNKNOWN_COLORS[hash(method) % len(UNKNOWN_COLORS)])


def method_color(method):
    return method_info(method)[1]


def method_params(method, params, sep=", "):
    """The parameters that tell one setting of a method from another, as text."""
    method = text(method)

    def get(name):
        v = params.get(name)
        if v is None:
            return None
        if isinstance(v, (str, bytes)):
            return text(v)
        v = float(v)
        return None if not math.isfinite(v) else v

    parts = []
    if method == "hht" and get("alpha") is not None:
        parts.append(f"α = {num(round(get('alpha'), 4))}")
    if method in ("newmark", "hht"):
        if get("delta") is not None:
            parts.append(f"δ = {num(round(get('delta'), 4))}")
        elif get("beta") is not None and get("gamma") is not None:
            parts.append(f"β = {num(round(get('beta'), 4))}")
            parts.append(f"γ = {num(round(get('gamma'), 4))}")
    if method == "rho-bathe" and get("rho_inf") is not None:
        parts.append(f"ρ∞ = {num(round(get('rho_inf'), 4))}")
        if get("substep_ratio") is not None:
            parts.append(f"γ = {num(round(get('substep_ratio'), 4))}")
    if method == "wilson-theta" and get("theta") is not None:
        parts.append(f"θ = {num(round(get('theta'), 4))}")
    if method == "noh-bathe" and get("p") is not None:
        parts.append(f"p = {num(round(get('p'), 4))}")
    if method == "generalized-alpha" and get("rho_inf") is not None:
        parts.append(f"ρ∞ = {num(round(get('rho_inf'), 4))}")
    if method == "cdm" and get("cdm_velocity") not in (None, "central"):
        parts.append(f"{get('cdm_velocity')} velocity")
    if method in ("hht", "generalized-alpha") and get("hht_contact") not in (None, "endpoint"):
        parts.append(f"{get('hht_contact')} contact")
    return sep.join(parts)


SHORT_NAMES = {"cdm": "central\ndifference", "backward-euler": "backward\nEuler"}


def method_label(method, params, sep=", "):
    name = method_info(method)[0]
    if sep == "\n":
        name = SHORT_NAMES.get(text(method), name)
    p = method_params(method, params, sep)
    if not p:
        return name
    return f"{name} ({p})" if sep == ", " else f"{name}{sep}{p}"


# ---------------------------------------------------------------------------------------------
# Drawing helpers
# ---------------------------------------------------------------------------------------------


def save(fig, out_dir, name):
    path = Path(out_dir) / name
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


def cell_edges(v):
    """Edges of the cells centred on the (sorted or reverse-sorted) values v."""
    v = np.asarray(v, dtype=float)
    if v.size == 1:
        return np.array([v[0] - 0.5, v[0] + 0.5])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def runs(mask):
    """(start, stop) index pairs, stop inclusive, of the runs of True in a 1-D mask."""
    out, start = [], None
    for i, m in enumerate(mask):
        if m and start is None:
            start = i
        if not m and start is not None:
            out.append((start, i - 1))
            start = None
    if start is not None:
        out.append((start, len(mask) - 1))
    return out


def interval_text(x, mask, symbol):
    parts = [f"[{num(x[a])}, {num(x[b])}]" if a != b else f"{{{num(x[a])}}}" for a, b in runs(mask)]
    return f"{symbol} ∈ " + " ∪ ".join(parts) if parts else ""


def practical_thresholds(r):
    t = r.attr("practical_thresholds")
    if t is None:
        return ""
    t = "; ".join(texts(t))
    for a, b in (("eps_p", "ε_p"), ("eps_v", "ε_v"), ("nop_p", "NoP_p"), ("nop_v", "NoP_v"), ("<=", "≤"), (">=", "≥")):
        t = t.replace(a, b)
    return t


def parse_thresholds(r):
    """practical_thresholds ('eps_p <= 0.03, nop_p <= 15', 'a <= x <= b', 'x >= a') as
    {indicator: (min or None, max or None)}; {} if absent or unreadable."""
    import re

    out = {}
    t = r.attr("practical_thresholds")
    if t is None:
        return out
    number = r"([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)"
    for part in "; ".join(texts(t)).replace(";", ",").split(","):
        part = part.strip()
        m = re.fullmatch(number + r"\s*<=\s*(\w+)\s*<=\s*" + number, part)
        if m:
            out[m.group(2)] = (float(m.group(1)), float(m.group(3)))
            continue
        m = re.fullmatch(r"(\w+)\s*(<=|>=)\s*" + number, part)
        if m:
            lo, hi = out.get(m.group(1), (None, None))
            if m.group(2) == "<=":
                hi = float(m.group(3))
            else:
                lo = float(m.group(3))
            out[m.group(1)] = (lo, hi)
    return out


def threshold_lines(ax, r, key, symbol):
    """Dashed horizontal lines at the practical thresholds of indicator `key`."""
    bounds = parse_thresholds(r).get(key)
    if not bounds:
        return
    label = "practical threshold"
    for value, op in zip(bounds, ("≥", "≤")):
        if value is not None:
            ax.axhline(value, color=PRACTICAL_COLOR, lw=1.1, ls="--", zorder=2,
                       label=f"{label} {symbol} {op} {num(value)}")


def mark_not_ok(ax, x, status, y_axes=0.03):
    """Crosses at the bottom of the axes where a 1-D study's point is not ok, one legend entry per status."""
    trans = mtransforms.blended_transform_factory(ax.transData, ax.transAxes)
    styles = {1: ("x", NOT_OK_COLOR), 2: ("+", NOT_OK_COLOR), -1: (".", "0.55")}
    for code, (marker, color) in styles.items():
        sel = status == code
        if np.any(sel):
            ax.plot(
                x[sel], np.full(sel.sum(), y_axes), marker, color=color, ms=7, mew=2, ls="none",
                transform=trans, clip_on=False, zorder=5, label=f"{STATUS_TEXT[code]} ({sel.sum()})",
            )


def log_axis_plain(axis):
    """Plain numbers (0.02, 50) rather than powers of ten on a logarithmic axis."""
    axis.set_major_formatter(mticker.FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(mticker.FuncFormatter(lambda v, _: ""))


def paper_bar(ax, lo, hi, label, y_axes=0.975):
    """A thick bar along the top of the axes over [lo, hi], labelled: the paper's 'practical stage'."""
    trans = mtransforms.blended_transform_factory(ax.transData, ax.transAxes)
    ax.plot([lo, hi], [y_axes, y_axes], color=PAPER_COLOR, lw=4, solid_capstyle="butt",
            transform=trans, clip_on=False, zorder=4)
    ax.text(lo, y_axes - 0.02, " " + label, transform=trans, ha="left", va="top", fontsize=8,
            color=PAPER_COLOR, zorder=4)


def shade_practical_1d(ax, r, x, symbol):
    """Shade the practical points of a 1-D study (the `practical` column); return whether any."""
    if not r.has("practical"):
        return False
    pr = np.asarray(r.data["practical"], dtype=float) == 1
    if not np.any(pr):
        thresholds = practical_thresholds(r)
        ax.axvspan(np.nan, np.nan, color=PRACTICAL_COLOR, alpha=0.13, lw=0,
                   label="practical range: no point" + (f" ({thresholds})" if thresholds else ""))
        return False
    edges = cell_edges(x)
    lo_clip, hi_clip = min(x[0], x[-1]), max(x[0], x[-1])
    label = f"practical range {interval_text(x, pr, symbol)}"
    thresholds = practical_thresholds(r)
    if thresholds:
        label += f"\n({thresholds})"
    for a, b in runs(pr):
        # a run spans its first to its last point; a single point gets its cell
        lo, hi = sorted((x[a], x[b]) if a != b else (edges[a], edges[b + 1]))
        ax.axvspan(max(lo, lo_clip), min(hi, hi_clip), color=PRACTICAL_COLOR, alpha=0.13, lw=0, label=label, zorder=0)
        label = None
    return True


# ---------------------------------------------------------------------------------------------
# Figure 3: Newmark over delta
# ---------------------------------------------------------------------------------------------


def indicator_panels_1d(r, x, xlabel, symbol, color, keys, paper=None, secondary=None):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.6), constrained_layout=True)
    status = r.status
    for ax, (key, ylabel, title) in zip(axes, keys):
        if not r.has(key):
            ax.text(0.5, 0.5, f"{key} not in {r.path.name}", transform=ax.transAxes, ha="center")
            continue
        y = np.where(status == 0, np.asarray(r.data[key], dtype=float), np.nan)
        shade_practical_1d(ax, r, x, symbol)
        threshold_lines(ax, r, key, ylabel.split(" ")[0])
        ax.plot(x, y, "-o", color=color, ms=3.5, lw=1.3, label=f"{ylabel.split(' ')[0]} (ok points)", zorder=3)
        if np.any(np.isfinite(y)):
            i = int(np.nanargmin(y))
            ties = int(np.sum(y == y[i]))
            where = f"{symbol} = {num(round(x[i], 4))}" if ties == 1 else f"{ties} points, first {symbol} = {num(round(x[i], 4))}"
            ax.plot(x[i], y[i], "*", ms=13, color="white", mec="black", mew=1.0, zorder=6, clip_on=False,
                    label=f"smallest: {num(round(y[i], 4) if y[i] < 1 else y[i])} ({where})")
        mark_not_ok(ax, x, status)
        if paper:
            paper_bar(ax, *paper)
        ax.set_yscale("log")
        ax.yaxis.set_major_locator(mticker.LogLocator(subs=(1.0, 2.0, 5.0)))
        log_axis_plain(ax.yaxis)
        ax.set_xlim(min(x[0], x[-1]), max(x[0], x[-1]))
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.25)
        if secondary:
            sec = ax.secondary_xaxis("top", functions=secondary[0])
            sec.set_xlabel(secondary[1])
        ax.legend(loc="upper right", bbox_to_anchor=(1.0, 0.9), framealpha=0.92)
    return fig, axes


def newmark_delta_figure(results_dir, out_dir, name, png, title, paper_label, where="", scene_sep="; "):
    """Fig. 3's layout for the results file `name`.h5 (Newmark over δ): ε_p and NoP_p against δ.
    `where` names the contact the indicators are taken at ("" for the paper's one contact);
    `scene_sep` goes between the title and the scene ("\n" for a long title)."""
    r = load(results_dir, name)
    if r.dims != ["delta"]:
        raise Skip(f"{r.path}: expected one grid axis 'delta', found {r.dims}")
    x = np.asarray(r.data["delta"], dtype=float)
    keys = [
        ("eps_p", "ε_p [−]", f"(a) relative error of the {where}contact pressure (eq. 18)"),
        ("nop_p", "NoP_p [−]", f"(b) number of peaks of the {where}contact pressure"),
    ]
    fig, _ = indicator_panels_1d(r, x, "δ [−]  (β = (1+δ)²/4, γ = ½+δ, eq. 13)", "δ", method_color("newmark"), keys,
                                 paper=(0.3, 1.0, paper_label))
    fig.suptitle(f"{title}{scene_sep}{results_scene(r)}")
    return [save(fig, out_dir, png)]


def fig3(results_dir, out_dir):
    return newmark_delta_figure(results_dir, out_dir, "newmark-delta", "fig3_newmark_delta.png",
                                "Fig. 3 — Newmark method over δ", "paper's practical stage δ ∈ [0.3, 1]")


def fig_two_rods(results_dir, out_dir):
    r = load(results_dir, "two-rods")
    contact = primary_contact(r.plan.get("scene", {}), r.data)
    return newmark_delta_figure(
        results_dir, out_dir, "two-rods", "fig_two_rods.png",
        f"Two equal rods — Newmark method over δ, at the {contact_text(contact)} (exact reference: the chain's "
        "characteristics)", "paper's practical stage on one rod δ ∈ [0.3, 1]",
        where=f"{contact.replace('-', '–')} " if contact and not contact.startswith("wall_") else "", scene_sep="\n")


def fig_period_error_line(results_dir, out_dir):
    r = load(results_dir, "hht-period-error-line")
    if r.dims != ["alpha"] or not r.has("delta"):
        raise Skip(f"{r.path}: expected the grid axis 'alpha' and the coupled column 'delta', found {r.dims}")
    x = np.asarray(r.data["alpha"], dtype=float)
    keys = [
        ("eps_p", "ε_p [−]", "(a) relative error of the contact pressure (eq. 18)"),
        ("nop_p", "NoP_p [−]", "(b) number of peaks of the contact pressure"),
    ]
    fig, _ = indicator_panels_1d(
        r, x, "α [−]", "α", method_color("hht"), keys,
        paper=(-0.5, -0.3, "paper's practical stage α ∈ [−0.5, −0.3]"),
        secondary=((lambda a: -1.5 * a, lambda d: -d / 1.5), "δ = −1.5·α [−]"),
    )
    fig.suptitle(f"HHT-α along δ = −1.5·α (eq. 19, the minimal period error); {results_scene(r)}")
    return [save(fig, out_dir, "fig_period_error_line.png")]


# ---------------------------------------------------------------------------------------------
# Figure 4: HHT over (delta, alpha)
# ---------------------------------------------------------------------------------------------


def grid_2d(r, key, xdim="delta", ydim="alpha"):
    """The surface `key` of a 2-D grid as Z[y, x] with the axis values (x, y)."""
    if sorted(r.dims) != sorted([xdim, ydim]):
        raise Skip(f"{r.path}: expected the grid axes {ydim} × {xdim}, found {r.dims}")
    z = np.asarray(r.data[key], dtype=float)
    if r.dims[0] == xdim:
        z = z.T
    return np.asarray(r.data[xdim], dtype=float), np.asarray(r.data[ydim], dtype=float), z


def hht_map(ax, r, key, norm_kind="log", cbar_label="", fig=None, valid=None):
    """pcolormesh of an HHT (δ, α) surface over the cells `valid` (default: the ok ones); the
    others are hatched grey. Returns (x, y, z, status)."""
    x, y, z = grid_2d(r, key)
    _, _, st = grid_2d(r, "status")
    if valid is None:
        valid = st == 0
    zm = np.ma.masked_where(~valid | ~np.isfinite(z), z)
    xe, ye = cell_edges(x), cell_edges(y)
    ax.add_patch(Rectangle((xe.min(), ye.min()), np.ptp(xe), np.ptp(ye), facecolor="0.86", edgecolor="0.55",
                           hatch="///", lw=0, zorder=0))
    vmin, vmax = float(zm.min()), float(zm.max())
    if norm_kind == "log" and vmin > 0:
        norm = mcolors.LogNorm(vmin=vmin, vmax=vmax)
    else:
        norm = mcolors.Normalize(vmin=vmin, vmax=vmax)
    ax.grid(False)
    mesh = ax.pcolormesh(xe, ye, zm, cmap=CMAP, norm=norm, shading="flat", zorder=1)
    cb = fig.colorbar(mesh, ax=ax, pad=0.02)
    cb.set_label(cbar_label)
    if norm_kind == "log":
        # 1, 2, 5 per decade; a range of less than a decade (the block's ε_p, 0.04 to 0.16) gets more
        narrow = vmin > 0 and vmax / vmin < 6
        subs = (1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0) if narrow else (1.0, 2.0, 5.0)
        cb.ax.yaxis.set_major_locator(mticker.LogLocator(subs=subs))
        log_axis_plain(cb.ax.yaxis)
    ax.set_xlim(xe.min(), xe.max())
    ax.set_ylim(ye.min(), ye.max())
    ax.set_xlabel("δ [−]")
    ax.set_ylabel("α [−]")
    ax.grid(False)
    ax.impactid_norm = norm
    return x, y, z, st


def hht_lines(ax, x, y, paper_stage=True, paper_stage_label=None):
    """The lines δ = −1.5α (eq. 19) and δ = −α (eq. 15) over the α range of the map, and the
    paper's practical stage on eq. 19 (its legend text `paper_stage_label`, if given)."""
    a = np.linspace(y.min(), y.max(), 50)
    handles = []
    handles += ax.plot(-1.5 * a, a, color="white", lw=2.0, ls=(0, (5, 2)), zorder=4,
                       path_effects=[mpatheffects.withStroke(linewidth=3.6, foreground="black")],
                       label="δ = −1.5·α  (eq. 19: minimal period error)")
    handles += ax.plot(-a, a, color="black", lw=1.6, ls=":", zorder=4,
                       label="δ = −α  (eq. 15; HHT unstable for δ < −α)")
    if paper_stage:
        s = np.linspace(-0.5, -0.3, 10)
        s = s[(s >= y.min()) & (s <= y.max())]
        if s.size:
            handles += ax.plot(-1.5 * s, s, color="0.78", lw=10, alpha=0.9, solid_capstyle="butt", zorder=3,
                               label=paper_stage_label or "paper's practical stage α ∈ [−0.5, −0.3] on eq. 19")
    return handles


def outline_practical(ax, r):
    if not r.has("practical"):
        return []
    x, y, pr = grid_2d(r, "practical")
    pr = np.where(np.isfinite(pr), pr, 0.0)
    if not np.any(pr == 1):  # say so, as the 1-D figures do
        thresholds = practical_thresholds(r)
        return [Patch(facecolor="none", edgecolor=PRACTICAL_COLOR, lw=2.0,
                      label="practical region: no point" + (f" ({thresholds})" if thresholds else ""))]
    # outline the union of practical cells (their edges), not a contour through the centres
    xe, ye = cell_edges(x), cell_edges(y)
    fine = np.kron(pr, np.ones((4, 4)))
    xf = np.interp(np.arange(fine.shape[1]) / 4 + 0.125, np.arange(len(xe)), xe)
    yf = np.interp(np.arange(fine.shape[0]) / 4 + 0.125, np.arange(len(ye)), ye)
    ax.contour(xf, yf, fine, levels=[0.5], colors=[PRACTICAL_COLOR], linewidths=2.0, zorder=5)
    # name the region inside it, at its practical cell nearest the centroid
    jj, ii = np.nonzero(pr == 1)
    cx, cy = x[ii].mean(), y[jj].mean()
    k = np.argmin(((x[ii] - cx) / np.ptp(x)) ** 2 + ((y[jj] - cy) / np.ptp(y)) ** 2)
    ax.text(x[ii[k]], y[jj[k]], "practical", color="white", fontsize=10, fontweight="bold", ha="center",
            va="center", zorder=6, path_effects=[mpatheffects.withStroke(linewidth=2.5, foreground=PRACTICAL_COLOR)])
    label = f"practical region ({int(np.sum(pr == 1))} points"
    thresholds = practical_thresholds(r)
    label += f": {thresholds})" if thresholds else ")"
    return [Line2D([], [], color=PRACTICAL_COLOR, lw=2.0, label=label)]


def stability_handles(st, stable, source, closed_form, chatter_where="on the wall"):
    """Legend entries of Fig. 4's masks: the predicted-unstable cells (hatched) and, among them,
    those that still ran ok (dots), and the chatter cells (not ok although predicted stable).
    `source` is the second value of predicted_stable(); `closed_form` the map δ ≥ −α."""
    if source.startswith("spectral.h5"):
        omega = source.split("Ω = ")[-1].rstrip(")")
        rule = f"spectral.h5: ρ > 1 for some Ω ≤ {omega}"
        if np.array_equal(stable, closed_form):
            rule += ", i.e. δ < −α"
    else:
        rule = "δ < −α, eq. 15; no spectral.h5 on this grid"
    handles = [Patch(facecolor="0.86", edgecolor="0.55", hatch="///",
                     label=f"linearly unstable ({rule}), not drawn: {int(np.sum(~stable))} points")]
    slow = ~stable & (st == 0)
    if np.any(slow):
        handles.append(Line2D([], [], marker="o", ms=3.0, mfc="none", mec="0.25", mew=0.9, ls="none",
                              label=f"… of which ran ok: growth too slow for the horizon ({int(slow.sum())})"))
    chatter = stable & (st > 0)
    if np.any(chatter):
        codes = sorted({int(c) for c in np.unique(st[chatter])})
        what = " / ".join(STATUS_TEXT[c].replace("not ok: ", "") for c in codes)
        handles.append(Line2D([], [], marker="x", ms=6, mew=1.8, color=CHATTER_COLOR, ls="none",
                              label=f"{what} although predicted stable: chatter {chatter_where} ({int(chatter.sum())})"))
    return handles


def fig4(results_dir, out_dir):
    return hht_maps_figure(results_dir, out_dir, "hht-delta-alpha", "fig4_hht_delta_alpha.png",
                           "Fig. 4 — HHT-α with independent δ (eq. 13) and α (eq. 14)")


def fig_hopkinson(results_dir, out_dir):
    r = load(results_dir, "hopkinson")
    contact = primary_contact(r.plan.get("scene", {}), r.data)
    where = f"{contact.replace('-', '–')} " if contact and not contact.startswith("wall_") else ""
    return hht_maps_figure(
        results_dir, out_dir, "hopkinson", "fig_hopkinson.png",
        f"Split-Hopkinson striker on a bar — HHT-α over (δ, α), at the {contact_text(contact)} (exact reference: "
        "the chain's characteristics)", where=where, scene_sep="\n", paper_stage_label="paper's practical stage "
        "(on one rod) α ∈ [−0.5, −0.3] on eq. 19",
        chatter_where=f"at the {contact_text(contact)}" if contact else "at a contact")


def fig_block_hht(results_dir, out_dir):
    r = load(results_dir, "block-hht-delta-alpha")
    contact = model_primary_contact(r) or primary_contact({}, r.data)
    where = f"{contact} " if contact else ""
    return hht_maps_figure(
        results_dir, out_dir, "block-hht-delta-alpha", "block-hht-delta-alpha.png",
        f"2D elastic block dropped on a rigid plane (GetFEM plane-strain model) — HHT-α over (δ, α), at the "
        f"{contact_text(contact)}{middle_contact_text(r, contact)}\nReference: {model_reference_text(r)}",
        where=where, scene_sep="\n",
        paper_stage_label="paper's practical stage (on the rod) α ∈ [−0.5, −0.3] on eq. 19",
        chatter_where="at the contacts")


def hht_maps_figure(results_dir, out_dir, name, png, heading, where="", scene_sep="; ", paper_stage_label=None,
                    chatter_where="on the wall"):
    """Fig. 4's layout for the results file `name`.h5 (HHT over δ × α): maps of ε_p and NoP_p.
    `where` names the contact the indicators are taken at ("" for the paper's one contact),
    `chatter_where` where the chatter of the not-ok, predicted-stable runs happens."""
    r = load(results_dir, name)
    x, y, st = grid_2d(r, "status")
    # The mask is the linear stability the spectral analysis predicts, not the simulated status:
    # near δ = −α a linearly unstable run can end ok (slow growth), and it must not be read as data.
    stable, source = predicted_stable(results_dir, y, x)
    valid = stable & (st == 0)
    chatter = stable & (st > 0)
    slow = ~stable & (st == 0)
    fig, axes = plt.subplots(1, 2, figsize=(12.5, 5.9), constrained_layout=True)
    handles = []
    for ax, key, label, title in (
        (axes[0], "eps_p", "ε_p [−]", f"(a) relative error of the {where}contact pressure ε_p (eq. 18)"),
        (axes[1], "nop_p", "NoP_p [−]", f"(b) number of peaks of the {where}contact pressure NoP_p"),
    ):
        _, _, z, _ = hht_map(ax, r, key, "log", label, fig, valid=valid)
        lines = hht_lines(ax, x, y, paper_stage_label=paper_stage_label)
        jj, ii = np.nonzero(slow)
        ax.plot(x[ii], y[jj], "o", ms=3.0, mfc="none", mec="0.25", mew=0.9, ls="none", zorder=2)
        # a chatter cell is predicted stable: white, not hatched, under its cross
        ax.pcolormesh(cell_edges(x), cell_edges(y), np.ma.masked_where(~chatter, np.ones_like(z)),
                      cmap=mcolors.ListedColormap(["white"]), shading="flat", zorder=1)
        jj, ii = np.nonzero(chatter)
        ax.plot(x[ii], y[jj], "x", ms=6, mew=1.8, color=CHATTER_COLOR, ls="none", zorder=5)
        star = []
        zok = np.where(valid, z, np.nan)
        if key == "eps_p" and np.any(np.isfinite(zok)):
            j, i = np.unravel_index(np.nanargmin(zok), zok.shape)
            star = ax.plot(x[i], y[j], "*", ms=15, color="white", mec="black", mew=1.0, zorder=6, clip_on=False,
                           label=f"smallest ε_p = {zok[j, i]:.4f} at δ = {num(x[i])}, α = {num(y[j])}"
                                 " (of the stable, ok points)")
        practical = outline_practical(ax, r)
        ax.set_title(title)
        if not handles:
            closed_form = x[None, :] >= -y[:, None] - 1e-12
            handles = lines + star + stability_handles(st, stable, source, closed_form, chatter_where) + practical
    fig.legend(handles=handles, loc="lower center", ncol=2, frameon=False, bbox_to_anchor=(0.5, 0.0))
    fig.get_layout_engine().set(rect=(0, 0.17, 1, 0.83))
    fig.suptitle(f"{heading}{scene_sep}{results_scene(r)}")
    return [save(fig, out_dir, png)]


# ---------------------------------------------------------------------------------------------
# Figures 5 and 6: time histories at identical dissipation
# ---------------------------------------------------------------------------------------------


class History:
    def __init__(self, path):
        self.path = Path(path)
        with h5py.File(self.path, "r") as f:
            self.attrs = {k: (text(f.attrs[k]) if isinstance(f.attrs[k], (bytes, str)) else f.attrs[k]) for k in f.attrs}
            self.data = {k: np.asarray(f[k][()], dtype=float) for k in f if isinstance(f[k], h5py.Dataset)}
        for key in ("t", "pressure", "velocity", "exact_pressure", "exact_velocity"):
            if key not in self.data:
                raise Skip(f"{self.path}: dataset {key!r} missing (layout of `impactid simulate --history`)")
        self.method = text(self.attrs.get("method", "?"))
        self.t_us = self.data["t"] * 1e6

    def label(self):
        return method_label(self.method, self.attrs)

    def jump_times(self):
        """(t_impact, t_release) in µs: from the scene attributes, or from the exact pressure."""
        a = self.attrs
        try:
            c = math.sqrt(float(a["youngs_modulus"]) / float(a["density"]))
            t_imp = float(a["gap"]) / float(a["velocity"])
            return t_imp * 1e6, (t_imp + 2 * float(a["length"]) / c) * 1e6
        except (KeyError, ValueError, ZeroDivisionError):
            on = np.nonzero(self.data["exact_pressure"] > 0)[0]
            if on.size == 0:
                raise Skip(f"{self.path}: the exact pressure is zero throughout: no impact")
            return self.t_us[on[0]], self.t_us[on[-1]]


def find_history_dir(results_dir, name):
    """The folder of a list study's per-point histories: results/histories/<name>/, or the plan's
    [output] histories (relative to the project root or to the results folder's parent)."""
    results_dir = Path(results_dir)
    candidates = [results_dir / "histories" / name]
    path = results_dir / f"{name}.h5"
    if path.exists():
        try:
            r = Results(path)
            h = r.plan.get("output", {}).get("histories")
            if h:
                h = Path(h)
                candidates += [h] if h.is_absolute() else [PROJECT_ROOT / h, results_dir.parent / h, Path.cwd() / h]
        except Skip:
            pass
    for c in candidates:
        if (c / "point-0.h5").exists():
            return c
    raise Skip(f"no time histories: {candidates[0]}/point-*.h5 not found; produce them with: {run_command(name)}")


def load_histories(results_dir, name="identical-dissipation"):
    folder = find_history_dir(results_dir, name)
    files = sorted(folder.glob("point-*.h5"), key=lambda p: int(p.stem.split("-")[1]))
    # keep only the points of the results file, if there is one with status
    hist = [History(p) for p in files]
    for h, p in zip(hist, files):
        h.point = int(p.stem.split("-")[1])
        h.indicators = {}
    path = Path(results_dir) / f"{name}.h5"
    if path.exists():  # keep only the points of the results file, and take their indicators
        r = Results(path)
        n = r.status.size
        hist = [h for h in hist if h.point < n]
        for h in hist:
            if r.status[h.point] == 0:
                h.indicators = {k: float(np.atleast_1d(r.data[k])[h.point]) for k in INDICATOR_SYMBOLS if r.has(k)}
    return folder, hist


def window_ylim(lines_xy, lo, hi, pad=0.08):
    ymin, ymax = np.inf, -np.inf
    for x, y in lines_xy:
        sel = (x >= lo) & (x <= hi) & np.isfinite(y)
        if np.any(sel):
            ymin, ymax = min(ymin, y[sel].min()), max(ymax, y[sel].max())
    if not np.isfinite(ymin):
        return None
    span = (ymax - ymin) or 1.0
    return ymin - pad * span, ymax + pad * span


def bulk_ylim(curves, exact, lo, hi, factor=0.3, pad=0.08):
    """The y-range of a zoom window [lo, hi] that shows the bulk of the curves: a curve whose
    excursion beyond the exact solution's range is more than `factor` times the exact jump and
    more than twice the next-largest excursion leaves the frame (Newmark's chatter at impact would
    otherwise flatten every other curve). curves: [(name, t, y)], exact: (t, y).
    Returns ((ymin, ymax) or None, [(name, min, max)] of the curves left out)."""
    te, ye = exact
    sel = (te >= lo) & (te <= hi) & np.isfinite(ye)
    if not np.any(sel):
        return window_ylim([(t, y) for _, t, y in curves] + [exact], lo, hi, pad), []
    emin, emax = ye[sel].min(), ye[sel].max()
    jump = (emax - emin) or abs(emax) or 1.0  # a constant exact solution: its level
    spans = []
    for name, t, y in curves:
        w = (t >= lo) & (t <= hi) & np.isfinite(y)
        if np.any(w):
            ymin, ymax = y[w].min(), y[w].max()
            spans.append((max(ymax - emax, emin - ymin, 0.0), name, ymin, ymax, t, y))
    spans.sort(key=lambda e: -e[0])
    out = []
    while len(spans) > 1 and spans[0][0] > factor * jump and spans[0][0] > 2 * spans[1][0]:
        excursion, name, ymin, ymax, _, _ = spans.pop(0)
        out.append((name, ymin, ymax))
    kept = [(t, y) for *_, t, y in spans] + [exact]
    return window_ylim(kept, lo, hi, pad), out


def least_covering(ax, rects):
    """Of the rectangles `rects` ([x0, y0, width, height] in axes coordinates), the first that the
    lines of `ax` cross least (their samples inside it): where an inset hides the least. The
    upper-left one for Figs 5-6; lower right when the pressure rises after the plateau (stepped rod)."""
    ax.get_ylim()  # the autoscaled limits, without drawing (a draw would shift the layout)
    to_axes = ax.transData + ax.transAxes.inverted()  # data to axes: the limits only
    counts = []
    for x0, y0, w, h in rects:
        n = 0
        for line in ax.get_lines():
            xy = to_axes.transform(np.column_stack([np.asarray(v, dtype=float) for v in line.get_data()]))
            n += int(np.sum((xy[:, 0] >= x0) & (xy[:, 0] <= x0 + w) & (xy[:, 1] >= y0) & (xy[:, 1] <= y0 + h)))
        counts.append(n)
    return rects[int(np.argmin(counts))]


def plateau_inset(ax, curves, exact, t_imp, dt_us, ylabel):
    """An inset in panel (a) over the plateau after the impact (20 to 250 steps after it), its y-range
    magnified to the ripple that is left there: central difference's undamped ringing, which gives
    its large NoP_p, is a few kPa and invisible at the scale of the impact. A curve still far off
    (Newmark's chatter) leaves the inset's frame, as in bulk_ylim. Nothing is drawn when every
    curve has settled (the velocity, held at 0 in contact)."""
    lo, hi = t_imp + 20 * dt_us, t_imp + 250 * dt_us
    te, ye = exact
    w = (te >= lo) & (te <= hi)
    if not np.any(w) or np.ptp(ye[w]) > 0:  # the inset is for a plateau of the exact solution
        return
    ylim, left_out = bulk_ylim(curves, exact, lo, hi, factor=0.01, pad=0.12)
    level = float(ye[w][0])
    if ylim is None or max(ylim[1] - level, level - ylim[0]) < 1e-4 * (abs(level) or 1.0):
        return
    half = max(ylim[1] - level, level - ylim[0])
    ins = ax.inset_axes(least_covering(ax, [[0.09, 0.47, 0.48, 0.43], [0.58, 0.08, 0.38, 0.29]]))
    for line in ax.get_lines():
        t, y = (np.asarray(v, dtype=float) for v in line.get_data())
        sel = (t >= lo - 5 * dt_us) & (t <= hi + 5 * dt_us)
        ins.plot(t[sel], y[sel], color=line.get_color(), ls=line.get_linestyle(), zorder=line.get_zorder(),
                 lw=0.8 if any(line.get_label().startswith(n) for n, _, _ in left_out) else 1.1)
    ins.set_xlim(lo, hi)
    ins.set_ylim(level - half, level + half)
    ins.tick_params(labelsize=7.5)
    unit = ylabel[ylabel.index("[") + 1:-1]
    ins.set_title(f"the plateau after impact (t [µs]), magnified: {num(level)} ± {num(round(half, 4))} {unit}"
                  + ("\n(" + ", ".join(n.split(" (")[0] for n, _, _ in left_out) + " leaves this frame)"
                     if left_out else ""), fontsize=8, pad=3)


def exact_pressure_jumps(h, t_imp, t_rel, margin):
    """The jumps of a history's exact pressure between the impact and the release, more than
    `margin` [µs] from either, as [(t [µs], before, after)]: the waves that reach the contact (from a
    step of a stepped rod, from the far end of a body). A jump sampled as the mean of its limits
    spans two samples: one jump."""
    p = h.data["exact_pressure"]
    t = h.t_us
    scale = np.nanmax(np.abs(p)) or 1.0
    changes = np.nonzero(np.abs(np.diff(p)) > 1e-6 * scale)[0]
    out = []
    k = 0
    while k < changes.size:
        i = changes[k]
        j = i
        while k + 1 < changes.size and changes[k + 1] == j + 1:  # the mean-of-limits sample
            k += 1
            j = changes[k]
        when = 0.5 * (t[i] + t[j + 1]) if j > i else t[i + 1]
        if t_imp + margin < when < t_rel - margin:
            out.append((when, float(p[i]), float(p[j + 1])))
        k += 1
    return out


def history_windows(hist, quantity, t_imp, t_rel, dt_us, max_windows=4):
    """The zoom windows of a history figure as [(what, lo, hi, title)], up to max_windows: the
    impact, each jump of the exact pressure in between (a wave from a step or a far end reaching the
    contact; none on the paper's rod), and the release if the run goes on after it (Figs 5-6).
    A velocity window at a pressure jump is left out when no curve's velocity moves there (a node
    held at v = 0 in contact); those jumps are returned as the second value, [(t, before, after)]."""
    ref = hist[0]
    t_end = float(ref.t_us[-1])
    windows = [("impact", t_imp - 6 * dt_us, t_imp + 45 * dt_us, f"zoom at impact, t = {t_imp:.1f} µs")]
    still = []
    jumps = exact_pressure_jumps(ref, t_imp, t_rel, 3 * dt_us)
    release_inside = t_rel + 15 * dt_us <= t_end
    room = max_windows - 1 - (1 if release_inside else 0)
    for when, before, after in jumps[:room]:
        # the numerical wave front is spread over some 40 steps before and after the exact one
        lo, hi = when - 40 * dt_us, min(when + 60 * dt_us, t_end)
        if quantity != "pressure":
            v0 = np.nanmax(np.abs(ref.data["exact_velocity"])) or 1.0
            moves = [np.ptp(h.data["velocity"][(h.t_us >= lo) & (h.t_us <= hi)]) > 1e-6 * v0 for h in hist]
            if not any(moves):
                still.append((when, before, after))
                continue
        windows.append((when, lo, hi, f"zoom at t = {when:.1f} µs, where the exact\npressure jumps from "
                                      f"{num(round(before, 3))} to {num(round(after, 3))} MPa"))
    if release_inside:
        # the pressure falls before the release; the velocity overshoots after it
        release = (t_rel - 85 * dt_us, t_rel + 15 * dt_us) if quantity == "pressure" else (t_rel - 15 * dt_us, t_rel + 85 * dt_us)
        windows.append(("release", *release, f"zoom at release, t = {t_rel:.1f} µs"))
    return windows, still


def history_figure(results_dir, out_dir, quantity, study="identical-dissipation", png=None, heading=None,
                   subject="at identical dissipation", scene_sep="; "):
    """Figs 5 and 6 (study 'identical-dissipation'), or the same layout for the histories of another
    list study: `png` and `heading` then name the figure, `subject` the comparison in its title.
    A scene of bodies (histories with per-contact columns) takes its scene from the study's results
    file and its exact reference from the chain's characteristics; the quantities are those of the
    primary contact."""
    folder, hist = load_histories(results_dir, study)
    if not hist:
        raise Skip(f"{folder}: no point-*.h5 files")
    ref = hist[0]
    bodies = any("." in k for k in ref.data)
    if quantity == "pressure":
        key, exact_key, ylabel, scale = "pressure", "exact_pressure", "contact pressure p [MPa]", 1.0
        name = png or "fig5_pressure_history.png"
        title = heading or "Fig. 5 — Time evolution of the contact pressure"
    else:
        key, exact_key, ylabel, scale = "velocity", "exact_velocity", "contact-node velocity v [mm/s]", 1.0
        name = png or "fig6_velocity_history.png"
        title = heading or "Fig. 6 — Time evolution of the velocity of the contact node"
    t_imp, t_rel = ref.jump_times()
    dt_us = float(ref.attrs.get("dt", np.median(np.diff(ref.data["t"])))) * 1e6
    windows, still = history_windows(hist, quantity, t_imp, t_rel, dt_us)

    fig = plt.figure(figsize=(11 if len(windows) <= 2 else 14, 7.6), layout="constrained")
    gs = fig.add_gridspec(2, len(windows), height_ratios=[1.15, 1])
    ax = fig.add_subplot(gs[0, :])
    zooms = [fig.add_subplot(gs[1, k]) for k in range(len(windows))]
    series = []
    # the roughest curves behind the smooth ones (total variation), the legend in point order
    variation = [np.nansum(np.abs(np.diff(h.data[key]))) for h in hist]
    rank = {id(h): r for r, h in enumerate(sorted(hist, key=lambda h: -variation[hist.index(h)]))}
    ind = ("eps_p", "nop_p") if quantity == "pressure" else ("eps_v", "nop_v")
    for a in [ax] + zooms:
        for h in hist:
            y = h.data[key] * scale
            label = h.label()
            if all(k in h.indicators for k in ind):
                label += (f": {INDICATOR_SYMBOLS[ind[0]]} = {h.indicators[ind[0]]:.4f},"
                          f" {INDICATOR_SYMBOLS[ind[1]]} = {num(h.indicators[ind[1]])}")
            a.plot(h.t_us, y, color=method_color(h.method), lw=1.0 if a is ax else 1.3, label=label,
                   zorder=2 + 0.1 * rank[id(h)])
        a.plot(ref.t_us, ref.data[exact_key] * scale, color=EXACT_COLOR, lw=1.3, ls="--",
               label="exact (chain: characteristics)" if bodies else "exact (d'Alembert)", zorder=3)
    for h in hist:
        series.append((method_label(h.method, h.attrs), h.t_us, h.data[key] * scale))
    exact = (ref.t_us, ref.data[exact_key] * scale)
    ax.set_xlim(0, ref.t_us[-1])
    ax.set_xlabel("t [µs]")
    ax.set_ylabel(ylabel)
    if any(w[0] == "release" for w in windows):
        ax.set_title("(a) the whole run; boxes: the zoomed windows")
    elif t_rel >= ref.t_us[-1] - 2 * dt_us:
        ax.set_title(f"(a) the whole run, to the exact release at its last step (t = {t_rel:.1f} µs); "
                     "boxes: the zoomed windows")
    else:
        ax.set_title("(a) the whole run, in contact to its end; boxes: the zoomed windows")
    if still:  # say why the pressure jumps have no velocity zoom
        ax.text(0.5, 0.72, "in contact, the contact node stays at v = 0 (to round-off) through the jumps of the "
                "exact pressure at t = " + ", ".join(f"{w:.1f}" for w, _, _ in still) + " µs: no zoom there",
                transform=ax.transAxes, ha="center", va="bottom", fontsize=8.5, color="0.2",
                bbox=dict(boxstyle="round,pad=0.3", facecolor="white", edgecolor="0.6", alpha=0.92))
    letters = "bcdefg"
    for z, (what, lo, hi, zoom_title), letter in zip(zooms, windows, letters):
        z.set_xlim(lo, hi)
        ylim, left_out = bulk_ylim(series, exact, lo, hi)
        if ylim:
            z.set_ylim(*ylim)
        if left_out:  # say so, with the range the curve reaches (panel (a) shows it whole)
            for line in z.get_lines():  # and draw it thin, behind the curves it would hide
                if line.get_label() in {name for name, _, _ in left_out} or any(
                        line.get_label().startswith(name + ":") for name, _, _ in left_out):
                    line.set_linewidth(0.8)
            unit = ylabel[ylabel.index("[") + 1:-1]
            note = "\n".join(f"{name} leaves the frame: {num(round(a, 2))} to {num(round(b, 2))} {unit}"
                              for name, a, b in left_out) + " (see (a))"
            z.text(0.98, 0.97, note, transform=z.transAxes, ha="right", va="top", fontsize=8,
                   color="0.15", zorder=6, bbox=dict(boxstyle="round,pad=0.3", facecolor="white",
                                                     edgecolor="0.6", alpha=0.92))
        z.set_xlabel("t [µs]")
        z.set_ylabel(ylabel)
        when = t_imp if what == "impact" else t_rel if what == "release" else what
        z.axvline(when, color="0.5", lw=0.8, ls=":", zorder=1)
        z.set_title(f"({letter}) {zoom_title}")
        _, connectors = ax.indicate_inset_zoom(z, edgecolor="0.3", alpha=0.9)
        for c in connectors:  # they would cross the figure: keep only the box
            c.set_visible(False)
    plateau_inset(ax, series, exact, t_imp, dt_us, ylabel)
    if quantity == "pressure" or not any(w[0] == "release" for w in windows):
        ax.legend(loc="upper right", framealpha=0.92)
    else:  # the velocity oscillates after the release: the empty band between 0 and −v0 before it
        ax.legend(loc="center left", bbox_to_anchor=(0.2, 0.40), framealpha=0.92, fontsize=8)
    results_path = Path(results_dir) / f"{study}.h5"
    if bodies and results_path.exists():  # a history file of a scene of bodies does not describe it
        scene = results_scene(Results(results_path))
    else:
        scene = scene_text({k: ref.attrs[k] for k in DEFAULT_SCENE if k in ref.attrs} | ({"dt": ref.attrs["dt"]} if "courant" not in ref.attrs and "dt" in ref.attrs else {}))
    fig.suptitle(f"{title} {subject}{scene_sep}{scene}")
    return [save(fig, out_dir, name)]


def fig5(results_dir, out_dir):
    return history_figure(results_dir, out_dir, "pressure")


def fig6(results_dir, out_dir):
    return history_figure(results_dir, out_dir, "velocity")


def stepped_rod_history(results_dir, out_dir, quantity):
    where = "at the wall"
    path = Path(results_dir) / "stepped-rod.h5"
    if path.exists():
        try:
            where = f"at the {contact_text(primary_contact(Results(path).plan.get('scene', {})))}"
        except Skip:
            pass
    what = "pressure" if quantity == "pressure" else "velocity of the contact node"
    return history_figure(results_dir, out_dir, quantity, "stepped-rod", f"fig_stepped_rod_{quantity}.png",
                          f"Stepped rod — time evolution of the {what} {where}",
                          "at identical dissipation (as Figs 5–6)", scene_sep="\n")


def fig_stepped_rod_pressure(results_dir, out_dir):
    return stepped_rod_history(results_dir, out_dir, "pressure")


def fig_stepped_rod_velocity(results_dir, out_dir):
    return stepped_rod_history(results_dir, out_dir, "velocity")


# ---------------------------------------------------------------------------------------------
# A user's model with many contacts: the total contact force (the block, examples/block)
# ---------------------------------------------------------------------------------------------


def relative_error(ref, y):
    """eq. 18 on any history: sum_i |ref - y| / sum_i |ref|."""
    den = np.nansum(np.abs(ref))
    return float(np.nansum(np.abs(ref - y)) / den) if den > 0 else np.nan


def model_histories(results_dir, name):
    """The per-point histories of a user model's list study, with the contacts' pressures:
    (results, [(point, attrs, {dataset: array})]) for the points of the results file."""
    r = load(results_dir, name)
    folder = find_history_dir(results_dir, name)
    out = []
    for k in range(r.status.size):
        path = folder / f"point-{k}.h5"
        if not path.exists():
            continue
        with h5py.File(path, "r") as f:
            attrs = {a: (text(f.attrs[a]) if isinstance(f.attrs[a], (bytes, str)) else f.attrs[a]) for a in f.attrs}
            data = {d: np.asarray(f[d][()], dtype=float) for d in f if isinstance(f[d], h5py.Dataset)}
        for key in ("t", "pressure"):
            if key not in data:
                raise Skip(f"{path}: dataset {key!r} missing (layout of `impactid simulate --history`)")
        out.append((k, attrs, data))
    if not out:
        raise Skip(f"{folder}: no point-*.h5 files of the points of {r.path}")
    return r, out


def contact_force(data, areas, prefix="pressure"):
    """The total contact force sum_k p_k·A_k of a history's '<prefix>.<contact>' datasets."""
    return sum(data[f"{prefix}.{c}"] * a for c, a in areas.items())


def fig_block_contact_force(results_dir, out_dir):
    name = "block-identical-dissipation"
    r, hist = model_histories(results_dir, name)
    areas_all = model_contact_areas(r)
    if not areas_all:
        raise Skip(f"{r.path}: the model's scene file (with the contacts' areas) is not found: "
                   f"{r.plan.get('scene', '?')} beside {text(r.attr('model_files', '?'))}")
    _, _, first = hist[0]
    contacts = sorted({d.split(".", 1)[1] for d in first if d.startswith("pressure.")})
    missing = [c for c in contacts if c not in areas_all]
    if not contacts or missing:
        raise Skip(f"{r.path}: the histories' contacts {', '.join(missing) or '(none)'} are not in the scene file")
    if not all(f"reference_pressure.{c}" in first for c in contacts):
        raise Skip(f"{r.path}: the histories have no reference_pressure.<contact> datasets")
    areas = {c: areas_all[c] for c in contacts}
    primary = model_primary_contact(r)
    force_unit, length, time_unit = model_units(r)
    p_unit = pressure_unit(force_unit, length)
    scale, t_unit = (1e6, "µs") if time_unit == "s" else (1.0, time_unit)
    methods = [text(a.get("method", "?")) for _, a, _ in hist]
    ref_t = first["t"] * scale
    ref_force = contact_force(first, areas, "reference_pressure")
    ref_p = first[f"reference_pressure.{primary}"] if primary and f"reference_pressure.{primary}" in first else None

    fig = plt.figure(figsize=(14.5, 9.4), layout="constrained")
    gs = fig.add_gridspec(2, 2, width_ratios=[2.3, 1])
    ax_f, ax_p = fig.add_subplot(gs[0, 0]), fig.add_subplot(gs[1, 0])
    zoom_f, zoom_p = fig.add_subplot(gs[0, 1]), fig.add_subplot(gs[1, 1])
    ax_p.sharex(ax_f)
    zoom_p.sharex(zoom_f)
    # the impact: from a few steps before the reference's first contact force to some 25 steps after
    dt = float(np.median(np.diff(ref_t)))
    on = np.nonzero(ref_force > 0)[0]
    t_imp = ref_t[on[0]] if on.size else ref_t[0]
    lo, hi = t_imp - 4 * dt, t_imp + 24 * dt
    # the roughest curves behind the smooth ones (total variation of the force), the legend in point order
    forces = [contact_force(d, areas) for _, _, d in hist]
    variation = [np.nansum(np.abs(np.diff(f))) for f in forces]
    order = np.argsort(np.argsort(-np.asarray(variation)))
    handles = []
    for (k, attrs, data), method, force, rank in zip(hist, methods, forces, order):
        color = method_color(method)
        label = f"{method_label(method, attrs)}: ε_F = {relative_error(ref_force, force):.4f}"
        if r.status[k] == 0 and r.has("eps_p") and r.has("nop_p"):
            label += (f"; {primary}: ε_p = {float(np.atleast_1d(r.data['eps_p'])[k]):.4f}, "
                      f"NoP_p = {num(np.atleast_1d(r.data['nop_p'])[k])}")
        elif r.status[k] != 0:
            label += f"; {STATUS_TEXT.get(int(r.status[k]), 'not ok')}"
        t = data["t"] * scale
        for ax, y in ((ax_f, force), (zoom_f, force), (ax_p, data["pressure"]), (zoom_p, data["pressure"])):
            line, = ax.plot(t, y, color=color, lw=1.1 if ax in (ax_f, ax_p) else 1.4, zorder=2 + 0.1 * rank,
                            label=label, marker="o" if ax in (zoom_f, zoom_p) else None, ms=2.5)
        handles.append(line)
    ref_label = f"reference: {model_reference_text(r).split(' (')[0]}"
    for ax, y in ((ax_f, ref_force), (zoom_f, ref_force), (ax_p, ref_p), (zoom_p, ref_p)):
        if y is not None:
            line, = ax.plot(ref_t, y, color=EXACT_COLOR, lw=1.4, ls="--", zorder=3, label=ref_label)
    handles.append(line)
    where = f"{contact_text(primary)}{middle_contact_text(r, primary)}"
    ax_f.set_title(f"(a) total contact force of the {len(contacts)} contacts, F = Σ p_k·A_k (the areas of the "
                   "scene file); boxes: the zooms")
    ax_p.set_title(f"(b) contact pressure p at the {where}, the primary contact")
    zoom_f.set_title("(c) F, zoom at impact (dots: the samples)")
    zoom_p.set_title(f"(d) p at {primary}, zoom at impact")
    for ax in (ax_f, zoom_f):
        ax.set_ylabel(f"total contact force F [{force_unit}]")
    for ax in (ax_p, zoom_p):
        ax.set_ylabel(f"contact pressure p [{p_unit}]")
        ax.set_xlabel(f"t [{t_unit}]")
    ax_f.set_xlim(0, ref_t[-1])
    zoom_f.set_xlim(lo, hi)
    for ax in (ax_f, zoom_f):
        ax.tick_params(labelbottom=False)
    for ax, z in ((ax_f, zoom_f), (ax_p, zoom_p)):
        _, connectors = ax.indicate_inset_zoom(z, edgecolor="0.3", alpha=0.9)
        for c in connectors:  # they would cross the figure: keep only the box
            c.set_visible(False)
    fig.legend(handles=handles, loc="lower center", ncol=2, frameon=False, fontsize=8.5,
               title="ε_F: eq. 18 on the total force F; ε_p, NoP_p: the study's indicators at " + str(primary)
               + " (eq. 18, number of peaks)", title_fontsize=8.5)
    fig.get_layout_engine().set(rect=(0, 0.11, 1, 0.89))
    fig.suptitle(f"2D elastic block dropped on a rigid plane — the five methods at identical dissipation "
                 f"(as Figs 5–6 on the rod)\n{results_scene(r)}\nReference: {model_reference_text(r)}")
    return [save(fig, out_dir, "block-contact-force.png")]


# ---------------------------------------------------------------------------------------------
# Figures 7 and 8: the indicators of the methods at identical dissipation
# ---------------------------------------------------------------------------------------------


def list_methods(results_dir, r, name="identical-dissipation"):
    """The method and parameters of each point of a list study, in point order."""
    n = r.status.size
    methods = [None] * n
    if r.has("method"):  # a per-point method column, if the file has one
        methods = [text(m) for m in np.atleast_1d(r.data["method"])]
    if any(m is None for m in methods):
        try:
            folder = find_history_dir(results_dir, name)
            for k in range(n):
                p = folder / f"point-{k}.h5"
                if p.exists() and methods[k] is None:
                    with h5py.File(p, "r") as f:
                        methods[k] = text(f.attrs.get("method", ""))
        except Skip:
            pass
    if any(m is None for m in methods):
        default = r.plan.get("method", {}).get("name", text(r.attr("method", "hht")))
        points = r.plan.get("study", {}).get("points", [])
        for k in range(n):
            if methods[k] is None:
                methods[k] = points[k].get("method", default) if k < len(points) else default
    params = []
    for k in range(n):
        p = {}
        for key, meta in r.meta.items():
            if text(meta.get("role", "")) == "parameter":
                v = np.atleast_1d(r.data[key])[k]
                p[key] = v
        params.append(p)
    return methods, params


def compare_figure(results_dir, out_dir, which):
    r = load(results_dir, "identical-dissipation")
    if r.dims != ["point"]:
        raise Skip(f"{r.path}: expected a list study (dimension 'point'), found {r.dims}")
    methods, params = list_methods(results_dir, r)
    if which == "pressure":
        keys = [("eps_p", "ε_p [−]", "(a) relative error ε_p (eq. 18)"), ("nop_p", "NoP_p [−]", "(b) number of peaks NoP_p")]
        name, title = "fig7_compare_pressure.png", "Fig. 7 — Comparison of the methods: contact pressure"
    else:
        keys = [("eps_v", "ε_v [−]", "(a) relative error ε_v (eq. 18)"), ("nop_v", "NoP_v [−]", "(b) number of peaks NoP_v")]
        name, title = "fig8_compare_velocity.png", "Fig. 8 — Comparison of the methods: velocity of the contact node"
    n = len(methods)
    labels = [method_label(m, p, sep="\n") for m, p in zip(methods, params)]
    colors = [method_color(m) for m in methods]
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.2), layout="constrained")
    xpos = np.arange(n)
    for ax, (key, ylabel, sub) in zip(axes, keys):
        if not r.has(key):
            ax.text(0.5, 0.5, f"{key} not in {r.path.name}", transform=ax.transAxes, ha="center")
            continue
        v = np.where(r.status == 0, np.asarray(r.data[key], dtype=float), np.nan)
        bars = ax.bar(xpos, np.nan_to_num(v), color=colors, edgecolor="black", lw=0.6, width=0.7, zorder=3)
        top = np.nanmax(v) if np.any(np.isfinite(v)) else 1.0
        for i, (b, val) in enumerate(zip(bars, v)):
            if np.isfinite(val):
                s = f"{val:.4f}" if key.startswith("eps") else f"{int(round(val))}"
                ax.text(b.get_x() + b.get_width() / 2, val + 0.015 * top, s, ha="center", va="bottom", fontsize=9)
            else:
                code = int(r.status[i])
                ax.text(b.get_x() + b.get_width() / 2, 0.02 * top, STATUS_TEXT.get(code, "not ok").replace(": ", ":\n"),
                        ha="center", va="bottom", fontsize=8, color=NOT_OK_COLOR, rotation=90)
        bounds = parse_thresholds(r).get(key, (None, None))
        if bounds[1] is not None:
            top = max(top, bounds[1])
        threshold_lines(ax, r, key, ylabel.split(" ")[0])
        headroom = 1.12
        if ax.get_legend_handles_labels()[0]:
            ax.legend(loc="upper left", framealpha=0.92)
            headroom = 1.3  # the legend above the tallest bar and its value
        ax.set_ylim(0, headroom * top)
        ax.set_xticks(xpos, labels, fontsize=8.5)
        ax.set_ylabel(ylabel)
        ax.set_title(sub)
        ax.grid(True, axis="y")
        ax.grid(False, axis="x")
    scene = results_scene(r)
    fig.suptitle(f"{title}, identical dissipation; {scene}\n{IDENTICAL_DISSIPATION}", fontsize=10)
    # the practical points, under the figure whose indicators the thresholds are on (Fig. 7 for
    # the pressure thresholds of the plans); not under the other, whose bars they do not judge
    if r.has("practical") and practical_thresholds(r) and any(k in parse_thresholds(r) for k, _, _ in keys):
        pr = np.asarray(r.data["practical"], dtype=float) == 1
        names = [method_label(m, p) for m, p, ok in zip(methods, params, pr) if ok]
        fig.text(0.5, 0.005, f"Practical ({practical_thresholds(r)}): " + ("; ".join(names) if names else "none"),
                 ha="center", va="bottom", fontsize=9)
        fig.get_layout_engine().set(rect=(0, 0.04, 1, 0.96))
    return [save(fig, out_dir, name)]


def fig7(results_dir, out_dir):
    return compare_figure(results_dir, out_dir, "pressure")


def fig8(results_dir, out_dir):
    return compare_figure(results_dir, out_dir, "velocity")


# ---------------------------------------------------------------------------------------------
# Spectral analysis
# ---------------------------------------------------------------------------------------------


def load_spectral(results_dir):
    path = Path(results_dir) / "spectral.h5"
    if not path.exists():
        raise Skip(f"{path} not found; produce it with: {run_command('spectral')}")
    s = {}
    with h5py.File(path, "r") as f:
        fmt = text(f.attrs.get("format", ""))
        if fmt != "impactid-spectral-1":
            raise Skip(f"{path}: format is {fmt!r}, not 'impactid-spectral-1'")
        s["attrs"] = {k: f.attrs[k] for k in f.attrs}
        for k in f:
            if isinstance(f[k], h5py.Dataset):
                v = f[k][()]
                s[k] = np.array(texts(v), dtype=object) if f[k].dtype.kind in ("S", "O", "U") else np.asarray(v)
    # the method names: `method_name` (strings; `method` is then the dimension 0..M-1), or
    # `method` itself when it holds strings
    if "method_name" in s:
        s["method"] = s["method_name"]
    elif "method" in s and s["method"].dtype != object:
        s["method"] = s.get("method_label")
    for key in ("omega_dt", "method", "spectral_radius", "period_error"):
        if key not in s or s[key] is None:
            raise Skip(f"{path}: dataset {key!r} missing")
    return path, s


def pretty_spectral_label(method, label):
    """'hht alpha=-0.3 delta=0.45' -> 'HHT-α (α = −0.3, δ = 0.45)'; other labels unchanged."""
    words = label.split()
    if not words or words[0] != method or not all("=" in w for w in words[1:]):
        return label
    params = {}
    for w in words[1:]:
        key, value = w.split("=", 1)
        try:
            params[key] = float(value)
        except ValueError:
            params[key] = value
    out = method_label(method, params)
    if method == "hht" and "alpha" in params and "delta" not in params:
        out = out[:-1] + ", δ = −α: eq. 15)" if out.endswith(")") else out + " (δ = −α: eq. 15)"
    return out


def spectral_styles(methods):
    """A colour per method and, for repeats of a method, different line styles."""
    seen = {}
    styles = []
    dashes = ["-", "--", "-.", ":"]
    for m in methods:
        k = seen.get(m, 0)
        seen[m] = k + 1
        styles.append((method_color(m), dashes[k % len(dashes)]))
    return styles


def fig_spectral(results_dir, out_dir):
    path, s = load_spectral(results_dir)
    W = np.asarray(s["omega_dt"], dtype=float)
    methods = [text(m) for m in s["method"]]
    labels = [pretty_spectral_label(m, text(l)) for m, l in zip(methods, s.get("method_label", s["method"]))]
    styles = spectral_styles(methods)
    ref = s["attrs"].get("omega_dt_reference")
    has_map = all(k in s for k in ("alpha", "delta", "stable"))
    has_dmin = "alpha" in s and ("delta_min_period_error_limit" in s or "delta_min_period_error" in s)
    fig, axs = plt.subplots(2, 3, figsize=(16.5, 9.8), layout="constrained")
    (ax_rho, ax_xi, ax_pe), (ax_dmin, ax_map, ax_key) = axs
    ref_label = f"Ω = {num(float(ref))}: the reference Ω of (d)" if ref is not None else None
    method_handles = []

    # (a) spectral radius
    for i, (lab, (c, ls)) in enumerate(zip(labels, styles)):
        rho = np.asarray(s["spectral_radius"][i], dtype=float)
        extra = []
        if "rho_inf" in s and not np.isnan(s["rho_inf"][i]):
            ri = float(s["rho_inf"][i])
            extra.append("ρ∞ = ∞" if ri > 1e6 else f"ρ∞ = {ri:.3g}" if ri > 1e-6 else "ρ∞ = 0")
        if "period_error_coefficient" in s and np.isfinite(s["period_error_coefficient"][i]):
            extra.append(f"c = {num(round(float(s['period_error_coefficient'][i]), 4))}")
        method_handles += ax_rho.semilogx(W, rho, color=c, ls=ls, lw=1.6,
                                          label=lab + (f":  {', '.join(extra)}" if extra else ""))
    ax_rho.set_ylim(0, 1.12)
    ax_rho.axhline(1, color="0.4", lw=0.7)
    ax_rho.set_ylabel("spectral radius ρ [−]")
    ax_rho.set_title("(a) spectral radius of the amplification matrix")
    if any(m == "cdm" for m in methods):
        ax_rho.axvline(2, color=method_color("cdm"), lw=0.8, ls=":")
        ax_rho.text(2.3, 1.015, "central difference:\nρ > 1 for Ω > 2", color="0.2", fontsize=8, va="bottom")

    # (b) algorithmic damping ratio, log-log: its slope at small Ω is the order of the dissipation
    if "damping_ratio" in s:
        xi_all = np.asarray(s["damping_ratio"], dtype=float)
        zero = []
        for i, (lab, (c, ls)) in enumerate(zip(labels, styles)):
            if np.any(np.isfinite(xi_all[i])) and np.nanmax(np.abs(xi_all[i])) < 1e-12:
                zero.append(lab.split(" (")[0])  # round-off around 0: central difference
                continue
            ax_xi.loglog(W, np.where(xi_all[i] > 0, xi_all[i], np.nan), color=c, ls=ls, lw=1.6)
        pos = xi_all[np.isfinite(xi_all) & (xi_all > 1e-12)]
        if pos.size:
            ax_xi.set_ylim(max(pos.min(), 1e-6), 2 * pos.max())
        if zero:
            ax_xi.text(0.98, 0.03, f"{', '.join(zero)}: " + r"$\bar\xi$ = 0 (no dissipation), not on the log axis",
                       transform=ax_xi.transAxes, ha="right", va="bottom", fontsize=8, color="0.2")
        ax_xi.set_ylabel(r"algorithmic damping ratio $\bar\xi$ [−]")
        ax_xi.set_title(r"(b) algorithmic damping ratio $\bar\xi$ (slope 1: first order; 3: second)")
    else:
        ax_xi.text(0.5, 0.5, f"no 'damping_ratio' in {path.name}", transform=ax_xi.transAxes, ha="center")

    # (c) period error over Ω²: on log-log axes |PE| ≈ c·Ω² makes the methods one line; divided by
    # Ω² on a linear axis each method is a level, c, at small Ω, and the sign is kept
    pe_all = np.asarray(s["period_error"], dtype=float)
    for i, (lab, (c, ls)) in enumerate(zip(labels, styles)):
        ax_pe.semilogx(W, pe_all[i] / W**2, color=c, ls=ls, lw=1.6)
    ax_pe.axhline(0, color="0.4", lw=0.7)
    ax_pe.set_ylabel(r"$(\bar T - T)\,/\,(T\,Ω^2)$ [−]")
    ax_pe.set_title(r"(c) relative period error over Ω²: c at Ω → 0 ($\bar T - T ≈ c\,Ω^2\,T$)")

    for a in (ax_rho, ax_xi, ax_pe):
        if ref is not None:
            a.axvline(float(ref), color="0.3", lw=0.9, ls="--", zorder=1)
        a.set_xlim(W.min(), W.max())
        a.set_xlabel("Ω = ω·Δt [−]")
        a.grid(True, which="major", alpha=0.3)
    # one key for the methods of (a)–(c), in the sixth slot
    ax_key.axis("off")
    if ref_label:
        method_handles.append(Line2D([], [], color="0.3", lw=0.9, ls="--", label=ref_label))
    ax_key.legend(handles=method_handles, loc="center", fontsize=8.5, frameon=False,
                  title="(a)–(c): the methods; ρ∞ = ρ(Ω → ∞),\nc = the period error coefficient of (c)",
                  title_fontsize=8.5)

    # (c) the delta of minimal period error over alpha
    if has_dmin:
        A = np.asarray(s["alpha"], dtype=float)
        a_line = np.linspace(A.min(), A.max(), 50)
        if "delta_min_period_error_limit" in s:
            ax_dmin.plot(A, s["delta_min_period_error_limit"], color=method_color("hht"), lw=5, alpha=0.45,
                         label="δ minimising the period error, Ω → 0")
        ax_dmin.plot(a_line, -1.5 * a_line, color="black", lw=1.2, ls="--", label="δ = −1.5·α (eq. 19)")
        ax_dmin.plot(a_line, -a_line, color="black", lw=1.2, ls=":", label="δ = −α (eq. 15; stability limit)")
        if "delta_min_period_error" in s:
            ax_dmin.plot(A, s["delta_min_period_error"], color="#D55E00", lw=1.6, ls="--", marker="o", ms=2.5,
                         label=f"δ minimising the period error at Ω = {num(float(ref)) if ref is not None else '?'}")
        ax_dmin.set_xlabel("α [−]")
        ax_dmin.set_ylabel("δ [−]")
        ax_dmin.set_title("(d) HHT-α: the δ of minimal period error")
        ax_dmin.legend(loc="upper right", fontsize=8)
    else:
        ax_dmin.set_visible(False)

    # (d) the HHT stability map
    if has_map:
        A = np.asarray(s["alpha"], dtype=float)
        D = np.asarray(s["delta"], dtype=float)
        st = np.asarray(s["stable"], dtype=float)
        if st.shape != (A.size, D.size) and st.shape == (D.size, A.size):
            st = st.T
        ae, de = cell_edges(A), cell_edges(D)
        cmap = mcolors.ListedColormap(["0.80", "#d9ecf7"])
        ax_map.grid(False)
        ax_map.pcolormesh(de, ae, st, cmap=cmap, vmin=0, vmax=1, shading="flat", zorder=0)
        uns = np.ma.masked_where(st != 0, st)
        ax_map.pcolor(de, ae, uns, hatch="///", alpha=0.0, zorder=1)
        hs = [Patch(facecolor="#d9ecf7", edgecolor="0.5", label="stable: ρ ≤ 1 for all Ω ≤ "
                    f"{num(float(s['attrs'].get('stability_omega_max', np.nan)))}"),
              Patch(facecolor="0.80", edgecolor="0.5", hatch="///", label="unstable")]
        hs += hht_lines(ax_map, D, A, paper_stage=False)
        # the points where simulation ended not ok, for comparison
        try:
            rr = load(results_dir, "hht-delta-alpha")
            x, y, stt = grid_2d(rr, "status")
            xe, ye = cell_edges(x), cell_edges(y)
            bad = (stt > 0).astype(float)
            fine = np.kron(bad, np.ones((4, 4)))
            xf = np.interp(np.arange(fine.shape[1]) / 4 + 0.125, np.arange(len(xe)), xe)
            yf = np.interp(np.arange(fine.shape[0]) / 4 + 0.125, np.arange(len(ye)), ye)
            ax_map.contour(xf, yf, fine, levels=[0.5], colors=["#D55E00"], linewidths=1.8, zorder=5)
            hs.append(Line2D([], [], color="#D55E00", lw=1.8,
                             label="edge of the not-ok runs of hht-delta-alpha.h5 (energy growth)"))
        except Skip:
            pass
        ax_map.set_xlim(de.min(), de.max())
        ax_map.set_ylim(ae.min(), ae.max())
        ax_map.set_xlabel("δ [−]")
        ax_map.set_ylabel("α [−]")
        ax_map.set_title("(e) HHT-α stability (β, γ from δ, eq. 13)")
        ax_map.grid(False)
        ax_map.legend(handles=hs, loc="upper right", fontsize=7.5, framealpha=0.92)
    else:
        ax_map.set_visible(False)
    fig.suptitle("Spectral analysis on the undamped oscillator ü + ω²u = 0 (no contact)")
    return [save(fig, out_dir, "fig_spectral.png")]


# ---------------------------------------------------------------------------------------------
# The stability map of simulations beside the spectral prediction
# ---------------------------------------------------------------------------------------------


def predicted_stable(results_dir, alpha, delta):
    """HHT stability over (alpha, delta) as the spectral study predicts it: the `stable` map of
    spectral.h5 at the nearest grid point (it is computed by core/amplification.hpp, not by a
    simulation), or, without that file, the closed form δ ≥ −α. Returns (map[a, d], source)."""
    try:
        _, s = load_spectral(results_dir)
        A, D = np.asarray(s["alpha"], dtype=float), np.asarray(s["delta"], dtype=float)
        st = np.asarray(s["stable"], dtype=float)
        if st.shape != (A.size, D.size) and st.shape == (D.size, A.size):
            st = st.T
        ia = np.abs(A[None, :] - alpha[:, None]).argmin(axis=1)
        idd = np.abs(D[None, :] - delta[:, None]).argmin(axis=1)
        if np.max(np.abs(A[ia] - alpha)) > 1e-9 or np.max(np.abs(D[idd] - delta)) > 1e-9:
            raise Skip("grids differ")
        return st[np.ix_(ia, idd)] > 0.5, "spectral.h5 (ρ ≤ 1 up to Ω = " + \
            f"{num(float(s['attrs'].get('stability_omega_max', np.nan)))})"
    except (Skip, KeyError):
        return delta[None, :] >= -alpha[:, None] - 1e-12, "δ ≥ −α (closed form)"


def fig_stability_map(results_dir, out_dir):
    r = load(results_dir, "stability-map")
    if sorted(r.dims) != sorted(["courant", "alpha", "delta"]):
        raise Skip(f"{r.path}: expected the grid axes courant × alpha × delta, found {r.dims}")
    order = [r.dims.index(d) for d in ("courant", "alpha", "delta")]
    status = np.transpose(np.asarray(r.data["status"], dtype=float), order)
    C, A, D = (np.asarray(r.data[d], dtype=float) for d in ("courant", "alpha", "delta"))
    stable, source = predicted_stable(results_dir, A, D)
    # 0: ok and predicted stable; 1: not ok and predicted unstable (agreement);
    # 2: ok although predicted unstable; 3: not ok although predicted stable; −1: not run
    colors = ["#d9ecf7", "0.72", "#F0B000", CHATTER_COLOR]
    labels = ["ok, predicted stable", "unstable, predicted unstable",
              "ok although predicted unstable", "unstable although predicted stable"]
    cmap = mcolors.ListedColormap(colors)
    cmap.set_bad("white")
    ncol = min(4, C.size)
    nrow = int(np.ceil(C.size / ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(3.4 * ncol, 3.1 * nrow + 0.9), squeeze=False,
                             sharex=True, sharey=True)
    de, ae = cell_edges(D), cell_edges(A)
    for k, ax in enumerate(axes.flat):
        if k >= C.size:
            ax.set_visible(False)
            continue
        st = status[k]
        ok = st == 0
        cls = np.where(stable, np.where(ok, 0, 3), np.where(ok, 2, 1)).astype(float)
        cls[st < 0] = np.nan
        ax.grid(False)
        ax.pcolormesh(de, ae, np.ma.masked_invalid(cls), cmap=cmap, vmin=-0.5, vmax=3.5, shading="flat")
        line = np.linspace(ae.min(), ae.max(), 50)
        ax.plot(-line, line, color="black", lw=1.0, ls=":")
        n_dis = int(np.sum((cls == 2) | (cls == 3)))
        ax.set_title(f"Courant {num(C[k])}: {n_dis} disagree", fontsize=9)
        ax.set_xlim(de.min(), de.max())
        ax.set_ylim(ae.min(), ae.max())
        if k % ncol == 0:
            ax.set_ylabel("α [−]")
        if k // ncol == nrow - 1:
            ax.set_xlabel("δ [−]")
    handles = [Patch(facecolor=c, edgecolor="0.5", label=l) for c, l in zip(colors, labels)]
    handles.append(Line2D([], [], color="black", ls=":", lw=1.0, label="δ = −α (eq. 15; the stability edge)"))
    fig.legend(handles=handles, loc="lower center", ncol=3, fontsize=8, frameon=False)
    fig.suptitle(f"HHT-α on the rod: simulated status over (δ, α) at each Courant number, beside the "
                 f"prediction of {source}\n(orange: slow growth near the edge not caught in the horizon, "
                 f"or below the lowest mode; red: chattering on the wall — plans/README.md)", fontsize=9.5)
    fig.tight_layout(rect=(0, 0.07, 1, 0.95))
    return [save(fig, out_dir, "fig_stability_map.png")]


# ---------------------------------------------------------------------------------------------
# Work-precision: wall time against the error of every method over mesh and Courant number
# ---------------------------------------------------------------------------------------------

COURANT_MARKERS = ["o", "s", "^", "D", "v", "P", "X", "<", ">"]


def frontier(t, y):
    """The points of (t, y) that no faster point beats: the smallest y reached in time t or less,
    in order of t (a Pareto front; both lower is better)."""
    keep = np.isfinite(t) & np.isfinite(y)
    t, y = t[keep], y[keep]
    order = np.argsort(t, kind="stable")
    out, best = [], np.inf
    for k in order:
        if y[k] < best:
            best = y[k]
            out.append(k)
    return t[out], y[out]


def unstable_band(band, times, colors, label):
    """The grey strip over a panel (axes `band`, sharing its time axis) with an × per run that is not
    ok, at its wall time in the method's colour: its indicators are NaN, only its time is known."""
    band.set_facecolor("0.9")
    band.set_ylim(0, 1)
    band.set_yticks([])
    band.grid(False)
    band.tick_params(axis="x", which="both", labelbottom=False, length=0)
    band.set_ylabel("not ok", rotation=0, ha="right", va="center", fontsize=9)
    for t, c in zip(times, colors):
        band.plot([t], [0.5], "x", color=c, ms=7, mew=2.0, zorder=5)
    band.text(0.99, 0.5, label, transform=band.transAxes, ha="right", va="center", fontsize=7.5, color="0.25")


def fig_work_precision(results_dir, out_dir):
    return work_precision_figure(results_dir, out_dir, "work-precision", "fig_work_precision.png")


def fig_block_work_precision(results_dir, out_dir):
    return work_precision_figure(results_dir, out_dir, "block-work-precision", "block-work-precision.png",
                                 "Work–precision on the 2D elastic block dropped on a rigid plane (GetFEM model)")


def work_precision_figure(results_dir, out_dir, name, png, heading="Work–precision"):
    """The work-precision figure of the results file `name`.h5 (study kind 'work-precision'):
    wall time against ε_p, ε_v and NoP_p. On the rod the thin lines join the meshes of one Courant
    number; on a user's model (one mesh: `elements` is its DOF count) they join the Courant numbers
    of one method, its indicators are at the primary contact and measured against the model's
    converged reference, which the title names."""
    r = load(results_dir, name)
    dims = ("method", "elements", "courant")
    if sorted(r.dims) != sorted(dims):
        raise Skip(f"{r.path}: expected the axes method × elements × courant (study kind "
                   f"'work-precision'), found {r.dims}")
    if not r.has("wall_time_s"):
        raise Skip(f"{r.path}: no 'wall_time_s' column")
    order = [r.dims.index(d) for d in dims]

    def cube(key):
        return np.transpose(np.asarray(r.data[key], dtype=float), order)

    status = np.transpose(r.status, order)
    t_ms = cube("wall_time_s") * 1e3
    M, E, C = (np.asarray(r.data[d], dtype=float) for d in dims)
    names, labels = [], []
    for i, m in enumerate(M):
        raw = text(r.attr(f"method_label_{int(m)}", r.attr(f"method_label_{i}", f"method {i}")))
        names.append(raw.split()[0] if raw.split() else raw)
        labels.append(pretty_spectral_label(names[-1], raw))
    colors = [method_color(n) for n in names]
    markers = [COURANT_MARKERS[k % len(COURANT_MARKERS)] for k in range(C.size)]
    model = is_model_results(r)
    primary = model_primary_contact(r) if model else None
    at = f"{primary} " if primary else ""
    one_mesh = E.size == 1  # a model: the thin lines join its Courant numbers instead
    mesh_text = f"{num(E[0])} DOFs" if model else f"n = {num(E.min())}–{num(E.max())}"
    panels = [(k, sym) for k, sym in (("eps_p", "ε_p"), ("eps_v", "ε_v"), ("nop_p", "NoP_p")) if r.has(k)]
    if not panels:
        raise Skip(f"{r.path}: none of eps_p, eps_v, nop_p")
    done = status >= 0
    bad = status > 0
    fig = plt.figure(figsize=(5.4 * len(panels), 6.0), layout="constrained")
    gs = fig.add_gridspec(2 if np.any(bad) else 1, len(panels), height_ratios=[1, 12] if np.any(bad) else [1])
    for n, (key, sym) in enumerate(panels):
        ax = fig.add_subplot(gs[-1, n])
        y = np.where(status == 0, cube(key), np.nan)
        y = np.where(y > 0, y, np.nan)  # a log axis; NoP_p = 0 (no peak) cannot be drawn on it
        zeros = int(np.sum((status == 0) & (cube(key) <= 0)))
        for i in range(M.size):
            if one_mesh:  # one thin line per method: its Courant numbers
                ax.plot(t_ms[i, 0, :], y[i, 0, :], "-", color=colors[i], lw=0.8, alpha=0.45, zorder=2)
            for k in range(C.size):  # one thin line per Courant number: the meshes, coarse to fine
                if not one_mesh:
                    ax.plot(t_ms[i, :, k], y[i, :, k], "-", color=colors[i], lw=0.8, alpha=0.45, zorder=2)
                ax.plot(t_ms[i, :, k], y[i, :, k], markers[k], color=colors[i], mec="white", mew=0.5, ms=5,
                        ls="none", zorder=3)
            if key.startswith("eps"):  # fewer peaks is not more accurate: no frontier of NoP
                ft, fy = frontier(t_ms[i].ravel(), y[i].ravel())
                ax.plot(ft, fy, "-", color=colors[i], lw=2.6, alpha=0.85, zorder=4, solid_capstyle="round")
        ax.set_xscale("log")
        ax.set_yscale("log")
        fin = y[np.isfinite(y)]
        if fin.size:
            lo, hi = np.log10(fin.min()), np.log10(fin.max())
            span = max(hi - lo, 0.3)
            full = span / 0.92
            ax.set_ylim(10 ** (lo - 0.04 * full), 10 ** (lo - 0.04 * full + full))
        if np.any(bad):
            ii, jj, kk = np.nonzero(bad)
            who = "; ".join(f"{labels[i].split(' (')[0]} at Courant {', '.join(num(c) for c in C[np.any(bad[i], axis=0)])}"
                            for i in range(M.size) if np.any(bad[i]))
            band = fig.add_subplot(gs[0, n], sharex=ax)
            runs_text = f"{int(bad.sum())} run{'' if bad.sum() == 1 else 's'}"
            unstable_band(band, t_ms[ii, jj, kk], [colors[i] for i in ii], f"{runs_text}, no {sym}: {who}")
        tt = t_ms[done & np.isfinite(t_ms)]
        if tt.size:
            ax.set_xlim(tt.min() / 1.6, tt.max() * 1.6)
        if zeros:
            ax.text(0.99, 0.02, f"{zeros} ok runs with {sym} = 0 not on the log axis", transform=ax.transAxes,
                    ha="right", va="bottom", fontsize=7.5, color="0.25")
        log_axis_plain(ax.xaxis)
        if key.startswith("nop"):
            if fin.size and fin.max() / fin.min() < 30:  # less than 1.5 decades: more than one label
                ax.yaxis.set_major_locator(mticker.LogLocator(subs=(1.0, 2.0, 5.0)))
            log_axis_plain(ax.yaxis)
        ax.grid(True, which="major", alpha=0.3)
        ax.set_xlabel("wall time [ms] (fastest of the repeats, one thread)")
        ax.set_ylabel(f"{sym} [−]")
        what = f"number of peaks of the {at}contact pressure" if key == "nop_p" else \
            f"relative error of the {at}{'contact pressure' if key == 'eps_p' else 'contact-node velocity'} (eq. 18)"
        (band if np.any(bad) else ax).set_title(f"({'abc'[n]}) {sym}: {what}", fontsize=9.5)
    keys = [[Line2D([], [], color=c, lw=2.6, label=l) for c, l in zip(colors, labels)],
            [Line2D([], [], color="0.45", marker=mk, mec="white", ls="none", ms=6, label=f"Courant {num(c)}")
             for mk, c in zip(markers, C)],
            [Line2D([], [], color="0.45", lw=0.8, alpha=0.6,
                    label=f"thin line: one method, Courant {num(C.max())} → {num(C.min())}, left to right" if one_mesh
                    else f"thin line: one Courant number, n = {num(E.min())} → {num(E.max())} elements, left to right"),
             Line2D([], [], color="0.45", lw=2.6, alpha=0.85,
                    label="thick line (ε panels): the method's frontier,\nthe smallest error reached in that time or less")]]
    if np.any(bad):
        keys[2].append(Line2D([], [], color="0.3", marker="x", mew=2.0, ms=7, ls="none",
                              label="× on the grey strip: a run that is not ok (unstable\nor failed), at its wall time until it stopped"))
    # More than five methods: their key in two columns, so that it fits under the panels.
    for handles, x, ncol in zip(keys, (0.2, 0.43, 0.7), (1 if M.size <= 5 else 2, 2, 1)):
        fig.legend(handles=handles, loc="upper center", bbox_to_anchor=(x, 0.15), ncol=ncol, fontsize=8,
                   frameon=False)
    fig.get_layout_engine().set(rect=(0, 0.16, 1, 0.84))
    scene = results_scene(r)
    timing = ""
    if r.has("wall_time_max_s"):
        ratio = cube("wall_time_max_s") / cube("wall_time_s")
        ratio = ratio[done & np.isfinite(ratio)]
        if ratio.size:
            timing = (f"; slowest/fastest repeat: median {np.median(ratio):.2f}, at most {ratio.max():.1f}")
    repeats = float(r.attr("repeats", np.nan))
    if repeats > 1:
        timing = f"the fastest of {num(repeats)} runs{timing}"
    else:
        timing = "one run each" if repeats == 1 else "the fastest of the repeats"
    if model:  # a long scene: a line of its own, and the reference under it
        scene = f"\n{scene}, Courant {num(C.min())}–{num(C.max())}\nReference: {model_reference_text(r)}."
    else:
        scene = f" {scene}, {mesh_text}, Courant {num(C.min())}–{num(C.max())}"
    fig.suptitle(f"{heading}: wall time against accuracy, each method at its recommended parameters;{scene}\n"
                 f"Lower left is better: at a time budget, the lowest curve is the most accurate method. Wall time: "
                 f"{timing}.", fontsize=10)
    return [save(fig, out_dir, png)]


# ---------------------------------------------------------------------------------------------
# The NLopt search over the HHT surface
# ---------------------------------------------------------------------------------------------


def objective_text(objective):
    if isinstance(objective, dict):
        return " + ".join(f"{num(w)}·{INDICATOR_SYMBOLS.get(k, k)}" if w != 1 else INDICATOR_SYMBOLS.get(k, k)
                          for k, w in objective.items())
    return INDICATOR_SYMBOLS.get(str(objective), str(objective))


def draw_evaluations(ax, o, best_ms=20):
    """The evaluations of an optimisation over (δ, α), in order, and its best point. Returns handles."""
    d = np.asarray(o.data["delta"], dtype=float)
    a = np.asarray(o.data["alpha"], dtype=float)
    feas = np.asarray(o.data.get("feasible", np.ones_like(d)), dtype=float) == 1
    ok = o.status == 0
    handles = []
    ax.plot(d, a, "-", color="white", lw=0.8, alpha=0.9, zorder=5)
    handles += ax.plot(d[feas], a[feas], "o", mfc="white", mec="black", ms=5.5, zorder=6, ls="none",
                       label=f"feasible evaluation ({int(feas.sum())})")
    handles += ax.plot(d[~feas & ok], a[~feas & ok], "o", mfc="0.15", mec="white", ms=5.5, zorder=6, ls="none",
                       label=f"infeasible evaluation ({int((~feas & ok).sum())})")
    if np.any(~ok):
        handles += ax.plot(d[~ok], a[~ok], "x", color=NOT_OK_COLOR, ms=7, mew=2, zorder=6, ls="none",
                           label=f"not ok ({int((~ok).sum())})")
    bd, ba = o.attr("best_delta"), o.attr("best_alpha")
    if bd is not None and ba is not None:
        lab = f"best: δ = {num(round(float(bd), 4))}, α = {num(round(float(ba), 4))}"
        for key in ("eps_p", "nop_p"):
            v = o.attr(f"best_{key}")
            if v is not None:
                lab += f", {INDICATOR_SYMBOLS[key]} = {num(round(float(v), 4))}"
        handles += ax.plot([float(bd)], [float(ba)], "*", ms=best_ms, color="#F0E442", mec="black", mew=1.2,
                           zorder=7, ls="none", label=lab, clip_on=False)
    return handles


def fig_optimize(results_dir, out_dir):
    o = load(results_dir, "hht-optimize")
    for key in ("delta", "alpha"):
        if not o.has(key):
            raise Skip(f"{o.path}: no {key!r} column: the figure needs a search over δ and α")
    try:
        r = load(results_dir, "hht-delta-alpha")
    except Skip as why:
        raise Skip(f"the ε_p surface is missing: {why}")
    fig, ax = plt.subplots(figsize=(9.0, 6.8), layout="constrained")
    x, y, z, st = hht_map(ax, r, "eps_p", "log", "ε_p [−] (the grid of hht-delta-alpha.h5)", fig)
    handles = hht_lines(ax, x, y, paper_stage=False)
    # each constraint on an indicator of the grid, as a contour of the grid
    study = o.plan.get("study", {})
    constraint_text = []
    stroke = [mpatheffects.withStroke(linewidth=3.4, foreground="white")]
    for key, bounds in study.get("constraints", {}).items():
        sym = INDICATOR_SYMBOLS.get(key, key)
        for side, op in (("min", "≥"), ("max", "≤")):
            if side not in bounds:
                continue
            limit = float(bounds[side])
            constraint_text.append(f"{sym} {op} {num(limit)}")
            if not r.has(key):
                continue
            _, _, grid = grid_2d(r, key)
            grid = np.where(st == 0, grid, np.nan)
            level = limit + (0.5 if key.startswith("nop") and side == "max" else -0.5 if key.startswith("nop") else 0)
            if np.nanmin(grid) < level < np.nanmax(grid):
                cs = ax.contour(x, y, grid, levels=[level], colors=["black"], linewidths=1.6, linestyles="-.",
                                zorder=4)
                for c in cs.collections:  # matplotlib 3.6: a ContourSet is not an Artist
                    c.set_path_effects(stroke)
                handles.append(Line2D([], [], color="black", lw=1.6, ls="-.", path_effects=stroke,
                                      label=f"{sym} = {num(limit)} on the grid (the constraint {sym} {op} {num(limit)})"))
    handles += draw_evaluations(ax, o)
    # a zoom on where the search ended
    d = np.asarray(o.data["delta"], dtype=float)
    a = np.asarray(o.data["alpha"], dtype=float)
    tail = slice(len(d) // 2, None)
    if len(d) >= 6:
        dl, dh = np.nanmin(d[tail]), np.nanmax(d[tail])
        al, ah = np.nanmin(a[tail]), np.nanmax(a[tail])
        pd = max(0.15 * (dh - dl), 0.01 * np.ptp(x), 0.004)
        pa = max(0.15 * (ah - al), 0.01 * np.ptp(y), 0.002)
        if (dh - dl) < 0.3 * np.ptp(x) and (ah - al) < 0.3 * np.ptp(y):
            ins = ax.inset_axes([0.6, 0.3, 0.37, 0.3])
            ins.grid(False)
            xe, ye = cell_edges(x), cell_edges(y)
            ins.pcolormesh(xe, ye, np.ma.masked_where(st != 0, z), cmap=CMAP,
                           norm=ax.impactid_norm, shading="flat")
            draw_evaluations(ins, o, best_ms=11)
            bounds = study.get("parameters", {})
            dlo, dhi = bounds.get("delta", {}).get("from", x.min()), bounds.get("delta", {}).get("to", x.max())
            alo, ahi = bounds.get("alpha", {}).get("from", y.min()), bounds.get("alpha", {}).get("to", y.max())
            ins.set_xlim(max(dl - pd, dlo - 0.2 * pd), min(dh + pd, dhi + 0.2 * pd))
            ins.set_ylim(max(al - pa, alo - 0.2 * pa), min(ah + pa, ahi + 0.2 * pa))
            ins.xaxis.set_major_locator(mticker.MaxNLocator(4))
            ins.yaxis.set_major_locator(mticker.MaxNLocator(4))
            ins.tick_params(labelsize=7)
            ins.set_title(f"zoom: evaluations {len(d) // 2}–{len(d) - 1}", fontsize=7.5, pad=2)
            ax.indicate_inset_zoom(ins, edgecolor="white", alpha=1.0)
    algo = text(o.attr("algorithm", study.get("algorithm", "?")))
    term = text(o.attr("termination", "?"))
    ax.legend(handles=handles, loc="upper right", fontsize=7.5, framealpha=0.92)
    ax.set_title(f"{algo}: minimise {objective_text(study.get('objective', 'eps_p'))}"
                 + (f" subject to {', '.join(constraint_text)}" if constraint_text else "")
                 + f"; {len(d)} evaluations, {term}", fontsize=9.5)
    fig.suptitle(f"HHT-α parameter search; {results_scene(o)}")
    return [save(fig, out_dir, "fig_optimize.png")]


# ---------------------------------------------------------------------------------------------

FIGURES = [
    ("fig3_newmark_delta.png", fig3),
    ("fig_two_rods.png", fig_two_rods),
    ("fig4_hht_delta_alpha.png", fig4),
    ("fig_hopkinson.png", fig_hopkinson),
    ("block-hht-delta-alpha.png", fig_block_hht),
    ("fig_period_error_line.png", fig_period_error_line),
    ("fig5_pressure_history.png", fig5),
    ("fig6_velocity_history.png", fig6),
    ("fig_stepped_rod_pressure.png", fig_stepped_rod_pressure),
    ("fig_stepped_rod_velocity.png", fig_stepped_rod_velocity),
    ("block-contact-force.png", fig_block_contact_force),
    ("fig7_compare_pressure.png", fig7),
    ("fig8_compare_velocity.png", fig8),
    ("fig_spectral.png", fig_spectral),
    ("fig_optimize.png", fig_optimize),
    ("fig_stability_map.png", fig_stability_map),
    ("fig_work_precision.png", fig_work_precision),
    ("block-work-precision.png", fig_block_work_precision),
]


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="make_figures.py",
        description="Regenerate every impactid figure (PNG) from the HDF5 results files.",
    )
    parser.add_argument("--results", default=None, help="folder of the results files (default: results/ of the project)")
    parser.add_argument("--out", default=None, help="folder for the PNG files (default: RESULTS/figures/)")
    parser.add_argument("--only", action="append", default=None, metavar="NAME",
                        help="draw only this figure (file name, with or without .png); may repeat")
    args = parser.parse_args(argv)
    results_dir = Path(args.results) if args.results else PROJECT_ROOT / "results"
    out_dir = Path(args.out) if args.out else results_dir / "figures"
    if not results_dir.is_dir():
        parser.error(f"--results {results_dir}: not a folder")
    out_dir.mkdir(parents=True, exist_ok=True)
    wanted = None
    if args.only:
        wanted = {w if w.endswith(".png") else w + ".png" for w in args.only}
        unknown = wanted - {n for n, _ in FIGURES}
        if unknown:
            parser.error(f"--only {', '.join(sorted(unknown))}: no such figure ({', '.join(n for n, _ in FIGURES)})")
    failed = 0
    for name, draw in FIGURES:
        if wanted and name not in wanted:
            continue
        try:
            for path in draw(results_dir, out_dir):
                print(f"wrote   {path}")
        except Skip as why:
            print(f"skipped {name}: {why}")
        except Exception as error:  # keep drawing the others; report and fail at the end
            failed += 1
            print(f"FAILED  {name}: {type(error).__name__}: {error}")
            traceback.print_exc(file=sys.stderr)
        finally:
            plt.close("all")
        sys.stdout.flush()
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
