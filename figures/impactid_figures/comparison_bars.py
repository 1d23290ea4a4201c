"""The indicators of the methods at identical dissipation as bars, the paper's Figs 7 and 8,
with the practical thresholds and, under the figure they judge, the practical points.

fig7_compare_pressure.png  ε_p and NoP_p  results/identical-dissipation.h5
fig8_compare_velocity.png  ε_v and NoP_v  (plans/identical-dissipation.toml); a point's method
                                          from the file, its history or the plan
"""

import h5py
import matplotlib.pyplot as plt
import numpy as np

from .histories import find_history_dir
from .plot import parse_thresholds, practical_thresholds, save, threshold_lines
from .results import Skip, load, text
from .scene import results_scene
from .style import NOT_OK_COLOR, STATUS_TEXT, method_color, method_label


IDENTICAL_DISSIPATION = (
    r"Identical dissipation: equal algorithmic damping ratio $\bar\xi$ at Ω = ω·Δt = 1, matched to "
    "HHT-α with α = −0.3, δ = 0.45; a method that cannot reach it at its own or its most dissipative."
)


def list_methods(results_dir, r, name="identical-dissipation"):
    """The method and parameters of each point of a list study, in point order."""
    n = r.status.size
    methods = [None] * n
    if r.has("method"):  # a per-point method column, if the file has one
        methods = [text(m) for m in np.atleast_1d(r.data["method"])]
    if any(m is None for m in methods):
        try:
            folder = find_history_dir(results_dir, name)
            for k in range(n):
                p = folder / f"point-{k}.h5"
                if p.exists() and methods[k] is None:
                    with h5py.File(p, "r") as f:
                        methods[k] = text(f.attrs.get("method", ""))
        except Skip:
            pass
    if any(m is None for m in methods):
        default = r.plan.get("method", {}).get("name", text(r.attr("method", "hht")))
        points = r.plan.get("study", {}).get("points", [])
        for k in range(n):
            if methods[k] is None:
                methods[k] = points[k].get("method", default) if k < len(points) else default
    params = []
    for k in range(n):
        p = {}
        for key, meta in r.meta.items():
            if text(meta.get("role", "")) == "parameter":
                v = np.atleast_1d(r.data[key])[k]
                p[key] = v
        params.append(p)
    return methods, params


def compare_figure(results_dir, out_dir, which):
    r = load(results_dir, "identical-dissipation")
    if r.dims != ["point"]:
        raise Skip(f"{r.path}: expected a list study (dimension 'point'), found {r.dims}")
    methods, params = list_methods(results_dir, r)
    if which == "pressure":
        keys = [("eps_p", "ε_p [−]", "(a) relative error ε_p (eq. 18)"), ("nop_p", "NoP_p [−]", "(b) number of peaks NoP_p")]
        name, title = "fig7_compare_pressure.png", "Fig. 7 — Comparison of the methods: contact pressure"
    else:
        keys = [("eps_v", "ε_v [−]", "(a) relative error ε_v (eq. 18)"), ("nop_v", "NoP_v [−]", "(b) number of peaks NoP_v")]
        name, title = "fig8_compare_velocity.png", "Fig. 8 — Comparison of the methods: velocity of the contact node"
    n = len(methods)
    labels = [method_label(m, p, sep="\n") for m, p in zip(methods, params)]
    colors = [method_color(m) for m in methods]
    # Side by side for a few methods; one above the other, a bar an inch wide, for many, so that
    # the labels (method and parameters on separate lines) do not run into each other.
    if n <= 7:
        fig, axes = plt.subplots(1, 2, figsize=(12, 5.2), layout="constrained")
    else:
        fig, axes = plt.subplots(2, 1, figsize=(max(12, 1.05 * n), 10), layout="constrained")
    xpos = np.arange(n)
    for ax, (key, ylabel, sub) in zip(axes, keys):
        if not r.has(key):
            ax.text(0.5, 0.5, f"{key} not in {r.path.name}", transform=ax.transAxes, ha="center")
            continue
        v = np.where(r.status == 0, np.asarray(r.data[key], dtype=float), np.nan)
        bars = ax.bar(xpos, np.nan_to_num(v), color=colors, edgecolor="black", lw=0.6, width=0.7, zorder=3)
        top = np.nanmax(v) if np.any(np.isfinite(v)) else 1.0
        for i, (b, val) in enumerate(zip(bars, v)):
            if np.isfinite(val):
                s = f"{val:.4f}" if key.startswith("eps") else f"{int(round(val))}"
                ax.text(b.get_x() + b.get_width() / 2, val + 0.015 * top, s, ha="center", va="bottom", fontsize=9)
            else:
                code = int(r.status[i])
                ax.text(b.get_x() + b.get_width() / 2, 0.02 * top, STATUS_TEXT.get(code, "not ok").replace(": ", ":\n"),
                        ha="center", va="bottom", fontsize=8, color=NOT_OK_COLOR, rotation=90)
        bounds = parse_thresholds(r).get(key, (None, None))
        if bounds[1] is not None:
            top = max(top, bounds[1])
        threshold_lines(ax, r, key, ylabel.split(" ")[0])
        headroom = 1.12
        if ax.get_legend_handles_labels()[0]:
            ax.legend(loc="upper left", framealpha=0.92)
            headroom = 1.3  # the legend above the tallest bar and its value
        ax.set_ylim(0, headroom * top)
        ax.set_xticks(xpos, labels, fontsize=8.5)
        ax.set_ylabel(ylabel)
        ax.set_title(sub)
        ax.grid(True, axis="y")
        ax.grid(False, axis="x")
    scene = results_scene(r)
    fig.suptitle(f"{title}, identical dissipation; {scene}\n{IDENTICAL_DISSIPATION}", fontsize=10)
    # the practical points, under the figure whose indicators the thresholds are on (Fig. 7 for
    # the pressure thresholds of the plans); not under the other, whose bars they do not judge
    if r.has("practical") and practical_thresholds(r) and any(k in parse_thresholds(r) for k, _, _ in keys):
        pr = np.asarray(r.data["practical"], dtype=float) == 1
        names = [method_label(m, p) for m, p, ok in zip(methods, params, pr) if ok]
        fig.text(0.5, 0.005, f"Practical ({practical_thresholds(r)}): " + ("; ".join(names) if names else "none"),
                 ha="center", va="bottom", fontsize=9)
        fig.get_layout_engine().set(rect=(0, 0.04, 1, 0.96))
    return [save(fig, out_dir, name)]


def fig7(results_dir, out_dir):
    return compare_figure(results_dir, out_dir, "pressure")


def fig8(results_dir, out_dir):
    return compare_figure(results_dir, out_dir, "velocity")
