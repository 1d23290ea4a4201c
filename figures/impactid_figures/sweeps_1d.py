"""Indicators over one parameter, the paper's Fig. 3 and its layout: ε_p and NoP_p against the
parameter on log axes, with the not-ok points, the smallest value, the paper's practical stage
and the practical range.

fig3_newmark_delta.png     Newmark over δ: results/newmark-delta.h5 (plans/newmark-delta.toml)
fig_two_rods.png           Newmark over δ on two rods: results/two-rods.h5 (plans/two-rods.toml)
fig_period_error_line.png  HHT-α along δ = −1.5α, over α: results/hht-period-error-line.h5
                           (plans/hht-period-error-line.toml)
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import ticker as mticker

from .plot import log_axis_plain, mark_not_ok, paper_bar, save, shade_practical_1d, threshold_lines
from .results import Skip, load
from .scene import contact_text, primary_contact, results_scene
from .style import method_color, num


def indicator_panels_1d(r, x, xlabel, symbol, color, keys, paper=None, secondary=None):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.6), constrained_layout=True)
    status = r.status
    for ax, (key, ylabel, title) in zip(axes, keys):
        if not r.has(key):
            ax.text(0.5, 0.5, f"{key} not in {r.path.name}", transform=ax.transAxes, ha="center")
            continue
        y = np.where(status == 0, np.asarray(r.data[key], dtype=float), np.nan)
        shade_practical_1d(ax, r, x, symbol)
        threshold_lines(ax, r, key, ylabel.split(" ")[0])
        ax.plot(x, y, "-o", color=color, ms=3.5, lw=1.3, label=f"{ylabel.split(' ')[0]} (ok points)", zorder=3)
        if np.any(np.isfinite(y)):
            i = int(np.nanargmin(y))
            ties = int(np.sum(y == y[i]))
            where = f"{symbol} = {num(round(x[i], 4))}" if ties == 1 else f"{ties} points, first {symbol} = {num(round(x[i], 4))}"
            ax.plot(x[i], y[i], "*", ms=13, color="white", mec="black", mew=1.0, zorder=6, clip_on=False,
                    label=f"smallest: {num(round(y[i], 4) if y[i] < 1 else y[i])} ({where})")
        mark_not_ok(ax, x, status)
        if paper:
            paper_bar(ax, *paper)
        ax.set_yscale("log")
        ax.yaxis.set_major_locator(mticker.LogLocator(subs=(1.0, 2.0, 5.0)))
        log_axis_plain(ax.yaxis)
        ax.set_xlim(min(x[0], x[-1]), max(x[0], x[-1]))
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.25)
        if secondary:
            sec = ax.secondary_xaxis("top", functions=secondary[0])
            sec.set_xlabel(secondary[1])
        ax.legend(loc="upper right", bbox_to_anchor=(1.0, 0.9), framealpha=0.92)
    return fig, axes


def newmark_delta_figure(results_dir, out_dir, name, png, title, paper_label, where="", scene_sep="; "):
    """Fig. 3's layout for the results file `name`.h5 (Newmark over δ): ε_p and NoP_p against δ.
    `where` names the contact the indicators are taken at ("" for the paper's one contact);
    `scene_sep` goes between the title and the scene ("\n" for a long title)."""
    r = load(results_dir, name)
    if r.dims != ["delta"]:
        raise Skip(f"{r.path}: expected one grid axis 'delta', found {r.dims}")
    x = np.asarray(r.data["delta"], dtype=float)
    keys = [
        ("eps_p", "ε_p [−]", f"(a) relative error of the {where}contact pressure (eq. 18)"),
        ("nop_p", "NoP_p [−]", f"(b) number of peaks of the {where}contact pressure"),
    ]
    fig, _ = indicator_panels_1d(r, x, "δ [−]  (β = (1+δ)²/4, γ = ½+δ, eq. 13)", "δ", method_color("newmark"), keys,
                                 paper=(0.3, 1.0, paper_label))
    fig.suptitle(f"{title}{scene_sep}{results_scene(r)}")
    return [save(fig, out_dir, png)]


def fig3(results_dir, out_dir):
    return newmark_delta_figure(results_dir, out_dir, "newmark-delta", "fig3_newmark_delta.png",
                                "Fig. 3 — Newmark method over δ", "paper's practical stage δ ∈ [0.3, 1]")


def fig_two_rods(results_dir, out_dir):
    r = load(results_dir, "two-rods")
    contact = primary_contact(r.plan.get("scene", {}), r.data)
    return newmark_delta_figure(
        results_dir, out_dir, "two-rods", "fig_two_rods.png",
        f"Two equal rods — Newmark method over δ, at the {contact_text(contact)} (exact reference: the chain's "
        "characteristics)", "paper's practical stage on one rod δ ∈ [0.3, 1]",
        where=f"{contact.replace('-', '–')} " if contact and not contact.startswith("wall_") else "", scene_sep="\n")


def fig_period_error_line(results_dir, out_dir):
    r = load(results_dir, "hht-period-error-line")
    if r.dims != ["alpha"] or not r.has("delta"):
        raise Skip(f"{r.path}: expected the grid axis 'alpha' and the coupled column 'delta', found {r.dims}")
    x = np.asarray(r.data["alpha"], dtype=float)
    keys = [
        ("eps_p", "ε_p [−]", "(a) relative error of the contact pressure (eq. 18)"),
        ("nop_p", "NoP_p [−]", "(b) number of peaks of the contact pressure"),
    ]
    fig, _ = indicator_panels_1d(
        r, x, "α [−]", "α", method_color("hht"), keys,
        paper=(-0.5, -0.3, "paper's practical stage α ∈ [−0.5, −0.3]"),
        secondary=((lambda a: -1.5 * a, lambda d: -d / 1.5), "δ = −1.5·α [−]"),
    )
    fig.suptitle(f"HHT-α along δ = −1.5·α (eq. 19, the minimal period error); {results_scene(r)}")
    return [save(fig, out_dir, "fig_period_error_line.png")]
