#!/usr/bin/python3
"""bench/scipy_peer.py, the SciPy peer that bench/report times impactid against, runs the same
methods as impactid: its contact forces equal those of `impactid simulate --history` on the same
scene, every contact at every sample, to 1e-10 of the largest force (the same algorithms in
another order of operations; what they measure: docs/performance.md, "The SciPy peer").

Scenes: a small beam (examples/beam3d, --nx 16: 9 contacts on a diagonal Delassus matrix for
central difference, a dense one for the implicit methods); examples/block (41 contacts); the block
with stiffness-proportional Rayleigh damping (central difference then factors M/dt^2 + C/(2 dt),
its Delassus matrix is dense and its contact problems go through the principal pivoting); two
blocks, one falling on the other, held by contacts between pairs of DOFs; and examples/three-dof,
whose rigid flight before the contact both fill in rather than step. A ratio against a
peer that computed something else would mean nothing, hence this test; it times nothing.

Usage: scipy_peer_test.py IMPACTID SOURCE_DIR
"""
import json
import math
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import scipy.io
import scipy.sparse

IMPACTID, SOURCE = sys.argv[1], Path(sys.argv[2])
PEER = SOURCE / "bench" / "scipy_peer.py"
BLOCK = SOURCE / "examples" / "block"
TOLERANCE = 1e-10
sys.path.insert(0, str(PEER.parent))
import scipy_peer  # noqa: E402  (bench/ is no package)

failures = 0


def check(ok, what):
    global failures
    print(("ok   " if ok else "FAIL ") + what)
    failures += not ok


def peer(scene, method, *options):
    """The peer's JSON, compared with impactid's run of the same scene and method."""
    run = subprocess.run(["/usr/bin/python3", str(PEER), str(scene), "--method", method,
                          "--impactid", IMPACTID, "--tolerance", repr(TOLERANCE), "--json",
                          *options], capture_output=True, text=True)
    try:
        return run.returncode, json.loads(run.stdout)
    except json.JSONDecodeError:
        return run.returncode, {"error": ": " + run.stderr[-2000:]}


def agrees(scene, method, *options):
    status, out = peer(scene, method, *options)
    label = f"{Path(scene).parent.name}/{Path(scene).name} {method} {' '.join(options)}".strip()
    force, velocity = out.get("force_difference", math.nan), out.get("velocity_difference",
                                                                       math.nan)
    check(status == 0 and force <= TOLERANCE and velocity <= TOLERANCE,
          f"{label}: forces differ by {force:.1e}, probe velocities by {velocity:.1e} (at most "
          f"{TOLERANCE:g} of the largest){out.get('error', '')}")
    # The check must bite: the run has contact, at more than one sample.
    check(out.get("contact_steps", 0) > 1,
          f"{label}: {out.get('contact_steps')} samples in contact (of {out.get('steps')})")
    return out


def two_blocks(folder):
    """examples/block twice: the lower one at rest on the plane y = 0, the upper one 1 um above
    it, falling at 1000 mm/s, with a contact between each node of the lower block's top edge and
    the node of the upper block's bottom edge above it (pairs: u_lower - u_upper <= gap)."""
    mass = scipy_peer.read_matrix(BLOCK / "M.mtx")
    stiffness = scipy_peer.read_matrix(BLOCK / "K.mtx")
    n = mass.shape[0]
    scipy.io.mmwrite(str(folder / "M.mtx"), scipy.sparse.block_diag([mass, mass]), precision=17)
    scipy.io.mmwrite(str(folder / "K.mtx"), scipy.sparse.block_diag([stiffness, stiffness]),
                     precision=17)
    dofs = np.genfromtxt(BLOCK / "dofs.csv", delimiter=",", names=True)
    y = dofs["component"] == 1
    bottom = {x: int(d) for d, x in zip(dofs["dof"][y & (dofs["node_y"] == 0.0)],
                                        dofs["node_x"][y & (dofs["node_y"] == 0.0)])}
    top_y = dofs["node_y"].max()
    top = {x: int(d) for d, x in zip(dofs["dof"][y & (dofs["node_y"] == top_y)],
                                     dofs["node_x"][y & (dofs["node_y"] == top_y)])}
    lines = ['[scene]', 'kind = "matrices"', 'units = "N, mm, s, t"', "dt = 4.23e-08",
             "t_end = 4e-06", "[scene.matrices]", 'mass = "M.mtx"', 'stiffness = "K.mtx"',
             "[scene.initial]", f'velocity = {{ value = -1000.0, dofs = "{n + 1}::2" }}']
    for k, (x, d) in enumerate(sorted(bottom.items())):
        lines += ["[[scene.contact]]", f'name = "ground_{k}"', f"dof = {d}", 'side = "lower"',
                  "gap = 0.0"]
    for k, (x, d) in enumerate(sorted(top.items())):
        lines += ["[[scene.contact]]", f'name = "pair_{k}"', f"dofs = [{d}, {n + bottom[x]}]",
                  "gap = 0.001"]
    (folder / "scene.toml").write_text("\n".join(lines) + "\n")
    return folder / "scene.toml", len(bottom) + len(top)


with tempfile.TemporaryDirectory() as scratch:
    scratch = Path(scratch)

    # 1. A small beam: cdm on the diagonal Delassus path, the implicit methods on a dense one.
    beam = scratch / "beam-16"
    generated = subprocess.run(["/usr/bin/python3", str(SOURCE / "examples" / "beam3d" /
                                                        "generate.py"), "--nx", "16", "--out",
                                str(beam)], capture_output=True, text=True)
    check(generated.returncode == 0, f"generate.py --nx 16 {generated.stderr[-2000:]}")
    for method, options in (("cdm", ()), ("hht", ()), ("hht", ("--alpha", "-0.2")),
                            ("newmark", ())):
        agrees(beam / "scene.toml", method, *options)

    # 2. The shipped block, as it is and with stiffness-proportional damping.
    for method in ("cdm", "hht"):
        agrees(BLOCK / "scene.toml", method)
    damped = scratch / "block-damped"
    damped.mkdir()
    text = (BLOCK / "scene.toml").read_text()
    text = text.replace('mass = "M.mtx"', f'mass = "{BLOCK / "M.mtx"}"').replace(
        'stiffness = "K.mtx"', f'stiffness = "{BLOCK / "K.mtx"}"')
    text = text.replace('primary_contact = "bottom_20"',
                        'primary_contact = "bottom_20"\nrayleigh_stiffness = 2e-09')
    (damped / "scene.toml").write_text(text)
    for method in ("cdm", "hht"):
        agrees(damped / "scene.toml", method)

    # 3. Two blocks held apart by contacts between pairs of DOFs.
    pairs = scratch / "two-blocks"
    pairs.mkdir()
    scene, m = two_blocks(pairs)
    check(m == 82, f"two blocks: 41 walls and 41 pairs ({m} contacts)")
    for method in ("cdm", "hht"):
        agrees(scene, method)
    forces = scipy_peer.run(scipy_peer.read_scene(scene), "cdm")["forces"]
    check(np.any(forces[:, :41] > 0.0) and np.any(forces[:, 41:] > 0.0),
          "two blocks: the walls and the pairs both carry forces")

    # 4. The three masses fly rigidly before their contact (K v0 = 0 exactly): both fill in the
    # same samples (impactid runs this tridiagonal model on its rod path: the same algorithm).
    for method in ("cdm", "hht"):
        out = agrees(SOURCE / "examples" / "three-dof" / "scene.toml", method)
        check(out.get("skipped") == 18, f"three-dof {method}: {out.get('skipped')} samples of "
                                        f"free flight filled in (18: up to two before contact)")

    # 5. The comparison bites: the peer's Newmark against impactid's HHT differs.
    model = scipy_peer.read_scene(BLOCK / "scene.toml")
    newmark = scipy_peer.run(model, "newmark")
    difference = scipy_peer.compare(model, newmark, IMPACTID, "hht", [])["force_difference"]
    check(difference > 1e-3,
          f"the peer's newmark against impactid's hht: forces differ by {difference:.2e} "
          f"(more than 1e-3: the comparison tells methods apart)")

print(f"scipy_peer_test: {failures} failure(s)")
sys.exit(1 if failures else 0)
