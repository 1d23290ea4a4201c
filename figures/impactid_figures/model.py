"""User models ([scene] kind = "matrices", often a plan's `scene = "FILE.toml"`; examples/block):
their one-line description, contacts and areas, units, primary contact and the reference their
indicators are measured against, from a results file's model_* attributes and reference_*
columns, the model's scene file and its mass matrix. Draws nothing.
"""

import tomllib
from pathlib import Path

import numpy as np

from .results import PLAN_FILES, PROJECT_ROOT, text
from .style import num


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
    converged numerical solution (core/reference/model_reference.hpp: central difference when M is diagonal,
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
