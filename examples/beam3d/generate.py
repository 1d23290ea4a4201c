#!/usr/bin/python3
"""Generate the "beam3d" example for impactid: Code_Aster's SDNV100 test, a 3D
steel beam striking a rigid wall, assembled with GetFEM at a chosen refinement.

Run with Debian's Python (needs python3-getfem, numpy, scipy):

    /usr/bin/python3 generate.py [--nx 100] [--nyz N] [--lateral fixed|free]
                                 [--out DIR] [--check]

Units: SI (N, m, s, kg), so a pressure is in Pa.

The test (Code_Aster's SDNV100, with the numbers issue 37 gives)
---------------------------------------------------------------
A beam of length L = 0.2 m and square section b x b = 0.02 m x 0.02 m, steel
E = 2e11 Pa, nu = 0.3, rho = 8000 kg/m^3, moves along its axis at v0 = 100 m/s
towards a rigid wall 2 mm ahead of its end face. The reference is the 1D wave
of the constrained modulus E_c = E (1 - nu) / ((1 + nu)(1 - 2 nu)): speed
c_p = sqrt(E_c / rho), contact pressure rho c_p v0 for 2 L / c_p after the
first contact at gap / v0, the struck face at rest meanwhile, then rebounding
at -v0. Written at the run's samples as reference.csv, from t = 0 to four
steps past t_end so that runs at other steps (a sweep over dt) stay inside it.

Model
-----
* Box [0, L] x [0, b] x [0, b], structured mesh of nx x nyz x nyz hexahedra
  (gf.Mesh('cartesian', X, Y, Z)), trilinear Lagrange elements FEM_QK(3,1),
  integration IM_GAUSS_PARALLELEPIPED(3,2) (exact for the mass and stiffness
  of affine boxes). nyz defaults to nx b / L rounded (cubes).
* --lateral fixed (default: every node's y and z displacements are zero, the
  condition under which the constrained-modulus 1D reference is exact): the unknowns are the x displacements only, one
  per node, and the stiffness is the x-x block of linear elasticity,
  (lambda + 2 mu) d_x u d_x v + mu (d_y u d_y v + d_z u d_z v), assembled as
  such with GetFEM's generic assembly language (--check compares it with the
  x-x block of gf.asm_linear_elasticity). A field uniform over the section
  then stays uniform, so each line of nodes along x is a 1D rod of modulus E_c
  with lumped mass: the 1D reference is this model's limit under refinement
  in x.
* --lateral free: 3 DOFs per node (gf.asm_linear_elasticity), the faces free.
  The beam's end then spreads sideways under the impact: the pressure starts
  at rho c_p v0 (at first the section cannot expand: plane strain) and falls
  towards rho c_0 v0, c_0 = sqrt(E / rho) the bar speed, as the lateral
  release waves cross the section; the contact lasts about 2 L / c_0. That is
  the 3D deviation from the 1D reference.
* Mass: rho gf.asm_mass_matrix, lumped by row sums (for trilinear boxes, each
  element gives an eighth of its mass to each of its nodes).
* Contacts: one per node of the struck face x = L, on its x DOF, side "upper"
  (u_x <= gap), gap = 2 mm, area = the node's tributary area of the face (so
  lambda / area is a pressure in Pa). primary_contact is the face's centre
  node (the one nearest it: the lower left of the four central nodes for an
  odd nyz).
* Initial velocity v0 on every x DOF, zero displacement.
* DOF numbering is GetFEM's (--lateral free: its interleaved components);
  dofs.csv gives each DOF's node coordinates and component (0 = x).

Time step and end time
----------------------
* omega_max: largest eigenvalue of M^{-1/2} K M^{-1/2} (M lumped) by
  scipy.sparse.linalg.eigsh (which='LA', fixed start vector);
  dt = 0.5 * 2 / omega_max (Courant 0.5 of central difference), rounded down
  to 3 significant digits.
* t_end = gap / v0 + 1.5 * 2 L / c_p, rounded up to 3 significant digits.

Outputs (in --out, default this script's folder; overwritten, byte-reproducible):
M.mtx (lumped, diagonal), K.mtx (Matrix Market coordinate real symmetric),
dofs.csv, reference.csv, scene.toml. They are generated, not kept in the
repository: the default (--nx 100) has 12,221 DOFs and a 5 MB K.mtx; --nx 220
about 10^5 DOFs, --nx 460 about 10^6 (--lateral fixed).

--check (not default) verifies with scipy: symmetry, K times a rigid
translation ~0, total lumped mass rho L b^2, the fixed-lateral stiffness equal
to the x-x block of gf.asm_linear_elasticity (meshes up to 2e4 DOFs), and
omega_max by shift-invert.
"""

import argparse
import math
import os
import sys
from decimal import ROUND_CEILING, ROUND_FLOOR

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import getfem as gf

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from getfem_export import Verdicts, fmt, round_sig, to_scipy, write_mtx  # noqa: E402

E = 2e11  # Pa
NU = 0.3
RHO = 8000.0  # kg/m^3
L = 0.2  # m
B = 0.02  # m, side of the square section
GAP = 0.002  # m
V0 = 100.0  # m/s, along +x
COURANT = 0.5
N_TRANSITS = 1.5  # times the two-way transit 2L/c_p after first contact
DROP_TOL = 1e-12  # relative to max|K|: assembled round-off entries of K below it are dropped
CHECK_BLOCK_MAX_DOFS = 20000  # --check assembles the full 3D problem up to this many x DOFs


def lame():
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    mu = E / (2 * (1 + NU))
    return lam, mu


def symmetrised(a):
    """(A + A^T)/2 with round-off entries (below DROP_TOL max|A|) dropped; and how many."""
    a = ((a + a.T) * 0.5).tocsc()
    small = np.abs(a.data) < DROP_TOL * np.abs(a.data).max()
    dropped = int(np.count_nonzero(small))
    a.data[small] = 0.0
    a.eliminate_zeros()
    a.sort_indices()
    return a, dropped


def components(mim, mf_u, n):
    """The component (0, 1, 2) of each DOF of a vector MeshFem: the load e_c . phi_i is
    non-zero only on the DOFs of component c."""
    zero = np.zeros(n)
    loads = [np.asarray(gf.asm_generic(mim, 1, f"{e}.Test_u", -1, "u", 1, mf_u, zero))
             for e in ("[1,0,0]", "[0,1,0]", "[0,0,1]")]
    nonzero = np.array([load != 0 for load in loads])
    assert np.all(nonzero.sum(axis=0) == 1), "each DOF must be exactly one component"
    return np.argmax(nonzero, axis=0)


def assemble(nx, nyz, lateral):
    """Mesh, matrices and DOF table of the beam: (K, Mc, nodes [3 x n], comp, mim, mf_u)."""
    X = np.linspace(0.0, L, nx + 1)
    Y = np.linspace(0.0, B, nyz + 1)
    mesh = gf.Mesh("cartesian", X, Y, Y)
    mim = gf.MeshIm(mesh, gf.Integ("IM_GAUSS_PARALLELEPIPED(3,2)"))
    lam, mu = lame()
    if lateral == "fixed":
        mf_u = gf.MeshFem(mesh, 1)
        mf_u.set_fem(gf.Fem("FEM_QK(3,1)"))
        n = int(mf_u.nbdof())
        expr = ("(lambda + 2*mu)*Grad_Test_u(1)*Grad_Test2_u(1)"
                " + mu*(Grad_Test_u(2)*Grad_Test2_u(2) + Grad_Test_u(3)*Grad_Test2_u(3))")
        K = to_scipy(gf.asm_generic(mim, 2, expr, -1, "u", 1, mf_u, np.zeros(n),
                                    "lambda", 0, lam, "mu", 0, mu))
        comp = np.zeros(n, dtype=int)
    else:
        mf_u = gf.MeshFem(mesh, 3)
        mf_u.set_fem(gf.Fem("FEM_QK(3,1)"))
        mf_d = gf.MeshFem(mesh, 1)
        mf_d.set_fem(gf.Fem("FEM_QK(3,0)"))
        n = int(mf_u.nbdof())
        nd = int(mf_d.nbdof())
        K = to_scipy(gf.asm_linear_elasticity(mim, mf_u, mf_d, np.full(nd, lam), np.full(nd, mu)))
        comp = components(mim, mf_u, n)
    Mc = (to_scipy(gf.asm_mass_matrix(mim, mf_u)) * RHO).tocsc()
    nodes = np.asarray(mf_u.basic_dof_nodes())
    return K, Mc, nodes, comp, mim, mf_u


def omega_max_of(K, m_diag):
    s = 1.0 / np.sqrt(m_diag)
    A = (sp.diags(s) @ K @ sp.diags(s)).tocsc()
    start = np.random.default_rng(12345).standard_normal(K.shape[0])
    top = spla.eigsh(A, k=1, which="LA", v0=start, tol=1e-12, return_eigenvectors=False)[0]
    return float(np.sqrt(top)), start


def exact_1d(t_contact, duration, pressure):
    """The 1D wave's (pressure, velocity) of the struck face at t; the mean at a jump (to
    1e-9 of the step), as impactid's exact solution of the paper's rod takes it."""
    def side(tt):
        if tt < t_contact:
            return 0.0, V0
        if tt < t_contact + duration:
            return pressure, 0.0
        return 0.0, -V0
    return side


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--nx", type=int, default=100, help="elements along the beam (default 100)")
    ap.add_argument("--nyz", type=int, default=None,
                    help="elements across each side of the section (default nx b/L, rounded)")
    ap.add_argument("--lateral", choices=("fixed", "free"), default="fixed",
                    help="y, z displacements: fixed (default; the 1D reference is exact) or free (3D)")
    ap.add_argument("--out", default=os.path.dirname(os.path.abspath(__file__)),
                    help="folder for the files (default: this script's)")
    ap.add_argument("--check", action="store_true", help="run the checks too")
    args = ap.parse_args()
    nx = args.nx
    nyz = args.nyz if args.nyz is not None else max(1, round(nx * B / L))
    if nx < 1 or nyz < 1:
        ap.error(f"--nx = {nx}, --nyz = {nyz}: each must be >= 1")
    os.makedirs(args.out, exist_ok=True)

    K_raw, Mc, nodes, comp, mim, mf_u = assemble(nx, nyz, args.lateral)
    n = K_raw.shape[0]
    K, n_roundoff = symmetrised(K_raw)
    m_diag = np.asarray(Mc.sum(axis=1)).ravel()  # row-sum lumping
    assert np.all(m_diag > 0)
    M = sp.diags(m_diag, format="csc")
    hx, hyz = L / nx, B / nyz
    ix = np.rint(nodes[0] / hx).astype(int)
    iy = np.rint(nodes[1] / hyz).astype(int)
    iz = np.rint(nodes[2] / hyz).astype(int)

    omega_max, start = omega_max_of(K, m_diag)
    dt = round_sig(COURANT * 2.0 / omega_max, 3, ROUND_FLOOR)
    lam, mu = lame()
    c_p = np.sqrt((lam + 2 * mu) / RHO)
    t_contact = GAP / V0
    duration = 2.0 * L / c_p
    t_end = round_sig(t_contact + N_TRANSITS * duration, 3, ROUND_CEILING)
    pressure = RHO * c_p * V0

    # contacts: the x DOFs of the struck face x = L, by (iy, iz)
    face = np.flatnonzero((ix == nx) & (comp == 0))
    face = face[np.lexsort((iy[face], iz[face]))]
    assert len(face) == (nyz + 1) ** 2
    contacts = []
    for d in face:
        j, k = int(iy[d]), int(iz[d])
        area = (hyz if 0 < j < nyz else hyz / 2) * (hyz if 0 < k < nyz else hyz / 2)
        contacts.append((f"face_{j}_{k}", int(d), area))
    centre = nyz // 2
    primary = f"face_{centre}_{centre}"

    # ---- write files -------------------------------------------------------
    out = args.out
    write_mtx(os.path.join(out, "K.mtx"), K)
    write_mtx(os.path.join(out, "M.mtx"), M)
    with open(os.path.join(out, "dofs.csv"), "w", newline="\n") as f:
        f.write("dof,node_x,node_y,node_z,component\n")
        for d in range(n):
            f.write(f"{d},{fmt(ix[d] * hx)},{fmt(iy[d] * hyz)},{fmt(iz[d] * hyz)},{comp[d]}\n")
    side = exact_1d(t_contact, duration, pressure)
    steps = math.ceil(t_end / dt - 1e-9)  # as impactid counts them (core/model/rod_scene.cpp)
    jump = 1e-9 * dt
    with open(os.path.join(out, "reference.csv"), "w", newline="\n") as f:
        f.write(f"# the 1D wave of the constrained modulus at the run's samples t = i dt: pressure "
                f"rho c_p v0 = {pressure:.6e} Pa for 2L/c_p = {duration:.6e} s from gap/v0\n")
        f.write(f"t,{primary}.pressure,{primary}.velocity\n")
        # From t = 0 to four steps past the run's last sample, so that a sweep over dt (a run's
        # samples linearly interpolated in this history) stays inside it up to 4x the step.
        for i in range(0, steps + 5):
            t = i * dt
            jumps = [s for s in (t_contact, t_contact + duration) if abs(t - s) <= jump]
            if jumps:
                (p0, v0), (p1, v1) = side(jumps[0] - 2 * jump), side(jumps[0] + 2 * jump)
                p, v = 0.5 * (p0 + p1), 0.5 * (v0 + v1)
            else:
                p, v = side(t)
            f.write(f"{fmt(t)},{fmt(p)},{fmt(v)}\n")

    x_every_third = args.lateral == "free" and np.array_equal(np.flatnonzero(comp == 0),
                                                               np.arange(0, n, 3))
    all_x = '"all"' if args.lateral == "fixed" else (
        '"0::3"' if x_every_third else "[" + ", ".join(str(int(d)) for d in np.flatnonzero(comp == 0)) + "]")
    command = f"generate.py --nx {nx} --nyz {nyz} --lateral {args.lateral}"
    lines = [
        f"# impactid example \"beam3d\": Code_Aster's SDNV100, a {fmt(L)} m x {fmt(B)} m x {fmt(B)} m",
        f"# steel beam ({nx} x {nyz} x {nyz} trilinear hexahedra, lateral displacements {args.lateral},",
        f"# GetFEM assembly, lumped mass by row sums, {n} DOFs) striking a rigid wall at {fmt(V0)} m/s,",
        f"# {fmt(GAP)} m ahead of its end face. Generated by `/usr/bin/python3 {command}`",
        "# (examples/beam3d/); do not edit by hand.",
        f"# dt = Courant {COURANT} x 2/omega_max (omega_max = {omega_max:.6e} rad/s, lumped), rounded down;",
        f"# t_end = first contact {fmt(t_contact)} s + {N_TRANSITS} x 2L/c_p (c_p = {c_p:.6e} m/s), rounded up.",
        "[scene]",
        'kind = "matrices"',
        'units = "N, m, s, kg"',
        f"dt = {fmt(dt)}",
        f"t_end = {fmt(t_end)}",
        f'primary_contact = "{primary}"',
        "",
        "[scene.matrices]    # paths relative to this file",
        'mass = "M.mtx"',
        'stiffness = "K.mtx"',
        "",
        "[scene.dof_sets]",
        f"all_x = {all_x}",
        "",
        "[scene.initial]",
        f'velocity = {{ value = {fmt(V0)}, dofs = "all_x" }}',
        "",
        "[scene.reference]",
        'file = "reference.csv"',
    ]
    for name, d, area in contacts:
        lines += ["", "[[scene.contact]]", f'name = "{name}"', f"dof = {d}", 'side = "upper"',
                  f"gap = {fmt(GAP)}", f"area = {fmt(area)}"]
    with open(os.path.join(out, "scene.toml"), "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")

    print(f"GetFEM assembly: {nx} x {nyz} x {nyz} Q1 hexahedra, lateral {args.lateral}: {n} DOFs, "
          f"{len(contacts)} contacts (primary {primary}), nnz K {K.nnz} ({n_roundoff} round-off "
          f"entries dropped)")
    print(f"c_p = {c_p:.9e} m/s, rho c_p v0 = {pressure:.9e} Pa, 2L/c_p = {duration:.9e} s")
    print(f"omega_max (lumped) = {omega_max:.9e} rad/s, dt = {fmt(dt)} s, t_end = {fmt(t_end)} s "
          f"({steps} steps)")
    for fn in ("K.mtx", "M.mtx", "dofs.csv", "reference.csv", "scene.toml"):
        print(f"  {os.path.join(out, fn)}: {os.path.getsize(os.path.join(out, fn))} bytes")

    if args.check:
        ok = check(K_raw, K, M, m_diag, comp, nx, nyz, args.lateral, omega_max, start, out)
        print("check:", "all passed" if ok else "FAILED")
        if not ok:
            sys.exit(1)


def check(K_raw, K, M, m_diag, comp, nx, nyz, lateral, omega_max, start, out):
    verdict = Verdicts()
    print("checks:")
    verdict.read_back(out, (("K.mtx", K), ("M.mtx", M)))
    knorm = spla.norm(K_raw, "fro")
    verdict("asymmetry of assembled K, ||K - K^T||_F / ||K||_F",
            spla.norm(K_raw - K_raw.T, "fro") / knorm, 1e-14)
    tx = (comp == 0).astype(float)
    verdict("||K t_x|| / (||K||_F ||t_x||)", np.linalg.norm(K @ tx) / (knorm * np.linalg.norm(tx)),
            1e-13)
    mass = RHO * L * B * B
    verdict(f"lumped mass in x vs rho L b^2 = {mass:.6e} kg (relative error)",
            abs(m_diag[tx > 0].sum() - mass) / mass, 1e-13)
    if lateral == "fixed" and K.shape[0] <= CHECK_BLOCK_MAX_DOFS:
        K3, _, _, comp3, _, _ = assemble(nx, nyz, "free")
        x3 = np.flatnonzero(comp3 == 0)
        Kxx = K3[x3][:, x3]
        # The same nodes in both numberings? GetFEM numbers them alike for qdim 1 and 3.
        verdict("||K_fixed - x-x block of asm_linear_elasticity||_F / ||K||_F",
                spla.norm(K_raw - Kxx, "fro") / knorm, 1e-13)
    top = spla.eigsh(K, k=1, M=M, sigma=1.5 * omega_max**2, which="LM", v0=start,
                     return_eigenvectors=False)[0]
    verdict("omega_max: |shift-invert (K, M) - scaled LA| / omega_max",
            abs(np.sqrt(top) - omega_max) / omega_max, 1e-9)
    return verdict.ok


if __name__ == "__main__":
    main()
