"""HHT-α over (δ, α), the paper's Fig. 4 and its layout: maps of ε_p and NoP_p over the points
predicted stable that ran ok, the linear instability the spectral analysis predicts hatched, the
chatter cells, the lines of eqs. 15 and 19, the smallest ε_p and the practical region.

fig4_hht_delta_alpha.png   results/hht-delta-alpha.h5 (plans/hht-delta-alpha.toml)
fig_hopkinson.png          results/hopkinson.h5 (plans/hopkinson.toml)
block-hht-delta-alpha.png  results/block-hht-delta-alpha.h5 (examples/block/hht-delta-alpha.toml)
each with results/spectral.h5 (plans/spectral.toml) for the predicted stability, if it exists.
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import colors as mcolors
from matplotlib import patheffects as mpatheffects
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from .hht_plane import grid_2d, hht_lines, hht_map, predicted_stable
from .model import middle_contact_text, model_primary_contact, model_reference_text
from .plot import cell_edges, practical_thresholds, save
from .results import load
from .scene import contact_text, primary_contact, results_scene
from .style import CHATTER_COLOR, PRACTICAL_COLOR, STATUS_TEXT, num


def outline_practical(ax, r, xdim="delta", ydim="alpha"):
    if not r.has("practical"):
        return []
    x, y, pr = grid_2d(r, "practical", xdim, ydim)
    pr = np.where(np.isfinite(pr), pr, 0.0)
    if not np.any(pr == 1):  # say so, as the 1-D figures do
        thresholds = practical_thresholds(r)
        return [Patch(facecolor="none", edgecolor=PRACTICAL_COLOR, lw=2.0,
                      label="practical region: no point" + (f" ({thresholds})" if thresholds else ""))]
    # outline the union of practical cells (their edges), not a contour through the centres
    xe, ye = cell_edges(x), cell_edges(y)
    fine = np.kron(pr, np.ones((4, 4)))
    xf = np.interp(np.arange(fine.shape[1]) / 4 + 0.125, np.arange(len(xe)), xe)
    yf = np.interp(np.arange(fine.shape[0]) / 4 + 0.125, np.arange(len(ye)), ye)
    ax.contour(xf, yf, fine, levels=[0.5], colors=[PRACTICAL_COLOR], linewidths=2.0, zorder=5)
    # name the region inside it, at its practical cell nearest the centroid
    jj, ii = np.nonzero(pr == 1)
    cx, cy = x[ii].mean(), y[jj].mean()
    k = np.argmin(((x[ii] - cx) / np.ptp(x)) ** 2 + ((y[jj] - cy) / np.ptp(y)) ** 2)
    ax.text(x[ii[k]], y[jj[k]], "practical", color="white", fontsize=10, fontweight="bold", ha="center",
            va="center", zorder=6, path_effects=[mpatheffects.withStroke(linewidth=2.5, foreground=PRACTICAL_COLOR)])
    label = f"practical region ({int(np.sum(pr == 1))} points"
    thresholds = practical_thresholds(r)
    label += f": {thresholds})" if thresholds else ")"
    return [Line2D([], [], color=PRACTICAL_COLOR, lw=2.0, label=label)]


def stability_handles(st, stable, source, closed_form, chatter_where="on the wall"):
    """Legend entries of Fig. 4's masks: the predicted-unstable cells (hatched) and, among them,
    those that still ran ok (dots), and the chatter cells (not ok although predicted stable).
    `source` is the second value of predicted_stable(); `closed_form` the map δ ≥ −α."""
    if source.startswith("spectral.h5"):
        omega = source.split("Ω = ")[-1].rstrip(")")
        rule = f"spectral.h5: ρ > 1 for some Ω ≤ {omega}"
        if np.array_equal(stable, closed_form):
            rule += ", i.e. δ < −α"
    else:
        rule = "δ < −α, eq. 15; no spectral.h5 on this grid"
    handles = [Patch(facecolor="0.86", edgecolor="0.55", hatch="///",
                     label=f"linearly unstable ({rule}), not drawn: {int(np.sum(~stable))} points")]
    slow = ~stable & (st == 0)
    if np.any(slow):
        handles.append(Line2D([], [], marker="o", ms=3.0, mfc="none", mec="0.25", mew=0.9, ls="none",
                              label=f"… of which ran ok: growth too slow for the horizon ({int(slow.sum())})"))
    chatter = stable & (st > 0)
    if np.any(chatter):
        codes = sorted({int(c) for c in np.unique(st[chatter])})
        what = " / ".join(STATUS_TEXT[c].replace("not ok: ", "") for c in codes)
        handles.append(Line2D([], [], marker="x", ms=6, mew=1.8, color=CHATTER_COLOR, ls="none",
                              label=f"{what} although predicted stable: chatter {chatter_where} ({int(chatter.sum())})"))
    return handles


def fig4(results_dir, out_dir):
    return hht_maps_figure(results_dir, out_dir, "hht-delta-alpha", "fig4_hht_delta_alpha.png",
                           "Fig. 4 — HHT-α with independent δ (eq. 13) and α (eq. 14)")


def fig_hopkinson(results_dir, out_dir):
    r = load(results_dir, "hopkinson")
    contact = primary_contact(r.plan.get("scene", {}), r.data)
    where = f"{contact.replace('-', '–')} " if contact and not contact.startswith("wall_") else ""
    return hht_maps_figure(
        results_dir, out_dir, "hopkinson", "fig_hopkinson.png",
        f"Split-Hopkinson striker on a bar — HHT-α over (δ, α), at the {contact_text(contact)} (exact reference: "
        "the chain's characteristics)", where=where, scene_sep="\n", paper_stage_label="paper's practical stage "
        "(on one rod) α ∈ [−0.5, −0.3] on eq. 19",
        chatter_where=f"at the {contact_text(contact)}" if contact else "at a contact")


def fig_block_hht(results_dir, out_dir):
    r = load(results_dir, "block-hht-delta-alpha")
    contact = model_primary_contact(r) or primary_contact({}, r.data)
    where = f"{contact} " if contact else ""
    return hht_maps_figure(
        results_dir, out_dir, "block-hht-delta-alpha", "block-hht-delta-alpha.png",
        f"2D elastic block dropped on a rigid plane (GetFEM plane-strain model) — HHT-α over (δ, α), at the "
        f"{contact_text(contact)}{middle_contact_text(r, contact)}\nReference: {model_reference_text(r)}",
        where=where, scene_sep="\n",
        paper_stage_label="paper's practical stage (on the rod) α ∈ [−0.5, −0.3] on eq. 19",
        chatter_where="at the contacts")


def fig_clamped_bar(results_dir, out_dir):
    return hht_maps_figure(
        results_dir, out_dir, "clamped-bar", "fig_clamped_bar.png",
        "Clamped bar released onto an obstacle (Doyen, Ern & Piperno 2011) — HHT-α over (δ, α), "
        "against its exact solution", scene_sep="\n",
        paper_stage_label="paper's practical stage (on the rod) α ∈ [−0.5, −0.3] on eq. 19",
        chatter_where="on the obstacle")


def fig_bouncing_bar(results_dir, out_dir):
    return hht_maps_figure(
        results_dir, out_dir, "bouncing-bar", "fig_bouncing_bar.png",
        "Bouncing bar under gravity (Doyen, Ern & Piperno 2011) — HHT-α over (δ, α), "
        "against its exact solution", scene_sep="\n",
        paper_stage_label="paper's practical stage (on the rod) α ∈ [−0.5, −0.3] on eq. 19",
        chatter_where="on the ground")


def hht_maps_figure(results_dir, out_dir, name, png, heading, where="", scene_sep="; ", paper_stage_label=None,
                    chatter_where="on the wall"):
    """Fig. 4's layout for the results file `name`.h5 (HHT over δ × α): maps of ε_p and NoP_p.
    `where` names the contact the indicators are taken at ("" for the paper's one contact),
    `chatter_where` where the chatter of the not-ok, predicted-stable runs happens."""
    r = load(results_dir, name)
    x, y, st = grid_2d(r, "status")
    # The mask is the linear stability the spectral analysis predicts, not the simulated status:
    # near δ = −α a linearly unstable run can end ok (slow growth), and it must not be read as data.
    stable, source = predicted_stable(results_dir, y, x)
    valid = stable & (st == 0)
    chatter = stable & (st > 0)
    slow = ~stable & (st == 0)
    fig, axes = plt.subplots(1, 2, figsize=(12.5, 5.9), constrained_layout=True)
    handles = []
    for ax, key, label, title in (
        (axes[0], "eps_p", "ε_p [−]", f"(a) relative error of the {where}contact pressure ε_p (eq. 18)"),
        (axes[1], "nop_p", "NoP_p [−]", f"(b) number of peaks of the {where}contact pressure NoP_p"),
    ):
        _, _, z, _ = hht_map(ax, r, key, "log", label, fig, valid=valid)
        lines = hht_lines(ax, x, y, paper_stage_label=paper_stage_label)
        jj, ii = np.nonzero(slow)
        ax.plot(x[ii], y[jj], "o", ms=3.0, mfc="none", mec="0.25", mew=0.9, ls="none", zorder=2)
        # a chatter cell is predicted stable: white, not hatched, under its cross
        ax.pcolormesh(cell_edges(x), cell_edges(y), np.ma.masked_where(~chatter, np.ones_like(z)),
                      cmap=mcolors.ListedColormap(["white"]), shading="flat", zorder=1)
        jj, ii = np.nonzero(chatter)
        ax.plot(x[ii], y[jj], "x", ms=6, mew=1.8, color=CHATTER_COLOR, ls="none", zorder=5)
        star = []
        zok = np.where(valid, z, np.nan)
        if key == "eps_p" and np.any(np.isfinite(zok)):
            j, i = np.unravel_index(np.nanargmin(zok), zok.shape)
            star = ax.plot(x[i], y[j], "*", ms=15, color="white", mec="black", mew=1.0, zorder=6, clip_on=False,
                           label=f"smallest ε_p = {zok[j, i]:.4f} at δ = {num(x[i])}, α = {num(y[j])}"
                                 " (of the stable, ok points)")
        practical = outline_practical(ax, r)
        ax.set_title(title)
        if not handles:
            closed_form = x[None, :] >= -y[:, None] - 1e-12
            handles = lines + star + stability_handles(st, stable, source, closed_form, chatter_where) + practical
    fig.legend(handles=handles, loc="lower center", ncol=2, frameon=False, bbox_to_anchor=(0.5, 0.0))
    fig.get_layout_engine().set(rect=(0, 0.17, 1, 0.83))
    fig.suptitle(f"{heading}{scene_sep}{results_scene(r)}")
    return [save(fig, out_dir, png)]
