"""One method's two parameters, Fig. 4's layout for methods other than HHT: maps of ε_p and NoP_p
over the grid of a plan, the points that are not ok hatched, the smallest ε_p starred and the
practical region outlined.

fig_rho_bathe.png  ρ∞-Bathe over (γ, ρ∞): results/rho-bathe.h5 (plans/rho-bathe.toml)
fig_noh_bathe.png  Noh–Bathe explicit over (Courant, p): results/noh-bathe.h5
                   (plans/noh-bathe.toml); its not-ok points are those past the explicit
                   stability limit Courant = Ω_crit(p)/2
fig_kim_explicit.png  Kim's two-stage explicit scheme over (Courant, p): results/kim-explicit.h5
                   (plans/kim-explicit.toml); the same limit with its own Ω_crit(p)
fig_kr_alpha.png   KR-α explicit over (Courant, ρ∞): results/kr-alpha.h5 (plans/kr-alpha.toml);
                   unconditionally stable, so the Courant axis runs past central difference's 1
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Patch

from .hht_maps import outline_practical
from .hht_plane import grid_map
from .plot import save
from .results import load, text
from .scene import results_scene
from .style import method_info, num


def parameter_map_figure(results_dir, out_dir, name, png, xdim, ydim, xlabel, ylabel, over):
    """The maps of plan `name`'s results, titled "<the method's label> over <over>"."""
    r = load(results_dir, name)
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.2), constrained_layout=True)
    panels = [("eps_p", "log", "ε_p [−]", "(a) relative error of the contact pressure ε_p (eq. 18)"),
              ("nop_p", "linear", "NoP_p [−]", "(b) number of peaks NoP_p")]
    for ax, (key, norm, label, sub) in zip(axes, panels):
        x, y, z, st = grid_map(ax, r, key, xdim, ydim, xlabel, ylabel, norm, label, fig)
        handles = [Patch(facecolor="0.86", edgecolor="0.55", hatch="///", label="not ok")]
        ok = (st == 0) & np.isfinite(z)
        if np.any(ok):
            j, i = np.unravel_index(np.argmin(np.where(ok, z, np.inf)), z.shape)
            handles += ax.plot(x[i], y[j], "*", ms=15, color="white", mec="black", mew=1.0, zorder=6,
                               label=f"smallest {label.split(' ')[0]}: {num(round(z[j, i], 4))} "
                                     f"({xlabel.split(' ')[0]} = {num(round(x[i], 4))}, "
                                     f"{ylabel.split(' ')[0]} = {num(round(y[j], 4))})")
        handles += outline_practical(ax, r, xdim, ydim)
        ax.set_title(sub, fontsize=10)
        ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.12), fontsize=8.5, framealpha=0.92)
    method = text(r.attr("method", ""))
    title = f"{method_info(method)[0]} over {over}"
    fig.suptitle(f"{title} — {method}; {results_scene(r)}", fontsize=10)
    return [save(fig, out_dir, png)]


def fig_rho_bathe(results_dir, out_dir):
    return parameter_map_figure(results_dir, out_dir, "rho-bathe", "fig_rho_bathe.png", "substep_ratio",
                                "rho_inf", "γ [−]", "ρ∞ [−]", "its sub-step ratio γ and ρ∞")


def fig_noh_bathe(results_dir, out_dir):
    return parameter_map_figure(results_dir, out_dir, "noh-bathe", "fig_noh_bathe.png", "courant", "p",
                                "Courant [−]", "p [−]", "the Courant number and p")


def fig_kim_explicit(results_dir, out_dir):
    return parameter_map_figure(results_dir, out_dir, "kim-explicit", "fig_kim_explicit.png", "courant", "p",
                                "Courant [−]", "p [−]", "the Courant number and p")


def fig_kr_alpha(results_dir, out_dir):
    return parameter_map_figure(results_dir, out_dir, "kr-alpha", "fig_kr_alpha.png", "courant", "rho_inf",
                                "Courant [−]", "ρ∞ [−]", "the Courant number and ρ∞")
