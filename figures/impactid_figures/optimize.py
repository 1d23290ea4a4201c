"""The NLopt search over the HHT surface: its evaluations in order over the ε_p map of Fig. 4,
each constraint as a contour of the grid, the best point, and a zoom on the end of the search.
With several searches (`starts`), each search's path is its own line from its start (a square).

fig_optimize.png   results/hht-optimize.h5 (plans/hht-optimize.toml) on results/hht-delta-alpha.h5
                   (plans/hht-delta-alpha.toml)
fig_multistart.png results/hht-multistart.h5 (plans/hht-multistart.toml), on the same grid
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import patheffects as mpatheffects
from matplotlib import ticker as mticker
from matplotlib.lines import Line2D

from .hht_plane import grid_2d, hht_lines, hht_map
from .plot import cell_edges, save
from .results import Skip, load, text
from .scene import results_scene
from .style import CMAP, INDICATOR_SYMBOLS, NOT_OK_COLOR, num


def objective_text(objective):
    if isinstance(objective, dict):
        return " + ".join(f"{num(w)}·{INDICATOR_SYMBOLS.get(k, k)}" if w != 1 else INDICATOR_SYMBOLS.get(k, k)
                          for k, w in objective.items())
    return INDICATOR_SYMBOLS.get(str(objective), str(objective))


def draw_evaluations(ax, o, best_ms=20):
    """The evaluations of an optimisation over (δ, α), in order, and its best point. Returns handles."""
    d = np.asarray(o.data["delta"], dtype=float)
    a = np.asarray(o.data["alpha"], dtype=float)
    feas = np.asarray(o.data.get("feasible", np.ones_like(d)), dtype=float) == 1
    ok = o.status == 0
    handles = []
    if o.has("start"):  # several searches: a path each, from its start
        search = np.asarray(o.data["start"], dtype=float)
        firsts = np.flatnonzero(np.r_[True, np.diff(search) != 0])
        for begin, end in zip(firsts, list(firsts[1:]) + [len(d)]):
            ax.plot(d[begin:end], a[begin:end], "-", color="white", lw=0.8, alpha=0.9, zorder=5)
        handles += ax.plot(d[firsts], a[firsts], "s", mfc="none", mec="white", mew=1.6, ms=9, zorder=6,
                           ls="none", label=f"start of a search ({len(firsts)})")
        for k, begin in enumerate(firsts):
            ax.annotate(str(int(search[begin])), (d[begin], a[begin]), xytext=(5, 4), textcoords="offset points",
                        color="white", fontsize=8, fontweight="bold", zorder=7,
                        path_effects=[mpatheffects.withStroke(linewidth=2.0, foreground="black")])
    else:
        ax.plot(d, a, "-", color="white", lw=0.8, alpha=0.9, zorder=5)
    handles += ax.plot(d[feas], a[feas], "o", mfc="white", mec="black", ms=5.5, zorder=6, ls="none",
                       label=f"feasible evaluation ({int(feas.sum())})")
    handles += ax.plot(d[~feas & ok], a[~feas & ok], "o", mfc="0.15", mec="white", ms=5.5, zorder=6, ls="none",
                       label=f"infeasible evaluation ({int((~feas & ok).sum())})")
    if np.any(~ok):
        handles += ax.plot(d[~ok], a[~ok], "x", color=NOT_OK_COLOR, ms=7, mew=2, zorder=6, ls="none",
                           label=f"not ok ({int((~ok).sum())})")
    bd, ba = o.attr("best_delta"), o.attr("best_alpha")
    if bd is not None and ba is not None:
        lab = f"best: δ = {num(round(float(bd), 4))}, α = {num(round(float(ba), 4))}"
        for key in ("eps_p", "nop_p"):
            v = o.attr(f"best_{key}")
            if v is not None:
                lab += f", {INDICATOR_SYMBOLS[key]} = {num(round(float(v), 4))}"
        handles += ax.plot([float(bd)], [float(ba)], "*", ms=best_ms, color="#F0E442", mec="black", mew=1.2,
                           zorder=7, ls="none", label=lab, clip_on=False)
    return handles


def fig_optimize(results_dir, out_dir, name="hht-optimize", out="fig_optimize.png"):
    o = load(results_dir, name)
    for key in ("delta", "alpha"):
        if not o.has(key):
            raise Skip(f"{o.path}: no {key!r} column: the figure needs a search over δ and α")
    try:
        r = load(results_dir, "hht-delta-alpha")
    except Skip as why:
        raise Skip(f"the ε_p surface is missing: {why}")
    fig, ax = plt.subplots(figsize=(9.0, 6.8), layout="constrained")
    x, y, z, st = hht_map(ax, r, "eps_p", "log", "ε_p [−] (the grid of hht-delta-alpha.h5)", fig)
    handles = hht_lines(ax, x, y, paper_stage=False)
    # each constraint on an indicator of the grid, as a contour of the grid
    study = o.plan.get("study", {})
    constraint_text = []
    stroke = [mpatheffects.withStroke(linewidth=3.4, foreground="white")]
    for key, bounds in study.get("constraints", {}).items():
        sym = INDICATOR_SYMBOLS.get(key, key)
        for side, op in (("min", "≥"), ("max", "≤")):
            if side not in bounds:
                continue
            limit = float(bounds[side])
            constraint_text.append(f"{sym} {op} {num(limit)}")
            if not r.has(key):
                continue
            _, _, grid = grid_2d(r, key)
            grid = np.where(st == 0, grid, np.nan)
            level = limit + (0.5 if key.startswith("nop") and side == "max" else -0.5 if key.startswith("nop") else 0)
            if np.nanmin(grid) < level < np.nanmax(grid):
                cs = ax.contour(x, y, grid, levels=[level], colors=["black"], linewidths=1.6, linestyles="-.",
                                zorder=4)
                for c in cs.collections:  # matplotlib 3.6: a ContourSet is not an Artist
                    c.set_path_effects(stroke)
                handles.append(Line2D([], [], color="black", lw=1.6, ls="-.", path_effects=stroke,
                                      label=f"{sym} = {num(limit)} on the grid (the constraint {sym} {op} {num(limit)})"))
    handles += draw_evaluations(ax, o)
    # a zoom on where the search ended
    d = np.asarray(o.data["delta"], dtype=float)
    a = np.asarray(o.data["alpha"], dtype=float)
    tail = slice(len(d) // 2, None)
    if len(d) >= 6 and not o.has("start"):
        dl, dh = np.nanmin(d[tail]), np.nanmax(d[tail])
        al, ah = np.nanmin(a[tail]), np.nanmax(a[tail])
        pd = max(0.15 * (dh - dl), 0.01 * np.ptp(x), 0.004)
        pa = max(0.15 * (ah - al), 0.01 * np.ptp(y), 0.002)
        if (dh - dl) < 0.3 * np.ptp(x) and (ah - al) < 0.3 * np.ptp(y):
            ins = ax.inset_axes([0.6, 0.3, 0.37, 0.3])
            ins.grid(False)
            xe, ye = cell_edges(x), cell_edges(y)
            ins.pcolormesh(xe, ye, np.ma.masked_where(st != 0, z), cmap=CMAP,
                           norm=ax.impactid_norm, shading="flat")
            draw_evaluations(ins, o, best_ms=11)
            bounds = study.get("parameters", {})
            dlo, dhi = bounds.get("delta", {}).get("from", x.min()), bounds.get("delta", {}).get("to", x.max())
            alo, ahi = bounds.get("alpha", {}).get("from", y.min()), bounds.get("alpha", {}).get("to", y.max())
            ins.set_xlim(max(dl - pd, dlo - 0.2 * pd), min(dh + pd, dhi + 0.2 * pd))
            ins.set_ylim(max(al - pa, alo - 0.2 * pa), min(ah + pa, ahi + 0.2 * pa))
            ins.xaxis.set_major_locator(mticker.MaxNLocator(4))
            ins.yaxis.set_major_locator(mticker.MaxNLocator(4))
            ins.tick_params(labelsize=7)
            ins.set_title(f"zoom: evaluations {len(d) // 2}–{len(d) - 1}", fontsize=7.5, pad=2)
            ax.indicate_inset_zoom(ins, edgecolor="white", alpha=1.0)
    algo = text(o.attr("algorithm", study.get("algorithm", "?")))
    term = text(o.attr("termination", "?"))
    if o.has("start"):
        searches = len(np.unique(np.asarray(o.data["start"], dtype=float)))
        term = f"{searches} searches"
    ax.legend(handles=handles, loc="upper right", fontsize=7.5, framealpha=0.92)
    ax.set_title(f"{algo}: minimise {objective_text(study.get('objective', 'eps_p'))}"
                 + (f" subject to {', '.join(constraint_text)}" if constraint_text else "")
                 + f"; {len(d)} evaluations, {term}", fontsize=9.5)
    fig.suptitle(f"HHT-α parameter search; {results_scene(o)}")
    return [save(fig, out_dir, out)]


def fig_multistart(results_dir, out_dir):
    return fig_optimize(results_dir, out_dir, "hht-multistart", "fig_multistart.png")
