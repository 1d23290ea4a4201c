"""The contact laws compared (core/contact/contact_treatment.hpp): ε_p, NoP_p and the largest penetration
of Lagrange multipliers, penalty springs and the augmented Lagrangian against the penalty
stiffness factor k / (E·A/h), one line per law.

fig_contact_laws.png  results/contact-laws.h5 (plans/contact-laws.toml: a grid with the law
                      as a choice axis, crossed with penalty_factor)
"""

import matplotlib.pyplot as plt
import numpy as np

from .plot import log_axis_plain, ok_values, save
from .results import Skip, load, text
from .scene import results_scene

LAW_STYLE = {  # colour and marker per law; Lagrange does not use k: a line to approach
    "lagrange": ("black", ""),
    "penalty": ("#D55E00", "o"),
    "augmented-lagrangian": ("#0072B2", "s"),
}


def fig_contact_laws(results_dir, out_dir):
    r = load(results_dir, "contact-laws")
    if r.dims != ["contact", "penalty_factor"]:
        raise Skip(f"{r.path}: expected the grid (contact, penalty_factor), found {r.dims}")
    laws = text(r.meta["contact"].get("flag_meanings", "")).split()
    k = np.asarray(r.data["penalty_factor"], dtype=float)
    panels = [("eps_p", "ε_p [−]", "(a) relative error of the contact pressure ε_p (eq. 18)", "log"),
              ("nop_p", "NoP_p [−]", "(b) number of peaks NoP_p", "linear"),
              ("max_penetration", "largest penetration [mm]", "(c) largest penetration into the wall", "log")]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6), constrained_layout=True)
    for ax, (key, ylabel, title, yscale) in zip(axes, panels):
        values = ok_values(ax, r, key)
        if values is None:
            continue
        for i, law in enumerate(laws):
            color, marker = LAW_STYLE.get(law, ("0.5", "^"))
            y = values[i]
            if key == "max_penetration" and law == "lagrange":
                continue  # no penetration: the multiplier holds the gap exactly
            if not np.any(np.isfinite(y)):
                continue
            style = "--" if law == "lagrange" else "-"
            ax.plot(k, y, style, marker=marker or None, ms=4, lw=1.4, color=color, label=law)
            bad = ~np.isfinite(y)
            if np.any(bad):
                ax.plot(k[bad], np.zeros(np.sum(bad)) if yscale == "linear" else np.full(np.sum(bad), np.nanmin(y)),
                        "x", color=color, ms=7, label=f"{law}: not ok")
        ax.set_xscale("log")
        ax.set_yscale(yscale)
        log_axis_plain(ax.xaxis)
        ax.set_xlabel("penalty_factor = k / (E·A/h) [−]")
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="both", alpha=0.25)
        ax.legend(framealpha=0.92, fontsize=9)
    method = text(r.attr("method", "hht"))
    fig.suptitle(f"Contact laws over the penalty stiffness — {method} at its defaults; {results_scene(r)}", fontsize=10)
    return [save(fig, out_dir, "fig_contact_laws.png")]
