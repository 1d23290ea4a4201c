#!/usr/bin/python3
"""An independent SciPy peer of impactid on a user's model (issue 37): the same methods on the
same matrices, written with numpy and scipy.sparse only, timed per step.

    /usr/bin/python3 bench/scipy_peer.py SCENE.toml --method cdm|hht|newmark
                     [--alpha A] [--delta D] [--impactid BINARY] [--json]

SCENE.toml is a `kind = "matrices"` scene in impactid's model format (docs/model-files.md; read
here with tomllib and numpy, not with impactid): M, K and optionally C as Matrix Market files, the
initial displacement and velocity, the contacts (walls on a DOF, "upper" u <= gap or "lower"
u >= -gap, and pairs u_i - u_j <= gap), dt (or courant), t_end, Rayleigh damping. The contacts
are Lagrange's, exact at the step's end, as impactid's default contact law enforces them.

The methods (what core/methods/sparse_integrators.hpp steps, by the same formulas):

- cdm: central difference with the central velocity on a diagonal (lumped) M, one sparse
  product per step, u+ = M^-1 (M (2u - u-) - dt^2 K u), with Carpenter's forward-increment
  multipliers: the contact-free u+ violates constraint k by p_k = G_k u+ - gap_k; the forces
  solve LCP(-p, D) with the Delassus matrix D = G A^-1 G^T of A = M/dt^2, diagonal for contacts
  on distinct DOFs, so mu_k = max(p_k, 0)/d_kk in O(m); u+ is corrected by A^-1 G^T mu and a wall
  in contact is put exactly on its gap. With a damping matrix, A = M/dt^2 + C/(2 dt) is factored
  by splu and D is general.
- hht (alpha in [-0.5, 0], delta = -alpha by default) and newmark (delta = 0.3 by default): the
  effective matrix (1 - alpha_f)(M + beta dt^2 K + gamma dt C) (alpha_f = -alpha; 0 for Newmark)
  factored once by scipy.sparse.linalg.splu; D = beta dt^2 G A^-1 G^T formed once (m solves);
  each step one solve for the contact-free acceleration, the LCP on D (Murty's least-index
  principal pivoting from the penetrating set, as core/algebra/contact_lcp.hpp solves it), and
  one more solve with G^T mu when a force acts. The force acts at t + dt, unweighted
  (impactid's default, `--hht-contact endpoint`).

Before the first contact a model that flies rigidly (u0 = 0, K v0 = C v0 = 0 exactly) is filled in
up to two steps before its first gap closes, as impactid does (core/run/simulation.hpp:
free_flight_samples), so both step the same samples.

Printed: the set-up (reading the files apart), the stepping and its time per stepped step; with
--impactid, the largest difference between this run's contact forces (every contact, every
sample) and those of `impactid simulate --scene SCENE --method M --history FILE.h5`, relative to
the largest force (and the same of the contacts' velocities), over the samples impactid completed
(a run its energy bound stopped ends early; the peer has no such bound), and whether it is within
--tolerance, 1e-10 by default: the same algorithm in another order of operations, with another
factorisation for the implicit methods (what it measures: docs/performance.md, "The SciPy
peer"). Exit status 1 when it is not.
"""
import argparse
import json
import math
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

import numpy as np
import scipy.io
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg

DEFAULT_TOLERANCE = 1e-10


# --- The model file --------------------------------------------------------------------------


def read_matrix(path):
    """A Matrix Market coordinate matrix as CSR, both triangles of a symmetric file, made exactly
    symmetric as impactid makes it (0.5 (A + A^T), explicit zeros dropped). numpy's loadtxt reads
    the entries: faster than scipy.io.mmread on a large file (docs/performance.md)."""
    with open(path) as f:
        header = f.readline().split()
        if len(header) < 5 or header[0] != "%%MatrixMarket" or header[2] != "coordinate":
            raise SystemExit(f"{path}: not a Matrix Market coordinate matrix")
        symmetry = header[4].lower()
        line = f.readline()
        while line.startswith("%") or not line.strip():
            line = f.readline()
        rows, cols, entries = (int(x) for x in line.split())
        data = np.loadtxt(f, dtype=np.float64, ndmin=2) if entries else np.zeros((0, 3))
    if data.shape[0] != entries:
        raise SystemExit(f"{path}: {data.shape[0]} entries, the header says {entries}")
    i, j, v = data[:, 0].astype(np.int64) - 1, data[:, 1].astype(np.int64) - 1, data[:, 2]
    if symmetry == "symmetric":  # one triangle stored
        off = i != j
        i, j, v = np.concatenate([i, j[off]]), np.concatenate([j, i[off]]), \
            np.concatenate([v, v[off]])
    a = scipy.sparse.csr_matrix((v, (i, j)), shape=(rows, cols))
    a = (0.5 * (a + a.T)).tocsr()
    a.eliminate_zeros()
    a.sort_indices()
    return a


def dof_set(spec, n, sets):
    """A set of DOFs as the model format gives one: a list, "all", "start:stop:step" or the name
    of a [scene.dof_sets] entry."""
    if isinstance(spec, list):
        return np.array(spec, dtype=np.int64)
    if spec == "all":
        spec = "::"
    if ":" in spec:
        fields = spec.split(":")
        parts = [0, n, 1]
        for k, field in enumerate(fields):
            if field:
                parts[k] = int(field)
        start, stop = (min(max(x + n if x < 0 else x, 0), n) for x in parts[:2])
        return np.arange(start, stop, parts[2], dtype=np.int64)
    if spec in sets:
        return dof_set(sets[spec], n, {})
    raise SystemExit(f"{spec!r} is not a set of DOFs")


def initial_vector(spec, n, sets, folder):
    if isinstance(spec, str):
        x = np.asarray(scipy.io.mmread(str(folder / spec)), dtype=np.float64)
        x = x.toarray() if scipy.sparse.issparse(x) else x
        return x.reshape(-1)
    out = np.zeros(n)
    out[dof_set(spec.get("dofs", "all"), n, sets)] = float(spec["value"])
    return out


def step_count(t_end, dt):
    return max(1, math.ceil(t_end / dt - 1e-9))


def read_scene(path, t_end=None):
    """The model of a scene file: a dict of the matrices, the state at t = 0, the contacts and the
    time grid."""
    path = Path(path)
    with open(path, "rb") as f:
        scene = tomllib.load(f)["scene"]
    if scene.get("kind") != "matrices":
        raise SystemExit(f"{path}: not a model (kind = \"matrices\")")
    folder = path.parent
    files = scene["matrices"]
    mass = read_matrix(folder / files["mass"])
    stiffness = read_matrix(folder / files["stiffness"])
    n = mass.shape[0]
    damping = read_matrix(folder / files["damping"]) if "damping" in files else None
    rayleigh_mass = float(scene.get("rayleigh_mass", 0.0))
    rayleigh_stiffness = float(scene.get("rayleigh_stiffness", 0.0))
    if rayleigh_mass or rayleigh_stiffness:
        damping = (damping if damping is not None else scipy.sparse.csr_matrix((n, n))) \
            + rayleigh_mass * mass + rayleigh_stiffness * stiffness
        damping = damping.tocsr()
        damping.eliminate_zeros()
    if damping is not None and damping.nnz == 0:
        damping = None
    sets = scene.get("dof_sets", {})
    initial = scene.get("initial", {})
    u0 = initial_vector(initial["displacement"], n, sets, folder) if "displacement" in initial \
        else np.zeros(n)
    v0 = initial_vector(initial["velocity"], n, sets, folder) if "velocity" in initial \
        else np.zeros(n)
    contacts = []
    for c in scene["contact"]:
        if "dofs" in c:
            plus, minus = c["dofs"]
        elif c.get("side", "upper") == "upper":
            plus, minus = c["dof"], -1
        else:
            plus, minus = -1, c["dof"]
        contacts.append({"name": c["name"], "plus": plus, "minus": minus,
                         "gap": float(c.get("gap", 0.0)), "area": float(c.get("area", 1.0)),
                         "velocity_dof": c.get("velocity_dof", c["dofs"][0] if "dofs" in c
                                               else c["dof"])})
    if "courant" in scene:
        # A model's Courant number is dt*omega/2 with Gershgorin's bound on omega
        # (core/model/model_scene.hpp: gershgorin_omega).
        lumped = np.asarray(mass.sum(axis=1)).reshape(-1)
        row = np.asarray(abs(stiffness).sum(axis=1)).reshape(-1)
        dt = 2.0 * float(scene["courant"]) / math.sqrt(np.max(row / lumped))
    else:
        dt = float(scene["dt"])
    t_end = float(scene["t_end"]) if t_end is None else t_end
    return {"path": str(path), "M": mass, "K": stiffness, "C": damping, "u0": u0, "v0": v0,
            "contacts": contacts, "dt": dt, "steps": step_count(t_end, dt)}


def constraint_matrix(model):
    """G (m x n, CSR): row k is +1 at plus_k and -1 at minus_k, so G u - gap <= 0."""
    rows, cols, values = [], [], []
    for k, c in enumerate(model["contacts"]):
        for dof, sign in ((c["plus"], 1.0), (c["minus"], -1.0)):
            if dof >= 0:
                rows.append(k)
                cols.append(dof)
                values.append(sign)
    m, n = len(model["contacts"]), model["M"].shape[0]
    return scipy.sparse.csr_matrix((values, (rows, cols)), shape=(m, n))


def free_flight_samples(model, g):
    """How many samples impactid fills in as rigid free flight rather than steps
    (core/run/simulation.hpp: free_flight_samples, core/model/model_scene.cpp: assemble)."""
    v0 = model["v0"]
    product = model["K"] @ v0
    if model["C"] is not None:
        product = product + model["C"] @ v0
    if np.any(model["u0"] != 0.0) or np.any(product != 0.0):
        return 0
    rate = g @ v0
    gaps = np.array([c["gap"] for c in model["contacts"]])
    closing = rate > 0.0
    if not np.any(closing):
        return 0
    first_contact = np.min(gaps[closing] / rate[closing])
    return int(min(max(math.floor(first_contact / model["dt"]) - 2.0, 0), model["steps"]))


# --- The contact problem ---------------------------------------------------------------------


class ContactLcp:
    """LCP(-p, D): mu >= 0, g = p - D mu <= 0, mu_k g_k = 0, D symmetric positive definite.
    Diagonal D: mu_k = max(p_k, 0)/d_kk. Otherwise Murty's least-index principal pivoting from
    the penetrating set, each active set solved by Cholesky, the sign tests with a tolerance of
    1e-12 of max|p| and at most 64 m + 1024 flips (core/algebra/contact_lcp.hpp's choices)."""

    def __init__(self, delassus):
        self.d = np.asarray(delassus, dtype=np.float64)
        self.diag = np.ascontiguousarray(np.diag(self.d))
        self.diagonal = bool(np.all(self.diag > 0.0)) and \
            np.count_nonzero(self.d) == np.count_nonzero(self.diag)
        self.cap = 64 * len(self.diag) + 1024

    def solve(self, p):
        if self.diagonal:
            return np.where(p > 0.0, p / self.diag, 0.0)
        m = len(p)
        tolerance = 1e-12 * (np.max(np.abs(p)) if m else 0.0)
        active = p > 0.0
        flips = 0
        while True:
            mu = np.zeros(m)
            s = np.flatnonzero(active)
            if s.size == 1:
                mu[s] = p[s] / self.diag[s]
            elif s.size > 1:
                try:
                    factor = scipy.linalg.cho_factor(self.d[np.ix_(s, s)], lower=True,
                                                      check_finite=False)
                except np.linalg.LinAlgError:
                    break
                mu[s] = scipy.linalg.cho_solve(factor, p[s], check_finite=False)
            g = p - self.d[:, s] @ mu[s]
            violated = np.flatnonzero(np.where(active, (mu < 0.0) & (-mu * self.diag > tolerance),
                                               g > tolerance))
            if violated.size == 0 or flips >= self.cap:
                break
            active[violated[0]] = not active[violated[0]]
            flips += 1
        return np.maximum(mu, 0.0)


def walls_of(model):
    """The walls among the contacts: their contact indices, their DOFs and the value a DOF in
    contact takes (upper: gap, lower: -gap)."""
    walls = [(k, c["plus"], c["gap"]) if c["minus"] < 0 else (k, c["minus"], -c["gap"])
             for k, c in enumerate(model["contacts"]) if c["plus"] < 0 or c["minus"] < 0]
    contact, dof, value = zip(*walls) if walls else ((), (), ())
    return np.array(contact, dtype=np.int64), np.array(dof, dtype=np.int64), np.array(value)


def snap_walls(walls, forces, u):
    """A wall whose force acts holds its DOF exactly on the gap, as impactid's snap_walls."""
    contact, dof, value = walls
    on = forces[contact] > 0.0
    u[dof[on]] = value[on]


def factor(a):
    """splu of a symmetric positive definite matrix: the minimum-degree ordering of A + A^T and
    SuperLU's symmetric mode (diagonal pivots) keep its fill near a Cholesky factor's; the
    default (COLAMD, partial pivoting) fills more and solves slower (docs/performance.md)."""
    return scipy.sparse.linalg.splu(a.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                    options={"SymmetricMode": True})


def consistent_acceleration(model):
    """a(0) from M a = -K u0 - C v0 (no force acts at t = 0)."""
    rhs = -(model["K"] @ model["u0"])
    if model["C"] is not None:
        rhs -= model["C"] @ model["v0"]
    return factor(model["M"]).solve(rhs)


# --- The methods -----------------------------------------------------------------------------


def run_cdm(model, g, skipped):
    """Central difference, central velocity. Returns the forces and probe velocities of every
    sample, the set-up time and the stepping time [s]."""
    start = time.perf_counter()
    mass, stiffness, damping = model["M"], model["K"], model["C"]
    diagonal = mass.count_nonzero() == np.count_nonzero(mass.diagonal())
    if not diagonal:
        raise SystemExit("central difference needs a diagonal (lumped) mass matrix")
    dt, n, steps = model["dt"], mass.shape[0], model["steps"]
    m_diag = mass.diagonal()
    gap = np.array([c["gap"] for c in model["contacts"]])
    probes = np.array([c["velocity_dof"] for c in model["contacts"]], dtype=np.int64)
    walls = walls_of(model)
    gt = g.T.tocsr()
    if damping is None:
        inverse = dt * dt / m_diag  # A^-1 of A = M/dt^2
        lcp = ContactLcp((g @ scipy.sparse.diags(inverse) @ gt).toarray())
        lhs = None
    else:
        lhs = factor(mass / (dt * dt) + damping / (2.0 * dt))
        lcp = ContactLcp(g @ lhs.solve(gt.toarray()))
        rhs_mass = mass / (dt * dt)
        rhs_damping = damping / (2.0 * dt)
    t0 = skipped * dt
    u = model["v0"] * t0 if skipped > 0 else model["u0"].copy()
    a0 = consistent_acceleration(model)
    u_prev = u - dt * model["v0"] + 0.5 * dt * dt * a0
    u_next = np.empty(n)
    forces = np.zeros((steps, g.shape[0]))
    velocity = np.empty((steps, len(probes)))
    forces[:skipped] = 0.0
    velocity[:skipped] = model["v0"][probes]
    setup = time.perf_counter() - start

    start = time.perf_counter()
    # One step more than samples: the first gives the state at t_skipped, which is not a sample
    # (impactid's run_method steps it before its loop).
    for i in range(skipped - 1, steps):
        if lhs is None:
            ku = stiffness @ u
            ku *= inverse
            np.multiply(u, 2.0, out=u_next)
            u_next -= u_prev
            u_next -= ku
        else:
            rhs = rhs_mass @ (2.0 * u - u_prev) - stiffness @ u + rhs_damping @ u_prev
            u_next[:] = lhs.solve(rhs)
        mu = lcp.solve(g @ u_next - gap)
        active = bool(np.any(mu > 0.0))
        if active:
            if lhs is None:
                u_next -= inverse * (gt @ mu)
            else:
                u_next -= lhs.solve(gt @ mu)
            snap_walls(walls, mu, u_next)
        if i >= skipped:
            forces[i] = mu if active else 0.0
            velocity[i] = (u_next[probes] - u_prev[probes]) / (2.0 * dt)
        u_prev, u, u_next = u, u_next, u_prev
    return forces, velocity, setup, time.perf_counter() - start


def implicit_coefficients(method, alpha, delta):
    if method == "hht":
        alpha = -0.3 if alpha is None else alpha
        if not -0.5 <= alpha <= 0.0:
            raise SystemExit(f"--alpha = {alpha}: must lie in [-0.5, 0]")
        delta = -alpha if delta is None else delta
        alpha_f = -alpha
    else:
        delta = 0.3 if delta is None else delta
        alpha_f = 0.0
    return (1.0 + delta) ** 2 / 4.0, 0.5 + delta, alpha_f  # beta, gamma (eq. 13), alpha_f


def run_implicit(model, g, skipped, beta, gamma, alpha_f):
    """Newmark's family with HHT's alpha_f (alpha_m = 0), the contact force at t + dt."""
    start = time.perf_counter()
    mass, stiffness, damping = model["M"], model["K"], model["C"]
    dt, n, steps = model["dt"], mass.shape[0], model["steps"]
    b0, b1, g0, g1 = 0.5 - beta, beta, 1.0 - gamma, gamma
    effective = mass + (1.0 - alpha_f) * b1 * dt * dt * stiffness
    if damping is not None:
        effective = effective + (1.0 - alpha_f) * g1 * dt * damping
    lu = factor(effective)
    gt = g.T.tocsr()
    delassus = b1 * dt * dt * (g @ lu.solve(gt.toarray()))
    lcp = ContactLcp(0.5 * (delassus + delassus.T))
    gap = np.array([c["gap"] for c in model["contacts"]])
    probes = np.array([c["velocity_dof"] for c in model["contacts"]], dtype=np.int64)
    walls = walls_of(model)
    a = consistent_acceleration(model)
    u = model["v0"] * (skipped * dt) if skipped > 0 else model["u0"].copy()
    v = model["v0"].copy()
    forces = np.zeros((steps, g.shape[0]))
    velocity = np.empty((steps, len(probes)))
    velocity[:skipped] = model["v0"][probes]
    dt2_b0, dt_g0, dt2_b1, dt_g1 = dt * dt * b0, dt * g0, dt * dt * b1, dt * g1
    setup = time.perf_counter() - start

    start = time.perf_counter()
    for i in range(skipped, steps):
        du = dt * v + dt2_b0 * a
        u_star = u + du
        v_star = v + dt_g0 * a
        rhs = -(stiffness @ (u_star - alpha_f * du))
        if damping is not None:
            rhs -= damping @ (v_star - alpha_f * (dt_g0 * a))
        a = lu.solve(rhs)
        mu = lcp.solve(g @ (u_star + dt2_b1 * a) - gap)
        active = bool(np.any(mu > 0.0))
        if active:
            a -= lu.solve(gt @ mu)
        u = u_star + dt2_b1 * a
        v = v_star + dt_g1 * a
        if active:
            snap_walls(walls, mu, u)
            forces[i] = mu
        velocity[i] = v[probes]
    return forces, velocity, setup, time.perf_counter() - start


def run(model, method, alpha=None, delta=None):
    g = constraint_matrix(model)
    skipped = free_flight_samples(model, g)
    if method == "cdm":
        forces, velocity, setup, stepping = run_cdm(model, g, skipped)
    else:
        forces, velocity, setup, stepping = run_implicit(
            model, g, skipped, *implicit_coefficients(method, alpha, delta))
    # Central difference steps once more than it has samples to fill (run_cdm).
    iterations = model["steps"] - skipped + (method == "cdm")
    return {"forces": forces, "velocity": velocity, "setup_s": setup, "stepping_s": stepping,
            "skipped": skipped, "stepped": model["steps"] - skipped, "iterations": iterations}


# --- Against impactid ------------------------------------------------------------------------


def impactid_history(binary, model, method, extra):
    """Forces (pressure x area) and probe velocities of every contact, samples x contacts, from
    impactid's own run of the scene (`impactid simulate --history FILE.h5`), and its JSON."""
    import h5py  # only here: a timing run needs no HDF5

    with tempfile.TemporaryDirectory() as folder:
        history = Path(folder) / "history.h5"
        # One refinement of a converged reference at most: a model without a reference of its
        # own gets one computed after the run, which the comparison does not need.
        done = subprocess.run([binary, "simulate", "--scene", model["path"], "--method", method,
                               *extra, "--reference-max-refinements", "1", "--json", "--history",
                               str(history)], capture_output=True, text=True)
        # Exit status 3: the run's verdict is unverified (its reference not trusted), which
        # says nothing of the run itself.
        if done.returncode not in (0, 3):
            raise SystemExit(f"impactid simulate failed: {done.stderr[-2000:]}")
        with h5py.File(history, "r") as f:
            forces = np.column_stack([f[f"pressure.{c['name']}"][:] * c["area"]
                                      for c in model["contacts"]])
            velocity = np.column_stack([f[f"velocity.{c['name']}"][:]
                                        for c in model["contacts"]])
    return forces, velocity, json.loads(done.stdout)


def compare(model, result, binary, method, extra):
    """The largest differences from impactid's run, relative to its largest force and its
    largest probe velocity."""
    theirs, their_v, summary = impactid_history(binary, model, method, extra)
    ours = result["forces"]
    if theirs.shape != ours.shape:
        raise SystemExit(f"impactid's history has {theirs.shape} samples x contacts, "
                         f"the peer's {ours.shape}")
    # A run that impactid stopped (its energy bound: the peer has none) is compared over the
    # samples it completed.
    done = int(summary["steps"])
    scale = np.max(np.abs(theirs[:done]), initial=0.0)
    force = float(np.max(np.abs(ours[:done] - theirs[:done])) / scale) if scale > 0 else math.inf
    v_scale = np.max(np.abs(their_v[:done]), initial=0.0)
    velocity = float(np.max(np.abs(result["velocity"][:done] - their_v[:done])) / v_scale) \
        if v_scale > 0 else math.inf
    return {"force_difference": force, "velocity_difference": velocity, "compared": done,
            "impactid_status": summary["status"], "impactid_wall_time_s": summary["wall_time_s"]}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene", help="a model's scene file (kind = \"matrices\")")
    parser.add_argument("--method", choices=("cdm", "hht", "newmark"), default="cdm")
    parser.add_argument("--alpha", type=float, help="hht: alpha in [-0.5, 0] (default -0.3)")
    parser.add_argument("--delta", type=float,
                        help="hht, newmark: delta of eq. 13 (default -alpha; newmark 0.3)")
    parser.add_argument("--t-end", type=float, help="end time instead of the scene's")
    parser.add_argument("--impactid", help="impactid's program: compare the contact forces "
                                           "with its run of the same scene and method")
    parser.add_argument("--tolerance", type=float,
                        default=DEFAULT_TOLERANCE,
                        help="the largest relative force difference accepted (default 1e-10)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    args = parser.parse_args()

    start = time.perf_counter()
    model = read_scene(args.scene, args.t_end)
    reading = time.perf_counter() - start
    result = run(model, args.method, args.alpha, args.delta)
    out = {"scene": args.scene, "method": args.method, "dofs": model["M"].shape[0],
           "contacts": len(model["contacts"]), "dt": model["dt"], "steps": model["steps"],
           "skipped": result["skipped"], "stepped": result["stepped"], "read_s": reading,
           "setup_s": result["setup_s"], "stepping_s": result["stepping_s"],
           "step_s": result["stepping_s"] / result["iterations"],
           "contact_steps": int(np.count_nonzero(np.any(result["forces"] > 0.0, axis=1)))}
    ok = True
    if args.impactid:
        extra = []
        if args.alpha is not None:
            extra += ["--alpha", repr(args.alpha)]
        if args.delta is not None:
            extra += ["--delta", repr(args.delta)]
        if args.t_end is not None:
            extra += ["--t-end", repr(args.t_end)]
        out.update(compare(model, result, args.impactid, args.method, extra))
        out["tolerance"] = args.tolerance
        ok = out["force_difference"] <= out["tolerance"]
        out["agrees"] = ok
    if args.json:
        print(json.dumps(out))
    else:
        print(f"model       {args.scene}: {out['dofs']} DOFs, {out['contacts']} contacts, "
              f"dt = {out['dt']:g}, {out['steps']} samples ({out['skipped']} filled in as free "
              f"flight, {out['stepped']} stepped, {out['contact_steps']} in contact)")
        print(f"method      {args.method} (SciPy {scipy.__version__}, numpy {np.__version__})")
        print(f"read        {reading * 1e3:.1f} ms (the matrix files)")
        print(f"set-up      {out['setup_s'] * 1e3:.1f} ms")
        print(f"stepping    {out['stepping_s'] * 1e3:.1f} ms = {out['step_s'] * 1e6:.1f} us per "
              f"step")
        if args.impactid:
            print(f"impactid    contact forces differ by {out['force_difference']:.2e} (largest "
                  f"|difference| / largest |force|; tolerance {out['tolerance']:.0e}: "
                  f"{'ok' if ok else 'FAIL'}), velocities by {out['velocity_difference']:.2e}; "
                  f"{out['compared']} samples, impactid's run {out['impactid_status']}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
