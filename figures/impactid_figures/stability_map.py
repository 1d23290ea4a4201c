"""The HHT stability map of issue 5: the status of every (δ, α) simulation at each Courant
number, coloured by whether it agrees with the spectral prediction.

fig_stability_map.png  results/stability-map.h5 (plans/stability-map.toml), with
                       results/spectral.h5 for the prediction (without it, the closed form δ ≥ −α)
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import colors as mcolors
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from .hht_plane import predicted_stable
from .plot import cell_edges, save
from .results import Skip, load
from .style import CHATTER_COLOR, num


def fig_stability_map(results_dir, out_dir):
    r = load(results_dir, "stability-map")
    if sorted(r.dims) != sorted(["courant", "alpha", "delta"]):
        raise Skip(f"{r.path}: expected the grid axes courant × alpha × delta, found {r.dims}")
    order = [r.dims.index(d) for d in ("courant", "alpha", "delta")]
    status = np.transpose(np.asarray(r.data["status"], dtype=float), order)
    C, A, D = (np.asarray(r.data[d], dtype=float) for d in ("courant", "alpha", "delta"))
    stable, source = predicted_stable(results_dir, A, D)
    # 0: ok and predicted stable; 1: not ok and predicted unstable (agreement);
    # 2: ok although predicted unstable; 3: not ok although predicted stable; −1: not run
    colors = ["#d9ecf7", "0.72", "#F0B000", CHATTER_COLOR]
    labels = ["ok, predicted stable", "unstable, predicted unstable",
              "ok although predicted unstable", "unstable although predicted stable"]
    cmap = mcolors.ListedColormap(colors)
    cmap.set_bad("white")
    ncol = min(4, C.size)
    nrow = int(np.ceil(C.size / ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(3.4 * ncol, 3.1 * nrow + 0.9), squeeze=False,
                             sharex=True, sharey=True)
    de, ae = cell_edges(D), cell_edges(A)
    for k, ax in enumerate(axes.flat):
        if k >= C.size:
            ax.set_visible(False)
            continue
        st = status[k]
        ok = st == 0
        cls = np.where(stable, np.where(ok, 0, 3), np.where(ok, 2, 1)).astype(float)
        cls[st < 0] = np.nan
        ax.grid(False)
        ax.pcolormesh(de, ae, np.ma.masked_invalid(cls), cmap=cmap, vmin=-0.5, vmax=3.5, shading="flat")
        line = np.linspace(ae.min(), ae.max(), 50)
        ax.plot(-line, line, color="black", lw=1.0, ls=":")
        n_dis = int(np.sum((cls == 2) | (cls == 3)))
        ax.set_title(f"Courant {num(C[k])}: {n_dis} disagree", fontsize=9)
        ax.set_xlim(de.min(), de.max())
        ax.set_ylim(ae.min(), ae.max())
        if k % ncol == 0:
            ax.set_ylabel("α [−]")
        if k // ncol == nrow - 1:
            ax.set_xlabel("δ [−]")
    handles = [Patch(facecolor=c, edgecolor="0.5", label=l) for c, l in zip(colors, labels)]
    handles.append(Line2D([], [], color="black", ls=":", lw=1.0, label="δ = −α (eq. 15; the stability edge)"))
    fig.legend(handles=handles, loc="lower center", ncol=3, fontsize=8, frameon=False)
    fig.suptitle(f"HHT-α on the rod: simulated status over (δ, α) at each Courant number, beside the "
                 f"prediction of {source}\n(orange: slow growth near the edge not caught in the horizon, "
                 f"or below the lowest mode; red: chattering on the wall — plans/README.md)", fontsize=9.5)
    fig.tight_layout(rect=(0, 0.07, 1, 0.95))
    return [save(fig, out_dir, "fig_stability_map.png")]
