#!/usr/bin/python3
"""Generate the "block" example for impactid: a 2D linearly elastic steel block
in plane strain dropping onto a rigid plane.

Run with Debian's Python (needs python3-getfem, numpy, scipy):

    /usr/bin/python3 generate.py [--nx 40] [--ny 20] [--width 20] [--height 10] [--check]

Units: N, mm, s, t (tonne), so stress is in MPa, density in t/mm^3, force in N.

Model
-----
* Rectangle [0, W] x [0, H] (W = 20 mm in x, H = 10 mm in y, unit thickness
  1 mm), structured mesh of nx x ny quadrilaterals (gf.Mesh('cartesian', X, Y)),
  bilinear Lagrange elements FEM_QK(2,1) with 2 DOFs per node,
  integration IM_GAUSS_PARALLELEPIPED(2,2) (2 x 2 Gauss points, exact for the
  mass and stiffness of affine rectangles).
* Steel: E = 200e3 MPa, nu = 0.3, rho = 7.85e-9 t/mm^3. Plane strain: the
  Lame coefficients are the 3D ones, lambda = E nu / ((1 + nu)(1 - 2 nu)),
  mu = E / (2 (1 + nu)), passed to gf.asm_linear_elasticity.
* Stiffness K: gf.asm_linear_elasticity(mim, mf_u, mf_d, lambda, mu) with
  lambda, mu constant per element (mf_d = FEM_QK(2,0)). It is symmetrised
  exactly, K <- (K + K^T)/2, before writing (the asymmetry left by the
  assembly is at round-off level; --check prints it), and entries with
  |K_ij| < 1e-12 max|K| are dropped: they are zero in exact arithmetic and
  come out of the quadrature at ~1e-18 max|K| (the smallest true entries are
  ~1e-3 max|K|); this removes about a fifth of the stored entries.
* Consistent mass: rho * gf.asm_mass_matrix(mim, mf_u).
* Lumped mass M: ROW-SUM lumping of the consistent mass (for bilinear
  rectangles this coincides with HRZ: every element gives a quarter of its mass
  to each of its 4 nodes, per component).
* DOF numbering: GetFEM's own (basic DOFs of mf_u, which with qdim = 2
  interleaves the components: DOF 2k is x, DOF 2k+1 is y of GetFEM's k-th
  node; the script checks this). dofs.csv gives, for each 0-based DOF, the node
  coordinates and the component (0 = x, 1 = y).
* Contact: one contact per node of the bottom edge y = 0, on its y-DOF,
  side "lower" (u_y >= -gap), gap = 0.001 mm; area = tributary length of the
  node along the edge x 1 mm thickness (so lambda/area is a pressure in MPa).
* Initial velocity -1000 mm/s on every y-DOF (rigid translation), zero in x,
  zero initial displacement.

Time step and end time
----------------------
* omega_max: largest eigenvalue of the symmetric matrix
  M^{-1/2} K M^{-1/2} (M lumped, diagonal), scipy.sparse.linalg.eigsh with
  which='LA', k=1 and a fixed start vector (seeded), omega_max = sqrt(lambda).
* dt = 0.5 * 2 / omega_max (Courant 0.5 of the central-difference limit),
  rounded DOWN to 3 significant digits.
* t_end = gap / 1000 mm/s (first contact) + 1.5 * 2 H / c_p, with the plane
  strain P-wave speed c_p = sqrt(E (1 - nu) / ((1 + nu)(1 - 2 nu) rho)),
  rounded UP to 3 significant digits.

Outputs (in the directory of this script, overwritten, byte-reproducible):
M.mtx (lumped, diagonal), M_consistent.mtx, K.mtx (Matrix Market coordinate
real symmetric, scipy.io.mmwrite(..., symmetry='symmetric', precision=17),
indices 1-based as Matrix Market requires; impactid DOFs are these minus one),
dofs.csv, scene.toml.

--check (not default) verifies with scipy: symmetry of K, K times the rigid
translations in x and in y is ~0 relative to ||K||, the lumped total mass per
component equals rho W H * 1 mm, stiffness from the generic assembly language
agrees, omega_max by shift-invert agrees, and prints the 6 lowest
eigenfrequencies (3 rigid modes ~ 0).
"""

import argparse
import os
import sys
from decimal import ROUND_CEILING, ROUND_FLOOR

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import getfem as gf

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from getfem_export import Verdicts, fmt, round_sig, to_scipy, write_mtx  # noqa: E402

E = 200e3  # MPa
NU = 0.3
RHO = 7.85e-9  # t/mm^3
GAP = 0.001  # mm
V0 = -1000.0  # mm/s, in y
COURANT = 0.5
N_TRANSITS = 1.5  # times the two-way transit 2H/c_p after first contact
DROP_TOL = 1e-12  # relative to max|K|: assembled round-off entries of K below it are dropped

DEFAULTS = {"nx": 40, "ny": 20, "width": 20.0, "height": 10.0}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--nx", type=int, default=DEFAULTS["nx"], help="elements in x (default 40)")
    ap.add_argument("--ny", type=int, default=DEFAULTS["ny"], help="elements in y (default 20)")
    ap.add_argument("--width", type=float, default=DEFAULTS["width"], help="W in mm (default 20)")
    ap.add_argument("--height", type=float, default=DEFAULTS["height"], help="H in mm (default 10)")
    ap.add_argument("--check", action="store_true", help="run the physics checks too")
    args = ap.parse_args()
    if args.nx < 1 or args.ny < 1 or args.width <= 0 or args.height <= 0:
        ap.error("--nx, --ny must be >= 1 and --width, --height > 0")
    nx, ny, W, H = args.nx, args.ny, args.width, args.height
    outdir = os.path.dirname(os.path.abspath(__file__))

    # ---- mesh, FEM, integration -------------------------------------------
    X = np.linspace(0.0, W, nx + 1)
    Y = np.linspace(0.0, H, ny + 1)
    mesh = gf.Mesh("cartesian", X, Y)
    mf_u = gf.MeshFem(mesh, 2)
    mf_u.set_fem(gf.Fem("FEM_QK(2,1)"))
    mf_d = gf.MeshFem(mesh, 1)
    mf_d.set_fem(gf.Fem("FEM_QK(2,0)"))
    mim = gf.MeshIm(mesh, gf.Integ("IM_GAUSS_PARALLELEPIPED(2,2)"))
    n = int(mf_u.nbdof())

    # ---- DOF table: node coordinates (snapped to the grid) and component --
    nodes = np.asarray(mf_u.basic_dof_nodes())  # 2 x n
    ix = np.rint(nodes[0] / W * nx).astype(int)
    iy = np.rint(nodes[1] / H * ny).astype(int)
    tol = 1e-9 * max(W, H)
    assert np.all(np.abs(X[ix] - nodes[0]) < tol) and np.all(np.abs(Y[iy] - nodes[1]) < tol)
    # component of each DOF: the x-load vector int(e_x . phi_i) is nonzero only on x DOFs
    zero = np.zeros(n)
    fx = np.asarray(gf.asm_generic(mim, 1, "[1,0].Test_u", -1, "u", 1, mf_u, zero))
    fy = np.asarray(gf.asm_generic(mim, 1, "[0,1].Test_u", -1, "u", 1, mf_u, zero))
    assert np.all((fx != 0) != (fy != 0)), "each DOF must be exactly one component"
    comp = np.where(fx != 0, 0, 1)
    assert len(set(zip(ix.tolist(), iy.tolist(), comp.tolist()))) == n
    assert n == 2 * (nx + 1) * (ny + 1)
    y_dofs = np.flatnonzero(comp == 1)
    y_every_second = np.array_equal(y_dofs, np.arange(1, n, 2))

    # ---- matrices ----------------------------------------------------------
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))  # plane strain = 3D Lame lambda
    mu = E / (2 * (1 + NU))
    nd = int(mf_d.nbdof())
    K_raw = to_scipy(gf.asm_linear_elasticity(mim, mf_u, mf_d,
                                               np.full(nd, lam), np.full(nd, mu)))
    K = ((K_raw + K_raw.T) * 0.5).tocsc()
    # Entries that are zero in exact arithmetic come out of the quadrature as
    # round-off (|k| < 1e-16 max|K|; the true ones are > 1e-3 max|K|): drop them.
    n_roundoff = int(np.count_nonzero(np.abs(K.data) < DROP_TOL * np.abs(K.data).max()))
    K.data[np.abs(K.data) < DROP_TOL * np.abs(K.data).max()] = 0.0
    K.eliminate_zeros()
    K.sort_indices()
    Mc = (to_scipy(gf.asm_mass_matrix(mim, mf_u)) * RHO).tocsc()
    Mc = ((Mc + Mc.T) * 0.5).tocsc()
    Mc.sort_indices()
    m_diag = np.asarray(Mc.sum(axis=1)).ravel()  # row-sum lumping
    assert np.all(m_diag > 0)
    M = sp.diags(m_diag, format="csc")

    # ---- omega_max of the lumped model ------------------------------------
    s = 1.0 / np.sqrt(m_diag)
    A = (sp.diags(s) @ K @ sp.diags(s)).tocsc()
    v0 = np.random.default_rng(12345).standard_normal(n)
    lam_max = spla.eigsh(A, k=1, which="LA", v0=v0, tol=1e-12,
                         return_eigenvectors=False)[0]
    omega_max = float(np.sqrt(lam_max))
    dt_exact = COURANT * 2.0 / omega_max
    dt = round_sig(dt_exact, 3, ROUND_FLOOR)

    c_p = np.sqrt(E * (1 - NU) / ((1 + NU) * (1 - 2 * NU) * RHO))
    t_contact = GAP / abs(V0)
    t_end_exact = t_contact + N_TRANSITS * 2.0 * H / c_p
    t_end = round_sig(t_end_exact, 3, ROUND_CEILING)

    # ---- contacts: y-DOFs of the bottom edge, left to right ----------------
    bottom = np.flatnonzero((iy == 0) & (comp == 1))
    bottom = bottom[np.argsort(ix[bottom], kind="stable")]
    assert len(bottom) == nx + 1
    contacts = []
    for k, d in enumerate(bottom):
        i = ix[d]
        # tributary length (uniform spacing W/nx; half at the two corners) x 1 mm thickness
        area = (W / nx if 0 < i < nx else W / nx / 2.0) * 1.0
        contacts.append((f"bottom_{k}", int(d), float(area)))
    k_mid = int(np.argmin(np.abs(2 * ix[bottom] - nx)))  # closest to x = W/2; ties (odd nx): left
    primary = contacts[k_mid][0]

    # ---- write files -------------------------------------------------------
    write_mtx(os.path.join(outdir, "K.mtx"), K)
    write_mtx(os.path.join(outdir, "M_consistent.mtx"), Mc)
    write_mtx(os.path.join(outdir, "M.mtx"), M)

    with open(os.path.join(outdir, "dofs.csv"), "w", newline="\n") as f:
        f.write("dof,node_x,node_y,component\n")
        for d in range(n):
            f.write(f"{d},{fmt(X[ix[d]])},{fmt(Y[iy[d]])},{comp[d]}\n")

    opts = "".join(f" --{k} {getattr(args, k)!r}" if isinstance(v, float) else f" --{k} {getattr(args, k)}"
                   for k, v in DEFAULTS.items() if getattr(args, k) != v)
    if y_every_second:
        all_y = '"1::2"'
    else:
        all_y = "[" + ", ".join(str(int(d)) for d in y_dofs) + "]"
    lines = [
        f"# impactid example \"block\": a {fmt(W)} mm x {fmt(H)} mm linearly elastic steel block",
        f"# (plane strain, {nx} x {ny} bilinear Q1 quadrilaterals, GetFEM assembly, lumped mass by",
        f"# row sums) dropping at 1000 mm/s onto the rigid plane y = 0, {fmt(GAP)} mm below it.",
        f"# Generated by `python3 generate.py{opts}` (examples/block/); do not edit by hand.",
        f"# dt = Courant {COURANT} x 2/omega_max (omega_max = {omega_max:.6e} rad/s, lumped), rounded down;",
        f"# t_end = first contact {fmt(t_contact)} s + {N_TRANSITS} x 2H/c_p (c_p = {c_p:.6e} mm/s), rounded up.",
        "[scene]",
        'kind = "matrices"',
        'units = "N, mm, s, t"',
        f"dt = {fmt(dt)}            # s",
        f"t_end = {fmt(t_end)}         # s",
        f'primary_contact = "{primary}"',
        "",
        "[scene.matrices]    # paths relative to this file",
        'mass = "M.mtx"',
        'stiffness = "K.mtx"',
        "",
        "[scene.dof_sets]",
        f"all_y = {all_y}",
        "",
        "[scene.initial]",
        f'velocity = {{ value = {fmt(V0)}, dofs = "all_y" }}',
    ]
    for name, d, area in contacts:
        lines += [
            "",
            "[[scene.contact]]",
            f'name = "{name}"',
            f"dof = {d}",
            'side = "lower"',
            f"gap = {fmt(GAP)}",
            f"area = {fmt(area)}",
        ]
    with open(os.path.join(outdir, "scene.toml"), "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")

    # ---- report ------------------------------------------------------------
    def ntri(a):
        return int(sp.triu(a).nnz)

    print(f"GetFEM assembly: {nx} x {ny} Q1 elements, W = {W} mm, H = {H} mm, plane strain")
    print(f"lambda = {lam:.6f} MPa, mu = {mu:.6f} MPa, c_p = {c_p:.6e} mm/s")
    print(f"DOFs: {n} (y DOFs every second from 1: {y_every_second}), bottom contacts: {len(contacts)}, "
          f"primary: {primary} (dof {contacts[k_mid][1]})")
    print(f"nnz K: {K.nnz} (lower triangle written: {ntri(K)}; {n_roundoff} round-off entries dropped), "
          f"M_consistent: {Mc.nnz} (written: {ntri(Mc)}), M lumped: {M.nnz}")
    print(f"omega_max (lumped) = {omega_max:.9e} rad/s  (f = {omega_max / (2 * np.pi):.6e} Hz)")
    print(f"dt = {COURANT} * 2/omega_max = {dt_exact:.9e} s -> {fmt(dt)} s")
    print(f"t_end = {t_contact:.3e} + {N_TRANSITS} * 2*{H}/c_p = {t_end_exact:.9e} s -> {fmt(t_end)} s "
          f"({t_end / dt:.1f} steps)")
    for fn in ("K.mtx", "M_consistent.mtx", "M.mtx", "dofs.csv", "scene.toml"):
        print(f"  {fn}: {os.path.getsize(os.path.join(outdir, fn))} bytes")

    if args.check:
        ok = check(mim, mf_u, K_raw, K, Mc, M, m_diag, comp, lam, mu, W, H, omega_max, v0, outdir)
        print("check:", "all passed" if ok else "FAILED")
        if not ok:
            sys.exit(1)


def check(mim, mf_u, K_raw, K, Mc, M, m_diag, comp, lam, mu, W, H, omega_max, v0, outdir):
    verdict = Verdicts()
    print("checks:")
    verdict.read_back(outdir, (("K.mtx", K), ("M_consistent.mtx", Mc), ("M.mtx", M)))
    knorm = spla.norm(K_raw, "fro")
    verdict("||K_written - K_assembled||_F / ||K||_F", spla.norm(K - K_raw, "fro") / knorm, 1e-15)
    verdict("asymmetry of assembled K, ||K - K^T||_F / ||K||_F",
            spla.norm(K_raw - K_raw.T, "fro") / knorm, 1e-14)
    tx = (comp == 0).astype(float)
    ty = (comp == 1).astype(float)
    for name, t in (("x", tx), ("y", ty)):
        verdict(f"||K t_{name}|| / (||K||_F ||t_{name}||)",
                np.linalg.norm(K @ t) / (knorm * np.linalg.norm(t)), 1e-13)
    # infinitesimal rotation (-y, x) is a third zero-energy mode
    nodes = np.asarray(mf_u.basic_dof_nodes())
    rot = np.where(comp == 0, -nodes[1], nodes[0])
    verdict("||K r|| / (||K||_F ||r||), r = rotation",
            np.linalg.norm(K @ rot) / (knorm * np.linalg.norm(rot)), 1e-13)
    mass = RHO * W * H * 1.0
    for name, t in (("x", tx), ("y", ty)):
        verdict(f"lumped mass in {name} vs rho W H = {mass:.6e} t (relative error)",
                abs(m_diag[t > 0].sum() - mass) / mass, 1e-13)
        verdict(f"consistent t_{name}^T Mc t_{name} vs rho W H (relative error)",
                abs(t @ (Mc @ t) - mass) / mass, 1e-13)
    # the same stiffness from GetFEM's generic assembly language
    n = K.shape[0]
    expr = "lambda*Div_Test_u*Div_Test2_u + 2*mu*Sym(Grad_Test_u):Grad_Test2_u"
    Kg = to_scipy(gf.asm_generic(mim, 2, expr, -1, "u", 1, mf_u, np.zeros(n),
                                 "lambda", 0, lam, "mu", 0, mu))
    verdict("||K_brick - K_generic||_F / ||K||_F", spla.norm(K_raw - Kg, "fro") / knorm, 1e-13)
    # positive semi-definite lumped mass, rigid body eigenfrequencies
    lam_top = spla.eigsh(K, k=1, M=M, sigma=1.5 * omega_max**2, which="LM", v0=v0,
                         return_eigenvectors=False)[0]
    verdict("omega_max: |shift-invert (K, M) - scaled LA| / omega_max",
            abs(np.sqrt(lam_top) - omega_max) / omega_max, 1e-9)
    shift = -1e-4 * omega_max**2
    ev = np.sort(spla.eigsh(K, k=6, M=M, sigma=shift, which="LM", v0=v0,
                            return_eigenvectors=False))
    om = np.sign(ev) * np.sqrt(np.abs(ev))
    print("  6 lowest eigenfrequencies (lumped M), rad/s:", " ".join(f"{w:.4e}" for w in om))
    print("                                         Hz:", " ".join(f"{w / (2 * np.pi):.4e}" for w in om))
    verdict("3 rigid modes: max |omega_rigid| / omega_4", np.max(np.abs(om[:3])) / om[3], 1e-5)
    evc = spla.eigsh(K, k=1, M=Mc, sigma=10.0 * omega_max**2, which="LM", v0=v0,
                     return_eigenvectors=False)[0]
    print(f"  (for comparison: omega_max with the consistent mass = {np.sqrt(evc):.6e} rad/s)")
    return verdict.ok


if __name__ == "__main__":
    main()
