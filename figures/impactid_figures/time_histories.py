"""Time histories at identical dissipation, the paper's Figs 5 and 6 and their layout: the
contact pressure or velocity of each method over t against the exact solution, the whole run,
zooms at the impact, at each jump of the exact pressure and at the release, and an inset on the
plateau after the impact.

fig5_pressure_history.png     results/histories/identical-dissipation/point-*.h5, with
fig6_velocity_history.png     results/identical-dissipation.h5 for the indicators
                              (plans/identical-dissipation.toml)
fig_stepped_rod_pressure.png  results/histories/stepped-rod/point-*.h5 and
fig_stepped_rod_velocity.png  results/stepped-rod.h5 (plans/stepped-rod.toml)
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from .histories import load_histories
from .plot import save
from .results import Results, Skip
from .scene import DEFAULT_SCENE, contact_text, primary_contact, results_scene, scene_text
from .style import EXACT_COLOR, INDICATOR_SYMBOLS, method_color, method_groups, method_label, num


def window_ylim(lines_xy, lo, hi, pad=0.08):
    ymin, ymax = np.inf, -np.inf
    for x, y in lines_xy:
        sel = (x >= lo) & (x <= hi) & np.isfinite(y)
        if np.any(sel):
            ymin, ymax = min(ymin, y[sel].min()), max(ymax, y[sel].max())
    if not np.isfinite(ymin):
        return None
    span = (ymax - ymin) or 1.0
    return ymin - pad * span, ymax + pad * span


def bulk_ylim(curves, exact, lo, hi, factor=0.3, pad=0.08):
    """The y-range of a zoom window [lo, hi] that shows the bulk of the curves: a curve whose
    excursion beyond the exact solution's range is more than `factor` times the exact jump and
    more than twice the next-largest excursion leaves the frame (Newmark's chatter at impact would
    otherwise flatten every other curve), and so do the curves above it when they are such a group
    (at most a third of the curves). curves: [(name, t, y)], exact: (t, y).
    Returns ((ymin, ymax) or None, [(name, min, max)] of the curves left out)."""
    te, ye = exact
    sel = (te >= lo) & (te <= hi) & np.isfinite(ye)
    if not np.any(sel):
        return window_ylim([(t, y) for _, t, y in curves] + [exact], lo, hi, pad), []
    emin, emax = ye[sel].min(), ye[sel].max()
    jump = (emax - emin) or abs(emax) or 1.0  # a constant exact solution: its level
    spans = []
    for name, t, y in curves:
        w = (t >= lo) & (t <= hi) & np.isfinite(y)
        if np.any(w):
            ymin, ymax = y[w].min(), y[w].max()
            spans.append((max(ymax - emax, emin - ymin, 0.0), name, ymin, ymax, t, y))
    spans.sort(key=lambda e: -e[0])
    # The outliers: the largest excursions above the widest-ranked gap of a factor 2 to the next
    # one, among the top third of the curves (two chattering methods, Bathe's and an unstable
    # Wilson-θ's, are each within 2× of the other but far beyond the rest).
    cut = 0
    for j in range(min(max(1, len(spans) // 3), len(spans) - 1)):
        if spans[j][0] > factor * jump and spans[j][0] > 2 * spans[j + 1][0]:
            cut = j + 1
    out = [(name, ymin, ymax) for _, name, ymin, ymax, _, _ in spans[:cut]]
    spans = spans[cut:]
    kept = [(t, y) for *_, t, y in spans] + [exact]
    return window_ylim(kept, lo, hi, pad), out


def least_covering(ax, rects):
    """Of the rectangles `rects` ([x0, y0, width, height] in axes coordinates), the first that the
    lines of `ax` cross least (their samples inside it): where an inset hides the least. The
    upper-left one for Figs 5-6; lower right when the pressure rises after the plateau (stepped rod)."""
    ax.get_ylim()  # the autoscaled limits, without drawing (a draw would shift the layout)
    to_axes = ax.transData + ax.transAxes.inverted()  # data to axes: the limits only
    counts = []
    for x0, y0, w, h in rects:
        n = 0
        for line in ax.get_lines():
            xy = to_axes.transform(np.column_stack([np.asarray(v, dtype=float) for v in line.get_data()]))
            n += int(np.sum((xy[:, 0] >= x0) & (xy[:, 0] <= x0 + w) & (xy[:, 1] >= y0) & (xy[:, 1] <= y0 + h)))
        counts.append(n)
    return rects[int(np.argmin(counts))]


def plateau_inset(ax, curves, exact, t_imp, dt_us, ylabel, legend=None):
    """An inset in panel (a) over the plateau after the impact (20 to 250 steps after it), its y-range
    magnified to the ripple that is left there: central difference's undamped ringing, which gives
    its large NoP_p, is a few kPa and invisible at the scale of the impact. A curve still far off
    (Newmark's chatter) leaves the inset's frame, as in bulk_ylim. Nothing is drawn when every
    curve has settled (the velocity, held at 0 in contact). The inset and its title end left of
    `legend` when the legend's labels (the methods' labels, from the registry) reach into it."""
    lo, hi = t_imp + 20 * dt_us, t_imp + 250 * dt_us
    te, ye = exact
    w = (te >= lo) & (te <= hi)
    if not np.any(w) or np.ptp(ye[w]) > 0:  # the inset is for a plateau of the exact solution
        return
    ylim, left_out = bulk_ylim(curves, exact, lo, hi, factor=0.01, pad=0.12)
    level = float(ye[w][0])
    if ylim is None or max(ylim[1] - level, level - ylim[0]) < 1e-4 * (abs(level) or 1.0):
        return
    half = max(ylim[1] - level, level - ylim[0])
    unit = ylabel[ylabel.index("[") + 1:-1]
    title = (f"the plateau after impact (t [µs]), magnified: {num(level)} ± {num(round(half, 4))} {unit}"
             + ("\n(" + ", ".join(n.split(" (")[0] for n, _, _ in left_out)
                + (" leaves" if len(left_out) == 1 else " leave") + " this frame)"
                if left_out else ""))
    rect = list(least_covering(ax, [[0.09, 0.47, 0.48, 0.43], [0.58, 0.08, 0.38, 0.29]]))
    if legend is not None:  # narrower, centred under its title, where long labels reach into it
        renderer = ax.figure.canvas.get_renderer()
        box = legend.get_window_extent(renderer).transformed(ax.transAxes.inverted())
        probe = ax.text(0, 0, title, fontsize=8, transform=ax.transAxes)
        half_title = 0.5 * probe.get_window_extent(renderer).width / ax.bbox.width
        probe.remove()
        room = box.x0 - 0.01 - rect[0]
        overlaps = box.y0 < rect[1] + rect[3] + 0.1 and box.y1 > rect[1] and box.x0 > rect[0] + 0.25
        if overlaps and room < max(rect[2], 0.5 * rect[2] + half_title):
            rect[2] = max(0.25, min(room, 2 * (room - half_title)))
    ins = ax.inset_axes(rect)
    for line in ax.get_lines():
        t, y = (np.asarray(v, dtype=float) for v in line.get_data())
        sel = (t >= lo - 5 * dt_us) & (t <= hi + 5 * dt_us)
        ins.plot(t[sel], y[sel], color=line.get_color(), ls=line.get_linestyle(), zorder=line.get_zorder(),
                 lw=0.8 if any(line.get_label().startswith(n) for n, _, _ in left_out) else 1.1)
    ins.set_xlim(lo, hi)
    ins.set_ylim(level - half, level + half)
    ins.tick_params(labelsize=7.5)
    ins.set_title(title, fontsize=8, pad=3)


def exact_pressure_jumps(h, t_imp, t_rel, margin):
    """The jumps of a history's exact pressure between the impact and the release, more than
    `margin` [µs] from either, as [(t [µs], before, after)]: the waves that reach the contact (from a
    step of a stepped rod, from the far end of a body). A jump sampled as the mean of its limits
    spans two samples: one jump."""
    p = h.data["exact_pressure"]
    t = h.t_us
    scale = np.nanmax(np.abs(p)) or 1.0
    changes = np.nonzero(np.abs(np.diff(p)) > 1e-6 * scale)[0]
    out = []
    k = 0
    while k < changes.size:
        i = changes[k]
        j = i
        while k + 1 < changes.size and changes[k + 1] == j + 1:  # the mean-of-limits sample
            k += 1
            j = changes[k]
        when = 0.5 * (t[i] + t[j + 1]) if j > i else t[i + 1]
        if t_imp + margin < when < t_rel - margin:
            out.append((when, float(p[i]), float(p[j + 1])))
        k += 1
    return out


def history_windows(hist, quantity, t_imp, t_rel, dt_us, max_windows=4):
    """The zoom windows of a history figure as [(what, lo, hi, title)], up to max_windows: the
    impact, each jump of the exact pressure in between (a wave from a step or a far end reaching the
    contact; none on the paper's rod), and the release if the run goes on after it (Figs 5-6).
    A velocity window at a pressure jump is left out when no curve's velocity moves there (a node
    held at v = 0 in contact); those jumps are returned as the second value, [(t, before, after)]."""
    ref = hist[0]
    t_end = float(ref.t_us[-1])
    windows = [("impact", t_imp - 6 * dt_us, t_imp + 45 * dt_us, f"zoom at impact, t = {t_imp:.1f} µs")]
    still = []
    jumps = exact_pressure_jumps(ref, t_imp, t_rel, 3 * dt_us)
    release_inside = t_rel + 15 * dt_us <= t_end
    room = max_windows - 1 - (1 if release_inside else 0)
    for when, before, after in jumps[:room]:
        # the numerical wave front is spread over some 40 steps before and after the exact one
        lo, hi = when - 40 * dt_us, min(when + 60 * dt_us, t_end)
        if quantity != "pressure":
            v0 = np.nanmax(np.abs(ref.data["exact_velocity"])) or 1.0
            moves = [np.ptp(h.data["velocity"][(h.t_us >= lo) & (h.t_us <= hi)]) > 1e-6 * v0 for h in hist]
            if not any(moves):
                still.append((when, before, after))
                continue
        windows.append((when, lo, hi, f"zoom at t = {when:.1f} µs, where the exact\npressure jumps from "
                                      f"{num(round(before, 3))} to {num(round(after, 3))} MPa"))
    if release_inside:
        # the pressure falls before the release; the velocity overshoots after it
        release = (t_rel - 85 * dt_us, t_rel + 15 * dt_us) if quantity == "pressure" else (t_rel - 15 * dt_us, t_rel + 85 * dt_us)
        windows.append(("release", *release, f"zoom at release, t = {t_rel:.1f} µs"))
    return windows, still


def history_figure(results_dir, out_dir, quantity, study="identical-dissipation", png=None, heading=None,
                   subject="at identical dissipation", scene_sep="; "):
    """Figs 5 and 6 (study 'identical-dissipation'), or the same layout for the histories of another
    list study: `png` and `heading` then name the figure, `subject` the comparison in its title.
    A scene of bodies (histories with per-contact columns) takes its scene from the study's results
    file and its exact reference from the chain's characteristics; the quantities are those of the
    primary contact."""
    folder, hist = load_histories(results_dir, study)
    if not hist:
        raise Skip(f"{folder}: no point-*.h5 files")
    ref = hist[0]
    bodies = any("." in k for k in ref.data)
    if quantity == "pressure":
        key, exact_key, ylabel, scale = "pressure", "exact_pressure", "contact pressure p [MPa]", 1.0
        name = png or "fig5_pressure_history.png"
        title = heading or "Fig. 5 — Time evolution of the contact pressure"
    else:
        key, exact_key, ylabel, scale = "velocity", "exact_velocity", "contact-node velocity v [mm/s]", 1.0
        name = png or "fig6_velocity_history.png"
        title = heading or "Fig. 6 — Time evolution of the velocity of the contact node"
    t_imp, t_rel = ref.jump_times()
    dt_us = float(ref.attrs.get("dt", np.median(np.diff(ref.data["t"])))) * 1e6
    windows, still = history_windows(hist, quantity, t_imp, t_rel, dt_us)

    # More than six methods: one block of panels per group of at most six (style.method_groups),
    # the same windows and scales in each, so that every curve can be told from its neighbours.
    groups = method_groups([h.method for h in hist])
    everyone = hist
    fig = plt.figure(figsize=(11 if len(windows) <= 2 else 14, 7.6 * len(groups)), layout="constrained")
    outer = fig.add_gridspec(len(groups), 1)
    letters = iter("abcdefghijklmnopqrstuvwxyz")
    for row, group in enumerate(groups):
        draw_history_block(fig, outer[row], [everyone[i] for i in group], windows, still, quantity, key, exact_key,
                           ylabel, scale, ref, bodies, t_imp, t_rel, dt_us, letters,
                           f"methods {row + 1} of {len(groups)}: " if len(groups) > 1 else "")
    results_path = Path(results_dir) / f"{study}.h5"
    if bodies and results_path.exists():  # a history file of a scene of bodies does not describe it
        scene = results_scene(Results(results_path))
    else:
        scene = scene_text({k: ref.attrs[k] for k in DEFAULT_SCENE if k in ref.attrs} | ({"dt": ref.attrs["dt"]} if "courant" not in ref.attrs and "dt" in ref.attrs else {}))
    fig.suptitle(f"{title} {subject}{scene_sep}{scene}")
    return [save(fig, out_dir, name)]


def draw_history_block(fig, cell, hist, windows, still, quantity, key, exact_key, ylabel, scale, ref, bodies,
                       t_imp, t_rel, dt_us, letters, group_text):
    """One block of Figs 5-6 in the grid cell `cell`: the whole run of the methods `hist` over the
    exact solution, and the zoom windows under it; panel letters from the iterator `letters`,
    `group_text` before the whole run's title when the methods are split into groups."""
    gs = cell.subgridspec(2, len(windows), height_ratios=[1.15, 1])
    ax = fig.add_subplot(gs[0, :])
    zooms = [fig.add_subplot(gs[1, k]) for k in range(len(windows))]
    series = []
    # the roughest curves behind the smooth ones (total variation), the legend in point order
    variation = [np.nansum(np.abs(np.diff(h.data[key]))) for h in hist]
    rank = {id(h): r for r, h in enumerate(sorted(hist, key=lambda h: -variation[hist.index(h)]))}
    ind = ("eps_p", "nop_p") if quantity == "pressure" else ("eps_v", "nop_v")
    for a in [ax] + zooms:
        for h in hist:
            y = h.data[key] * scale
            label = h.label()
            if all(k in h.indicators for k in ind):
                label += (f": {INDICATOR_SYMBOLS[ind[0]]} = {h.indicators[ind[0]]:.4f},"
                          f" {INDICATOR_SYMBOLS[ind[1]]} = {num(h.indicators[ind[1]])}")
            a.plot(h.t_us, y, color=method_color(h.method), lw=1.0 if a is ax else 1.3, label=label,
                   zorder=2 + 0.1 * rank[id(h)])
        a.plot(ref.t_us, ref.data[exact_key] * scale, color=EXACT_COLOR, lw=1.3, ls="--",
               label="exact (chain: characteristics)" if bodies else "exact (d'Alembert)", zorder=3)
    for h in hist:
        series.append((method_label(h.method, h.attrs), h.t_us, h.data[key] * scale))
    exact = (ref.t_us, ref.data[exact_key] * scale)
    ax.set_xlim(0, ref.t_us[-1])
    ax.set_xlabel("t [µs]")
    ax.set_ylabel(ylabel)
    if any(w[0] == "release" for w in windows):
        ax.set_title(f"({next(letters)}) {group_text}the whole run; boxes: the zoomed windows")
    elif t_rel >= ref.t_us[-1] - 2 * dt_us:
        ax.set_title(f"({next(letters)}) {group_text}the whole run, to the exact release at its last step (t = {t_rel:.1f} µs); "
                     "boxes: the zoomed windows")
    else:
        ax.set_title(f"({next(letters)}) {group_text}the whole run, in contact to its end; boxes: the zoomed windows")
    if still:  # say why the pressure jumps have no velocity zoom
        ax.text(0.5, 0.72, "in contact, the contact node stays at v = 0 (to round-off) through the jumps of the "
                "exact pressure at t = " + ", ".join(f"{w:.1f}" for w, _, _ in still) + " µs: no zoom there",
                transform=ax.transAxes, ha="center", va="bottom", fontsize=8.5, color="0.2",
                bbox=dict(boxstyle="round,pad=0.3", facecolor="white", edgecolor="0.6", alpha=0.92))
    for z, (what, lo, hi, zoom_title), letter in zip(zooms, windows, letters):
        z.set_xlim(lo, hi)
        ylim, left_out = bulk_ylim(series, exact, lo, hi)
        if ylim:
            z.set_ylim(*ylim)
        if left_out:  # say so, with the range the curve reaches (panel (a) shows it whole)
            for line in z.get_lines():  # and draw it thin, behind the curves it would hide
                if line.get_label() in {name for name, _, _ in left_out} or any(
                        line.get_label().startswith(name + ":") for name, _, _ in left_out):
                    line.set_linewidth(0.8)
            unit = ylabel[ylabel.index("[") + 1:-1]
            note = "\n".join(f"{name} leaves the frame: {num(round(a, 2))} to {num(round(b, 2))} {unit}"
                              for name, a, b in left_out) + " (see the whole run above)"
            z.text(0.98, 0.97, note, transform=z.transAxes, ha="right", va="top", fontsize=8,
                   color="0.15", zorder=6, bbox=dict(boxstyle="round,pad=0.3", facecolor="white",
                                                     edgecolor="0.6", alpha=0.92))
        z.set_xlabel("t [µs]")
        z.set_ylabel(ylabel)
        when = t_imp if what == "impact" else t_rel if what == "release" else what
        z.axvline(when, color="0.5", lw=0.8, ls=":", zorder=1)
        z.set_title(f"({letter}) {zoom_title}")
        _, connectors = ax.indicate_inset_zoom(z, edgecolor="0.3", alpha=0.9)
        for c in connectors:  # they would cross the figure: keep only the box
            c.set_visible(False)
    if quantity == "pressure" or not any(w[0] == "release" for w in windows):
        legend = ax.legend(loc="upper right", framealpha=0.92)
    else:  # the velocity oscillates after the release: the empty band between 0 and −v0 before it
        legend = ax.legend(loc="center left", bbox_to_anchor=(0.2, 0.40), framealpha=0.92, fontsize=8)
    plateau_inset(ax, series, exact, t_imp, dt_us, ylabel, legend)


def fig5(results_dir, out_dir):
    return history_figure(results_dir, out_dir, "pressure")


def fig6(results_dir, out_dir):
    return history_figure(results_dir, out_dir, "velocity")


def stepped_rod_history(results_dir, out_dir, quantity):
    where = "at the wall"
    path = Path(results_dir) / "stepped-rod.h5"
    if path.exists():
        try:
            where = f"at the {contact_text(primary_contact(Results(path).plan.get('scene', {})))}"
        except Skip:
            pass
    what = "pressure" if quantity == "pressure" else "velocity of the contact node"
    return history_figure(results_dir, out_dir, quantity, "stepped-rod", f"fig_stepped_rod_{quantity}.png",
                          f"Stepped rod — time evolution of the {what} {where}",
                          "at identical dissipation (as Figs 5–6)", scene_sep="\n")


def fig_stepped_rod_pressure(results_dir, out_dir):
    return stepped_rod_history(results_dir, out_dir, "pressure")


def fig_stepped_rod_velocity(results_dir, out_dir):
    return stepped_rod_history(results_dir, out_dir, "velocity")
