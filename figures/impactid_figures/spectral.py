"""The spectral analysis on ü + ω²u = 0 over Ω = ω·Δt: the spectral radius, the algorithmic
damping ratio, the period error over Ω², the HHT δ of minimal period error, and the HHT
stability map with the edge of the not-ok simulations.

fig_spectral.png  results/spectral.h5 (plans/spectral.toml), with results/hht-delta-alpha.h5
                  for the edge of the not-ok runs, if it exists
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import colors as mcolors
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from .hht_plane import grid_2d, hht_lines
from .plot import cell_edges, save
from .results import Skip, load, load_spectral, text
from .style import method_color, num, pretty_spectral_label


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
