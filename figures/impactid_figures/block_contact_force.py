"""The total contact force of a user's model with many contacts (the block of examples/block):
F(t) = Σ p_k·A_k of the methods at identical dissipation against the model's converged
reference, the pressure at the primary contact, and zooms at the impact.

block-contact-force.png  results/histories/block-identical-dissipation/point-*.h5 and
                         results/block-identical-dissipation.h5
                         (examples/block/identical-dissipation.toml), with the contacts' areas
                         from the model's scene file (examples/block/scene.toml)
"""

import h5py
import matplotlib.pyplot as plt
import numpy as np

from .histories import find_history_dir
from .model import middle_contact_text, model_contact_areas, model_primary_contact, model_reference_text, \
    model_units, pressure_unit
from .plot import save
from .results import Skip, load, text
from .scene import contact_text, results_scene
from .style import EXACT_COLOR, STATUS_TEXT, method_color, method_label, num


def relative_error(ref, y):
    """eq. 18 on any history: sum_i |ref - y| / sum_i |ref|."""
    den = np.nansum(np.abs(ref))
    return float(np.nansum(np.abs(ref - y)) / den) if den > 0 else np.nan


def model_histories(results_dir, name):
    """The per-point histories of a user model's list study, with the contacts' pressures:
    (results, [(point, attrs, {dataset: array})]) for the points of the results file."""
    r = load(results_dir, name)
    folder = find_history_dir(results_dir, name)
    out = []
    for k in range(r.status.size):
        path = folder / f"point-{k}.h5"
        if not path.exists():
            continue
        with h5py.File(path, "r") as f:
            attrs = {a: (text(f.attrs[a]) if isinstance(f.attrs[a], (bytes, str)) else f.attrs[a]) for a in f.attrs}
            data = {d: np.asarray(f[d][()], dtype=float) for d in f if isinstance(f[d], h5py.Dataset)}
        for key in ("t", "pressure"):
            if key not in data:
                raise Skip(f"{path}: dataset {key!r} missing (layout of `impactid simulate --history`)")
        out.append((k, attrs, data))
    if not out:
        raise Skip(f"{folder}: no point-*.h5 files of the points of {r.path}")
    return r, out


def contact_force(data, areas, prefix="pressure"):
    """The total contact force sum_k p_k·A_k of a history's '<prefix>.<contact>' datasets."""
    return sum(data[f"{prefix}.{c}"] * a for c, a in areas.items())


def fig_block_contact_force(results_dir, out_dir):
    name = "block-identical-dissipation"
    r, hist = model_histories(results_dir, name)
    areas_all = model_contact_areas(r)
    if not areas_all:
        raise Skip(f"{r.path}: the model's scene file (with the contacts' areas) is not found: "
                   f"{r.plan.get('scene', '?')} beside {text(r.attr('model_files', '?'))}")
    _, _, first = hist[0]
    contacts = sorted({d.split(".", 1)[1] for d in first if d.startswith("pressure.")})
    missing = [c for c in contacts if c not in areas_all]
    if not contacts or missing:
        raise Skip(f"{r.path}: the histories' contacts {', '.join(missing) or '(none)'} are not in the scene file")
    if not all(f"reference_pressure.{c}" in first for c in contacts):
        raise Skip(f"{r.path}: the histories have no reference_pressure.<contact> datasets")
    areas = {c: areas_all[c] for c in contacts}
    primary = model_primary_contact(r)
    force_unit, length, time_unit = model_units(r)
    p_unit = pressure_unit(force_unit, length)
    scale, t_unit = (1e6, "µs") if time_unit == "s" else (1.0, time_unit)
    methods = [text(a.get("method", "?")) for _, a, _ in hist]
    ref_t = first["t"] * scale
    ref_force = contact_force(first, areas, "reference_pressure")
    ref_p = first[f"reference_pressure.{primary}"] if primary and f"reference_pressure.{primary}" in first else None

    fig = plt.figure(figsize=(14.5, 9.4), layout="constrained")
    gs = fig.add_gridspec(2, 2, width_ratios=[2.3, 1])
    ax_f, ax_p = fig.add_subplot(gs[0, 0]), fig.add_subplot(gs[1, 0])
    zoom_f, zoom_p = fig.add_subplot(gs[0, 1]), fig.add_subplot(gs[1, 1])
    ax_p.sharex(ax_f)
    zoom_p.sharex(zoom_f)
    # the impact: from a few steps before the reference's first contact force to some 25 steps after
    dt = float(np.median(np.diff(ref_t)))
    on = np.nonzero(ref_force > 0)[0]
    t_imp = ref_t[on[0]] if on.size else ref_t[0]
    lo, hi = t_imp - 4 * dt, t_imp + 24 * dt
    # the roughest curves behind the smooth ones (total variation of the force), the legend in point order
    forces = [contact_force(d, areas) for _, _, d in hist]
    variation = [np.nansum(np.abs(np.diff(f))) for f in forces]
    order = np.argsort(np.argsort(-np.asarray(variation)))
    handles = []
    for (k, attrs, data), method, force, rank in zip(hist, methods, forces, order):
        color = method_color(method)
        label = f"{method_label(method, attrs)}: ε_F = {relative_error(ref_force, force):.4f}"
        if r.status[k] == 0 and r.has("eps_p") and r.has("nop_p"):
            label += (f"; {primary}: ε_p = {float(np.atleast_1d(r.data['eps_p'])[k]):.4f}, "
                      f"NoP_p = {num(np.atleast_1d(r.data['nop_p'])[k])}")
        elif r.status[k] != 0:
            label += f"; {STATUS_TEXT.get(int(r.status[k]), 'not ok')}"
        t = data["t"] * scale
        for ax, y in ((ax_f, force), (zoom_f, force), (ax_p, data["pressure"]), (zoom_p, data["pressure"])):
            line, = ax.plot(t, y, color=color, lw=1.1 if ax in (ax_f, ax_p) else 1.4, zorder=2 + 0.1 * rank,
                            label=label, marker="o" if ax in (zoom_f, zoom_p) else None, ms=2.5)
        handles.append(line)
    ref_label = f"reference: {model_reference_text(r).split(' (')[0]}"
    for ax, y in ((ax_f, ref_force), (zoom_f, ref_force), (ax_p, ref_p), (zoom_p, ref_p)):
        if y is not None:
            line, = ax.plot(ref_t, y, color=EXACT_COLOR, lw=1.4, ls="--", zorder=3, label=ref_label)
    handles.append(line)
    where = f"{contact_text(primary)}{middle_contact_text(r, primary)}"
    ax_f.set_title(f"(a) total contact force of the {len(contacts)} contacts, F = Σ p_k·A_k (the areas of the "
                   "scene file); boxes: the zooms")
    ax_p.set_title(f"(b) contact pressure p at the {where}, the primary contact")
    zoom_f.set_title("(c) F, zoom at impact (dots: the samples)")
    zoom_p.set_title(f"(d) p at {primary}, zoom at impact")
    for ax in (ax_f, zoom_f):
        ax.set_ylabel(f"total contact force F [{force_unit}]")
    for ax in (ax_p, zoom_p):
        ax.set_ylabel(f"contact pressure p [{p_unit}]")
        ax.set_xlabel(f"t [{t_unit}]")
    ax_f.set_xlim(0, ref_t[-1])
    zoom_f.set_xlim(lo, hi)
    for ax in (ax_f, zoom_f):
        ax.tick_params(labelbottom=False)
    for ax, z in ((ax_f, zoom_f), (ax_p, zoom_p)):
        _, connectors = ax.indicate_inset_zoom(z, edgecolor="0.3", alpha=0.9)
        for c in connectors:  # they would cross the figure: keep only the box
            c.set_visible(False)
    fig.legend(handles=handles, loc="lower center", ncol=2, frameon=False, fontsize=8.5,
               title="ε_F: eq. 18 on the total force F; ε_p, NoP_p: the study's indicators at " + str(primary)
               + " (eq. 18, number of peaks)", title_fontsize=8.5)
    fig.get_layout_engine().set(rect=(0, 0.11, 1, 0.89))
    fig.suptitle(f"2D elastic block dropped on a rigid plane — the five methods at identical dissipation "
                 f"(as Figs 5–6 on the rod)\n{results_scene(r)}\nReference: {model_reference_text(r)}")
    return [save(fig, out_dir, "block-contact-force.png")]
