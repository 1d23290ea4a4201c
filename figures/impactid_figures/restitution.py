"""Paoli–Schatzman's impact law over its coefficient of restitution (core/contact/paoli_schatzman_law.hpp,
docs/remedies.md): ε_p, NoP_p and the energy at the end E/E0 of central difference on the bouncing
bar against e, one line per mesh.

fig_paoli_schatzman.png  results/paoli-schatzman.h5 (plans/paoli-schatzman.toml: a grid of
                         restitution × the bar's elements)
"""

import matplotlib.pyplot as plt
import numpy as np

from .plot import log_axis_plain, mark_not_ok, ok_values, save
from .results import Skip, load
from .scene import results_scene

ELEMENTS = "body.bar.segment.1.elements"


def fig_paoli_schatzman(results_dir, out_dir):
    r = load(results_dir, "paoli-schatzman")
    if r.dims != ["restitution", ELEMENTS]:
        raise Skip(f"{r.path}: expected the grid (restitution, {ELEMENTS}), found {r.dims}")
    e = np.asarray(r.data["restitution"], dtype=float)
    meshes = np.asarray(r.data[ELEMENTS], dtype=float)
    panels = [("eps_p", "ε_p [−]", "(a) relative error of the contact pressure ε_p (eq. 18)", "log"),
              ("nop_p", "NoP_p [−]", "(b) number of peaks NoP_p", "linear"),
              ("energy_ratio", "E_end / E0 [−]", "(c) energy at the end over the initial energy", "linear")]
    colors = plt.cm.viridis(np.linspace(0.0, 0.85, len(meshes)))
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6), constrained_layout=True)
    for ax, (key, ylabel, title, yscale) in zip(axes, panels):
        values = ok_values(ax, r, key)
        if values is None:
            continue
        for j, (n, color) in enumerate(zip(meshes, colors)):
            ax.plot(e, values[:, j], "-o", ms=3, lw=1.3, color=color, label=f"{n:g} elements")
        # A point not ok on any mesh is marked once at the bottom (unstable: energy growth).
        worst = np.max(r.status, axis=1) if r.status.ndim == 2 else r.status
        mark_not_ok(ax, e, worst)
        if key == "energy_ratio":
            ax.axhline(1.0, color="0.3", lw=0.8, ls="--", label="E0 (the exact solution's energy)")
        ax.set_yscale(yscale)
        if yscale == "log":
            log_axis_plain(ax.yaxis)
        ax.set_xlim(e.min(), e.max())
        ax.set_xlabel("restitution e [−]  (e = 0: Lagrange's multiplier)")
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="both", alpha=0.25)
        ax.legend(framealpha=0.92, fontsize=8)
    fig.suptitle("Paoli–Schatzman's impact law over the restitution e — central difference, the gap held on "
                 f"(u_n+1 + e·u_n−1)/(1 + e)\n{results_scene(r)}", fontsize=10)
    return [save(fig, out_dir, "fig_paoli_schatzman.png")]
