"""The HHT-α (δ, α) plane, shared by Fig. 4's family, the spectral figure, the NLopt search and
the stability map: a surface of a 2-D grid (`grid_2d`), its colour map (`hht_map`), the lines
δ = −1.5α (eq. 19) and δ = −α (eq. 15), and the stability the spectral analysis predicts
(`predicted_stable`: the `stable` map of results/spectral.h5, else the closed form δ ≥ −α).
Draws into the axes it is given.
"""

import numpy as np
from matplotlib import colors as mcolors
from matplotlib import patheffects as mpatheffects
from matplotlib import ticker as mticker
from matplotlib.patches import Rectangle

from .plot import cell_edges, log_axis_plain
from .results import Skip, load_spectral
from .style import CMAP, num


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
    return grid_map(ax, r, key, "delta", "alpha", "δ [−]", "α [−]", norm_kind, cbar_label, fig, valid)


def grid_map(ax, r, key, xdim, ydim, xlabel, ylabel, norm_kind="log", cbar_label="", fig=None, valid=None):
    """pcolormesh of the surface `key` of a 2-D grid over (xdim, ydim), on the cells `valid`
    (default: the ok ones); the others are hatched grey. Returns (x, y, z, status)."""
    x, y, z = grid_2d(r, key, xdim, ydim)
    _, _, st = grid_2d(r, "status", xdim, ydim)
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
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
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


def predicted_stable(results_dir, alpha, delta):
    """HHT stability over (alpha, delta) as the spectral study predicts it: the `stable` map of
    spectral.h5 at the nearest grid point (it is computed by core/spectral/amplification.hpp, not by a
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
