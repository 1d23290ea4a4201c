"""Work–precision (study kind 'work-precision'): wall time against ε_p, ε_v and NoP_p of each
method at its recommended parameters, over meshes and Courant numbers, with each method's
frontier and the runs that are not ok on a strip over the panels.

fig_work_precision.png    results/work-precision.h5 (plans/work-precision.toml)
block-work-precision.png  results/block-work-precision.h5 (examples/block/work-precision.toml)
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import ticker as mticker
from matplotlib.lines import Line2D

from .model import is_model_results, model_primary_contact, model_reference_text
from .plot import log_axis_plain, save
from .results import Skip, load, text
from .scene import results_scene
from .style import SERIES_PER_PANEL, method_color, method_groups, num, pretty_spectral_label


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
    """The work-precision figure of the results file `name`.h5 (study kind 'work-precision')."""
    return [save(draw(load(results_dir, name), heading), out_dir, png)]


def draw(r, heading="Work–precision"):
    """Wall time against ε_p, ε_v and NoP_p of a work-precision results file, as a figure: one
    column per indicator, one row per group of at most six methods (style.method_groups), so that
    a panel holds few methods, each in its colour, with its Courant numbers as markers. On the rod
    the thin lines join the meshes of one Courant number; on a user's model (one mesh: `elements`
    is its DOF count) they join the Courant numbers of one method, its indicators are at the
    primary contact and measured against the model's converged reference, which the title names."""
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
    groups = method_groups(names)
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
    band_rows = 1 if np.any(bad) else 0
    fig = plt.figure(figsize=(5.0 * len(panels) + 2.6, 3.3 * len(groups) + 2.4 + 0.5 * band_rows),
                     layout="constrained")
    not_ok_text = ""
    gs = fig.add_gridspec(band_rows + len(groups), len(panels) + 1,
                          height_ratios=([0.3] if band_rows else []) + [3.3] * len(groups),
                          width_ratios=[5.0] * len(panels) + [2.6])
    for n, (key, sym) in enumerate(panels):
        y = np.where(status == 0, cube(key), np.nan)
        y = np.where(y > 0, y, np.nan)  # a log axis; NoP_p = 0 (no peak) cannot be drawn on it
        zeros = int(np.sum((status == 0) & (cube(key) <= 0)))
        fin = y[np.isfinite(y)]
        first = None
        for g, group in enumerate(groups):
            ax = fig.add_subplot(gs[band_rows + g, n], sharex=first, sharey=first)
            first = first or ax
            for i in group:
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
            if fin.size:
                lo, hi = np.log10(fin.min()), np.log10(fin.max())
                span = max(hi - lo, 0.3)
                full = span / 0.92
                ax.set_ylim(10 ** (lo - 0.04 * full), 10 ** (lo - 0.04 * full + full))
            tt = t_ms[done & np.isfinite(t_ms)]
            if tt.size:
                ax.set_xlim(tt.min() / 1.6, tt.max() * 1.6)
            if zeros and g == len(groups) - 1:
                ax.text(0.99, 0.02, f"{zeros} ok runs with {sym} = 0 not on the log axis", transform=ax.transAxes,
                        ha="right", va="bottom", fontsize=7.5, color="0.25")
            log_axis_plain(ax.xaxis)
            if key.startswith("nop"):
                if fin.size and fin.max() / fin.min() < 30:  # less than 1.5 decades: more than one label
                    ax.yaxis.set_major_locator(mticker.LogLocator(subs=(1.0, 2.0, 5.0)))
                log_axis_plain(ax.yaxis)
            ax.grid(True, which="major", alpha=0.3)
            if g == len(groups) - 1:
                ax.set_xlabel("wall time [ms] (fastest of the repeats, one thread)")
            else:
                ax.tick_params(labelbottom=False)
            ax.set_ylabel(f"{sym} [−]")
            if n == len(panels) - 1:  # the row's methods, beside its last panel
                key_ax = fig.add_subplot(gs[band_rows + g, len(panels)])
                key_ax.axis("off")
                key_ax.legend(handles=[Line2D([], [], color=colors[i], lw=2.6, label=labels[i]) for i in group],
                              loc="center left", fontsize=8, frameon=False)
            if g == 0 and not band_rows:
                top = ax
        if np.any(bad):
            ii, jj, kk = np.nonzero(bad)
            who = "; ".join(f"{labels[i].split(' (')[0]} at Courant {', '.join(num(c) for c in C[np.any(bad[i], axis=0)])}"
                            for i in range(M.size) if np.any(bad[i]))
            band = fig.add_subplot(gs[0, n], sharex=first)
            runs_text = f"{int(bad.sum())} run{'' if bad.sum() == 1 else 's'}"
            # which runs, once under the title: in the strip a long list squeezes the panels
            unstable_band(band, t_ms[ii, jj, kk], [colors[i] for i in ii], f"{runs_text}, no {sym}")
            not_ok_text = f"\nNot ok (× on the grey strips): {who}."
            top = band
        what = f"number of peaks of the {at}contact pressure" if key == "nop_p" else \
            f"relative error of the {at}{'contact pressure' if key == 'eps_p' else 'contact-node velocity'} (eq. 18)"
        top.set_title(f"({'abc'[n]}) {sym}: {what}", fontsize=9.5)
    keys = [[Line2D([], [], color="0.45", marker=mk, mec="white", ls="none", ms=6, label=f"Courant {num(c)}")
             for mk, c in zip(markers, C)],
            [Line2D([], [], color="0.45", lw=0.8, alpha=0.6,
                    label=f"thin line: one method, Courant {num(C.max())} → {num(C.min())}, left to right" if one_mesh
                    else f"thin line: one Courant number, n = {num(E.min())} → {num(E.max())} elements, left to right"),
             Line2D([], [], color="0.45", lw=2.6, alpha=0.85,
                    label="thick line (ε panels): the method's frontier,\nthe smallest error reached in that time or less")]]
    if np.any(bad):
        keys[1].append(Line2D([], [], color="0.3", marker="x", mew=2.0, ms=7, ls="none",
                              label="× on the grey strip: a run that is not ok (unstable\nor failed), at its wall time until it stopped"))
    fig.legend(handles=keys[0] + keys[1], loc="lower center", bbox_to_anchor=(0.5, 0.0), ncol=4, fontsize=8,
               frameon=False)
    fig.get_layout_engine().set(rect=(0, 0.9 / fig.get_figheight(), 1, 1 - 0.9 / fig.get_figheight()))
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
    rows_text = f" Methods in {len(groups)} rows of at most {SERIES_PER_PANEL}." if len(groups) > 1 else ""
    fig.suptitle(f"{heading}: wall time against accuracy, each method at its recommended parameters;{scene}\n"
                 f"Lower left is better: at a time budget, the lowest curve is the most accurate method. Wall time: "
                 f"{timing}.{rows_text}{not_ok_text}", fontsize=10)
    return fig
