"""Drawing helpers shared by the figure families: saving a PNG, the cell edges of a grid, the
practical range of a results file (its `practical` column shaded, its `practical_thresholds` as
dashed lines and in the legend), not-ok marks under a 1-D panel, the paper's practical stage as
a bar, plain numbers on log axes. They draw into the axes they are given and read no file.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import ticker as mticker
from matplotlib import transforms as mtransforms

from .results import texts
from .style import DPI, NOT_OK_COLOR, PAPER_COLOR, PRACTICAL_COLOR, STATUS_TEXT, num


def save(fig, out_dir, name):
    path = Path(out_dir) / name
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


def cell_edges(v):
    """Edges of the cells centred on the (sorted or reverse-sorted) values v."""
    v = np.asarray(v, dtype=float)
    if v.size == 1:
        return np.array([v[0] - 0.5, v[0] + 0.5])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def runs(mask):
    """(start, stop) index pairs, stop inclusive, of the runs of True in a 1-D mask."""
    out, start = [], None
    for i, m in enumerate(mask):
        if m and start is None:
            start = i
        if not m and start is not None:
            out.append((start, i - 1))
            start = None
    if start is not None:
        out.append((start, len(mask) - 1))
    return out


def interval_text(x, mask, symbol):
    parts = [f"[{num(x[a])}, {num(x[b])}]" if a != b else f"{{{num(x[a])}}}" for a, b in runs(mask)]
    return f"{symbol} ∈ " + " ∪ ".join(parts) if parts else ""


def practical_thresholds(r):
    t = r.attr("practical_thresholds")
    if t is None:
        return ""
    t = "; ".join(texts(t))
    for a, b in (("eps_p", "ε_p"), ("eps_v", "ε_v"), ("nop_p", "NoP_p"), ("nop_v", "NoP_v"), ("<=", "≤"), (">=", "≥")):
        t = t.replace(a, b)
    return t


def parse_thresholds(r):
    """practical_thresholds ('eps_p <= 0.03, nop_p <= 15', 'a <= x <= b', 'x >= a') as
    {indicator: (min or None, max or None)}; {} if absent or unreadable."""
    import re

    out = {}
    t = r.attr("practical_thresholds")
    if t is None:
        return out
    number = r"([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)"
    for part in "; ".join(texts(t)).replace(";", ",").split(","):
        part = part.strip()
        m = re.fullmatch(number + r"\s*<=\s*(\w+)\s*<=\s*" + number, part)
        if m:
            out[m.group(2)] = (float(m.group(1)), float(m.group(3)))
            continue
        m = re.fullmatch(r"(\w+)\s*(<=|>=)\s*" + number, part)
        if m:
            lo, hi = out.get(m.group(1), (None, None))
            if m.group(2) == "<=":
                hi = float(m.group(3))
            else:
                lo = float(m.group(3))
            out[m.group(1)] = (lo, hi)
    return out


def threshold_lines(ax, r, key, symbol):
    """Dashed horizontal lines at the practical thresholds of indicator `key`."""
    bounds = parse_thresholds(r).get(key)
    if not bounds:
        return
    label = "practical threshold"
    for value, op in zip(bounds, ("≥", "≤")):
        if value is not None:
            ax.axhline(value, color=PRACTICAL_COLOR, lw=1.1, ls="--", zorder=2,
                       label=f"{label} {symbol} {op} {num(value)}")


def mark_not_ok(ax, x, status, y_axes=0.03):
    """Crosses at the bottom of the axes where a 1-D study's point is not ok, one legend entry per status."""
    trans = mtransforms.blended_transform_factory(ax.transData, ax.transAxes)
    styles = {1: ("x", NOT_OK_COLOR), 2: ("+", NOT_OK_COLOR), -1: (".", "0.55")}
    for code, (marker, color) in styles.items():
        sel = status == code
        if np.any(sel):
            ax.plot(
                x[sel], np.full(sel.sum(), y_axes), marker, color=color, ms=7, mew=2, ls="none",
                transform=trans, clip_on=False, zorder=5, label=f"{STATUS_TEXT[code]} ({sel.sum()})",
            )


def log_axis_plain(axis):
    """Plain numbers (0.02, 50) rather than powers of ten on a logarithmic axis."""
    axis.set_major_formatter(mticker.FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(mticker.FuncFormatter(lambda v, _: ""))


def paper_bar(ax, lo, hi, label, y_axes=0.975):
    """A thick bar along the top of the axes over [lo, hi], labelled: the paper's 'practical stage'."""
    trans = mtransforms.blended_transform_factory(ax.transData, ax.transAxes)
    ax.plot([lo, hi], [y_axes, y_axes], color=PAPER_COLOR, lw=4, solid_capstyle="butt",
            transform=trans, clip_on=False, zorder=4)
    ax.text(lo, y_axes - 0.02, " " + label, transform=trans, ha="left", va="top", fontsize=8,
            color=PAPER_COLOR, zorder=4)


def shade_practical_1d(ax, r, x, symbol):
    """Shade the practical points of a 1-D study (the `practical` column); return whether any."""
    if not r.has("practical"):
        return False
    pr = np.asarray(r.data["practical"], dtype=float) == 1
    if not np.any(pr):
        thresholds = practical_thresholds(r)
        ax.axvspan(np.nan, np.nan, color=PRACTICAL_COLOR, alpha=0.13, lw=0,
                   label="practical range: no point" + (f" ({thresholds})" if thresholds else ""))
        return False
    edges = cell_edges(x)
    lo_clip, hi_clip = min(x[0], x[-1]), max(x[0], x[-1])
    label = f"practical range {interval_text(x, pr, symbol)}"
    thresholds = practical_thresholds(r)
    if thresholds:
        label += f"\n({thresholds})"
    for a, b in runs(pr):
        # a run spans its first to its last point; a single point gets its cell
        lo, hi = sorted((x[a], x[b]) if a != b else (edges[a], edges[b + 1]))
        ax.axvspan(max(lo, lo_clip), min(hi, hi_clip), color=PRACTICAL_COLOR, alpha=0.13, lw=0, label=label, zorder=0)
        label = None
    return True


def ok_values(ax, r, key):
    """The values of `key` at the file's ok points (NaN elsewhere); None, with a note on the panel
    `ax`, when the file has no `key`."""
    if not r.has(key):
        ax.text(0.5, 0.5, f"{key} not in {r.path.name}", transform=ax.transAxes, ha="center")
        return None
    return np.where(r.status == 0, np.asarray(r.data[key], dtype=float), np.nan)
