"""The scene of a results file in one line, for the figures' titles: the paper's rod (a plan's
[scene] over DEFAULT_SCENE), a scene of bodies ([[scene.body]] in a plan's [scene];
plans/README.md) body by body with its contacts, and a user's model (model.py). Draws nothing;
reads the plan text stored in a results file (root attribute `plan`).
"""

import math

import numpy as np

from .model import is_model_results, model_scene_text
from .results import text
from .style import num

# The default scene (docs/conventions.md, "Parameters"): a plan's [scene] overrides these.
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


# Scenes of several bodies ([[scene.body]] in a plan's [scene]; plans/README.md)

SEGMENT_KEYS = ("length", "elements", "youngs_modulus", "density", "area")


def is_scene_of_bodies(scene):
    """Whether a [scene] table describes a scene of bodies (it has `body` or `wall`), as
    study/plan/scene_file.hpp decides."""
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
    """The contacts of a scene of bodies, left to right, as core/model/scene.cpp names them:
    [(name, gap, dotted keys of the gap)] with 'wall_left', '<left>-<right>' and 'wall_right'
    (a clamped wall is none)."""
    bodies = scene_bodies(scene)
    walls = scene.get("wall", {})
    out = []
    # A clamped wall (kind = "clamped") holds its end node: it is no contact.
    contact = {side: side in walls and walls[side].get("kind", "contact") == "contact" for side in ("left", "right")}
    if contact["left"] and bodies:
        out.append(("wall_left", float(walls["left"].get("gap", bodies[0]["gap"])),
                    ("wall.left.gap", f"body.{bodies[0]['name']}.gap", "body.1.gap")))
    for k, (left, right) in enumerate(zip(bodies, bodies[1:])):
        out.append((f"{left['name']}-{right['name']}", right["gap"], (f"body.{right['name']}.gap", f"body.{k + 2}.gap")))
    if contact["right"]:
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
    # A clamped wall (kind = "clamped") holds its end: no wall to hit, said as such.
    clamped = [side for side in ("left", "right") if walls.get(side, {}).get("kind") == "clamped"]
    rigid = [side for side in ("left", "right") if side in walls and side not in clamped]
    if len(rigid) == 2:
        line = f"{line} between two walls"
    elif rigid == ["left"]:
        line = f"left wall, {line}"
    elif rigid == ["right"]:
        line = f"{line} on the right wall"
    if clamped:
        line = f"{line}, clamped at the {' and '.join(clamped)} end{'s' if len(clamped) == 2 else ''}"
    parts = [line]
    gravity = float(scene.get("gravity", 0.0))
    if gravity != 0.0 and "gravity" not in varying:
        parts.append(f"g = {num(abs(gravity))} toward the {'left' if gravity < 0 else 'right'} wall")
    if not any(k.endswith(".elements") for k in varying):  # else each line or point says its own
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
