#!/usr/bin/python3
"""examples/beam3d (Code_Aster's SDNV100, assembled with GetFEM) against impactid's own rod and
the 1D wave.

With its lateral displacements fixed (SDNV100's condition) the 3D beam is, node line by node
line, a 1D rod of the constrained modulus E(1 - nu)/((1 + nu)(1 - 2 nu)) with lumped mass:
every contact of its struck face must then give the built-in rod's pressure and velocity
(core/model, the paper's rod) at the same dt, for an explicit and for implicit methods (the
sparse path against the tridiagonal one), to round-off. Under refinement along the beam,
central difference's eps_p against the 1D wave must fall at first order. With the lateral faces
free, the beam is a bar: its contact lasts about 2L/c_0 (c_0 = sqrt(E/rho)) at a mean pressure of
about rho c_0 v0, not the 1D reference's 2L/c_p and rho c_p v0, and the momentum 2 m v0 is given
back by the end.

Usage: beam3d_test.py IMPACTID SOURCE_DIR
"""
import json
import math
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

IMPACTID, SOURCE = sys.argv[1], Path(sys.argv[2])
GENERATE = SOURCE / "examples" / "beam3d" / "generate.py"
E, NU, RHO, L, V0, GAP = 2e11, 0.3, 8000.0, 0.2, 100.0, 0.002  # generate.py's SI values
E_C = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))
failures = 0


def check(ok, what):
    global failures
    print(("ok   " if ok else "FAIL ") + what)
    failures += not ok


def generate(folder, *options):
    run = subprocess.run(["/usr/bin/python3", str(GENERATE), "--out", str(folder), *options],
                         capture_output=True, text=True)
    check(run.returncode == 0 and "check: all passed" in run.stdout,
          f"generate.py {' '.join(options)}: {run.stdout.strip().splitlines()[-1:]}"
          + run.stderr[-2000:])
    text = (Path(folder) / "scene.toml").read_text()
    dt = float(re.search(r"^dt = (\S+)", text, re.M).group(1))
    t_end = float(re.search(r"^t_end = (\S+)", text, re.M).group(1))
    areas = {name: float(area) for name, area in
             re.findall(r'name = "(face_\d+_\d+)"\n(?:.*\n)*?area = (\S+)', text)}
    return dt, t_end, areas


def simulate(*arguments):
    run = subprocess.run([IMPACTID, "simulate", "--json", *arguments], capture_output=True,
                         text=True)
    if run.returncode != 0:
        check(False, f"impactid simulate {' '.join(arguments)}: {run.stderr[-2000:]}")
        return {}
    return json.loads(run.stdout)


def history(path):
    header = Path(path).read_text().split("\n", 1)[0].split(",")
    return header, np.genfromtxt(path, delimiter=",", skip_header=1)


def rod_equivalent(folder, method, dt, t_end, nx):
    """The built-in rod that the fixed-lateral beam is: mm, MPa, t."""
    out = Path(folder) / f"rod-{method}.csv"
    result = simulate("--method", method, "--length", repr(L * 1e3), "--elements", str(nx),
                      "--youngs-modulus", repr(E_C / 1e6), "--density", repr(RHO * 1e-12),
                      "--velocity", repr(V0 * 1e3), "--gap", repr(GAP * 1e3), "--mass",
                      "lumped", "--dt", repr(dt), "--t-end", repr(t_end), "--history", str(out))
    return result, history(out)


with tempfile.TemporaryDirectory() as scratch:
    scratch = Path(scratch)

    # 1. The fixed-lateral beam is the built-in rod, contact by contact.
    fixed = scratch / "fixed-20"
    dt, t_end, areas = generate(fixed, "--nx", "20", "--check")
    check(len(areas) == 9, f"9 contacts on the struck face of 20 x 2 x 2 hexahedra: {len(areas)}")
    for method in ("cdm", "newmark", "hht"):
        beam_file = fixed / f"beam-{method}.csv"
        beam = simulate("--scene", str(fixed / "scene.toml"), "--method", method, "--history",
                        str(beam_file))
        rod, (_, r) = rod_equivalent(fixed, method, dt, t_end, 20)
        header, b = history(beam_file)
        scale = np.max(np.abs(r[:, 1])) * 1e6
        worst = max(np.max(np.abs(b[:, header.index(f"pressure.{name}[N/m^2]")] - r[:, 1] * 1e6))
                    for name in areas) / scale
        velocity = np.max(np.abs(b[:, 2] - r[:, 2] * 1e-3)) / V0
        check(np.array_equal(b[:, 0], r[:, 0]) and worst < 1e-10 and velocity < 1e-10,
              f"{method}: every face contact's pressure is the rod's to {worst:.1e}, the primary "
              f"velocity to {velocity:.1e} (relative; at most 1e-10)")
        same = all(math.isclose(beam.get(k, math.nan), rod.get(k, math.nan), rel_tol=1e-9)
                   for k in ("eps_p", "eps_v")) and all(beam.get(k) == rod.get(k)
                                                        for k in ("nop_p", "nop_v"))
        check(same, f"{method}: the beam's indicators are the rod's: eps_p {beam.get('eps_p')} "
              f"vs {rod.get('eps_p')}, NoP_p {beam.get('nop_p')} vs {rod.get('nop_p')}")

    # 1b. The reference covers a sweep over dt: a step 1.13 and 0.9 times the default one still
    # has the reference at every sample (it reaches four steps past t_end, from t = 0).
    for factor in (1.13, 0.9):
        other = simulate("--scene", str(fixed / "scene.toml"), "--method", "cdm", "--set",
                         f"dt={dt * factor!r}")
        check(other.get("status") == "ok" and math.isfinite(other.get("eps_p", math.nan)),
              f"cdm at dt x {factor}: {other.get('status')} ({other.get('message')}), "
              f"eps_p {other.get('eps_p')}")

    # 2. Under refinement along the beam, central difference converges to the 1D wave.
    eps = []
    for nx in (20, 40, 80):
        folder = scratch / f"fixed-{nx}-1"
        generate(folder, "--nx", str(nx), "--nyz", "1", "--check")
        eps.append(simulate("--scene", str(folder / "scene.toml"), "--method", "cdm").get(
            "eps_p", math.nan))
    check(eps[0] > eps[1] > eps[2] and eps[2] < 0.45 * eps[0],
          f"cdm eps_p against the 1D wave at nx = 20, 40, 80: {eps} (falling, x4 refinement "
          f"at least /2.2)")

    # 3. Free lateral faces: a bar, not the constrained 1D wave.
    free = scratch / "free-40"
    dt, t_end, areas = generate(free, "--nx", "40", "--lateral", "free", "--check")
    result = simulate("--scene", str(free / "scene.toml"), "--method", "cdm", "--history",
                      str(free / "cdm.csv"))
    header, h = history(free / "cdm.csv")
    force = sum(h[:, header.index(f"pressure.{name}[N/m^2]")] * area
                for name, area in areas.items())
    face = sum(areas.values())
    on = np.flatnonzero(force > 0)
    duration = h[on[-1], 0] - h[on[0], 0] + dt
    c_0, c_p = math.sqrt(E / RHO), math.sqrt(E_C / RHO)
    check(result.get("status") == "ok", f"free: the run is ok ({result.get('status')})")
    check(abs(duration / (2 * L / c_0) - 1) < 0.05,
          f"free: contact for {duration * 1e6:.1f} us, 2L/c_0 = {2 * L / c_0 * 1e6:.1f} us "
          f"(2L/c_p = {2 * L / c_p * 1e6:.1f}), within 5 %")
    mean = force[on].mean() / face
    check(abs(mean / (RHO * c_0 * V0) - 1) < 0.05,
          f"free: mean face pressure in contact {mean:.3e} Pa, rho c_0 v0 = {RHO * c_0 * V0:.3e} "
          f"(rho c_p v0 = {RHO * c_p * V0:.3e}), within 5 %")
    impulse = force.sum() * dt / (2 * RHO * L * face * V0)
    check(abs(impulse - 1) < 0.03, f"free: impulse / (2 m v0) = {impulse:.4f}, within 3 %")

print(f"beam3d_test: {failures} failure(s)")
sys.exit(1 if failures else 0)
