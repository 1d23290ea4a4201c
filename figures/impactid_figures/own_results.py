"""Any file impactid writes, drawn by what it holds: `impactid plot FILE.h5` and
`impactid.plot(...)` (figures/plot_results.py is the command line). Unlike the other modules it
knows no plan: it reads the file's `format` and `study_kind` attributes (results/README.md).

  grid, 2 axes          one heat map per indicator over the two axes; cells that are not ok hatched,
                        unstable ones crossed, failed ones plussed; the practical region outlined
  grid, 3 or more axes  the same maps over the last two axes, one panel per value of the others
  grid, 1 axis; list    one panel per indicator over the axis (a list: over its points, named by
                        their parameters), with not-ok points marked and the practical range shaded
  optimize              the objective over the evaluations, and the search in its first two
                        parameters
  work-precision        wall time against the errors, the methods in small multiples
                        (work_precision.py)
  spectral              ρ, ξ̄ and the period error over Ω = ω·Δt, at most six methods a panel, and
                        the HHT stability map when the file has one
  history               (`impactid simulate --history`, a plan's [output] histories) pressure and
                        velocity over t against the file's exact or reference solution, the whole
                        run and a zoom at the first contact

plot_file(path, out_dir, fmt) returns the files written. A file that is not impactid's, or has
nothing to draw, raises BadFile with the reason; so does a damaged file (a dataset whose Fletcher32
checksum HDF5 refuses, or attributes and text that do not match the file's impactid_checksum).
"""

import math
import struct
import zlib
from pathlib import Path

import h5py
import matplotlib.pyplot as plt
import numpy as np
from matplotlib import colors as mcolors
from matplotlib import ticker as mticker
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from . import work_precision
from .spectral import spectral_styles
from .plot import cell_edges, log_axis_plain, mark_not_ok, practical_thresholds, shade_practical_1d, threshold_lines
from .results import Results, text, texts
from .style import (CMAP, DPI, EXACT_COLOR, INDICATOR_SYMBOLS, NOT_OK_COLOR, PRACTICAL_COLOR, method_color,
                    method_groups, method_label, num, pretty_spectral_label)


class BadFile(Exception):
    """A file that is not one impactid writes, or that holds nothing to draw."""


# Columns with role "indicator" that are no indicator of accuracy to draw as a surface.
NOT_DRAWN = {"practical", "wall_time_s", "wall_time_max_s", "steps", "dof_steps", "objective", "feasible"}
LOG_INDICATORS = {"eps_p", "eps_v", "p_max", "p_max_ratio", "energy_ratio", "wall_time_s"}
# The checksum of a file's attributes and text, as study/formats/hdf5_support.cpp computes it
# (metadata_checksum): objects by path, attributes by name, each item a field (8-byte
# little-endian length, then its bytes), CRC-32 over all fields.
CHECKSUM_ATTRIBUTE = "impactid_checksum"
DIMENSION_SCALE_ATTRIBUTES = {"CLASS", "NAME", "DIMENSION_LIST", "REFERENCE_LIST"}


def metadata_checksum(f):
    crc = 0

    def field(data):
        nonlocal crc
        crc = zlib.crc32(struct.pack("<Q", len(data)) + data, crc)

    def visit(obj, path):
        field(path.encode())
        for name in sorted(obj.attrs.keys(), key=lambda n: n.encode()):
            if name == CHECKSUM_ATTRIBUTE or name in DIMENSION_SCALE_ATTRIBUTES:
                continue
            value = obj.attrs[name]
            if isinstance(value, bytes):
                value = value.decode()
            if isinstance(value, str):
                field(name.encode())
                field(value.encode())
                continue
            value = np.asarray(value)
            if value.dtype.kind == "f":
                kind = "<f8"
            elif value.dtype.kind in "iu":
                kind = "<i8"
            else:
                continue  # references and other types are not covered
            field(name.encode())
            field(value.astype(kind).tobytes())
        if isinstance(obj, h5py.Group):
            for name in sorted(obj.keys(), key=lambda n: n.encode()):
                visit(obj[name], ("/" if path == "/" else path + "/") + name)
        elif obj.dtype.kind in "OSU":
            for item in np.asarray(obj.asstr()[()]).ravel():
                field(item.encode())

    visit(f, "/")
    return crc


def verify(f, path):
    """Raises BadFile when a dataset's stored checksum or the file's impactid_checksum refuses it."""
    for name, d in f.items():
        if isinstance(d, h5py.Dataset):
            try:
                d[()]
            except OSError as error:
                raise BadFile(f"{path}: {name}: data corrupted: its stored checksum does not match "
                              f"the bytes read ({error}); the file is damaged") from None
    if CHECKSUM_ATTRIBUTE in f.attrs and int(f.attrs[CHECKSUM_ATTRIBUTE]) != metadata_checksum(f):
        raise BadFile(f"{path}: the checksum of its attributes and text (/@{CHECKSUM_ATTRIBUTE}): data "
                      f"corrupted: the stored checksum does not match the attributes and text read "
                      f"(the file is damaged)")


STATUS_MARKS = {1: ("x", "unstable"), 2: ("+", "failed"), -1: (".", "not done")}


def plot_file(path, out_dir=None, fmt="png"):
    path = Path(path)
    if fmt not in ("png", "pdf"):
        raise BadFile(f"--format {fmt}: must be png or pdf")
    out_dir = Path(out_dir) if out_dir else path.with_name(path.stem + "-figures")
    try:
        with h5py.File(path, "r") as f:
            fmt_attr = text(f.attrs.get("format", ""))
            names = set(f.keys())
            verify(f, path)
    except OSError as error:
        raise BadFile(f"{path}: not an HDF5 file ({error})") from None
    out_dir.mkdir(parents=True, exist_ok=True)
    saver = Saver(out_dir, path.stem, fmt)
    if fmt_attr == "impactid-results-1":
        r = Results(path)
        if r.status.size == 0 or np.all(r.status == -1):
            raise BadFile(f"{path}: no point is done yet (status −1 everywhere); finish the run with --resume")
        kind = text(r.attr("study_kind", ""))
        if kind == "work-precision":
            return work_precision_file(r, saver)
        if kind == "optimize":
            return optimize_file(r, saver)
        if kind in ("grid", "list"):
            return sweep_file(r, saver, kind)
        raise BadFile(f"{path}: study_kind = {kind!r}: not one this program draws (grid, list, optimize, "
                      f"work-precision, spectral)")
    if fmt_attr == "impactid-spectral-1":
        return spectral_file(path, saver)
    if not fmt_attr and "t" in names and ("pressure" in names or any(n.startswith("pressure.") for n in names)):
        return history_file(path, saver)
    raise BadFile(f"{path}: format = {fmt_attr!r}: not a file impactid writes (a results file, "
                  f"impactid-results-1; a spectral file, impactid-spectral-1; or a history file with t and pressure)")


class Saver:
    def __init__(self, out_dir, stem, fmt):
        self.out_dir, self.stem, self.fmt, self.written = out_dir, stem, fmt, []

    def __call__(self, fig, what):
        path = self.out_dir / f"{self.stem}-{what}.{self.fmt}"
        fig.savefig(path, dpi=DPI)
        plt.close(fig)
        self.written.append(path)
        return path


# ---- results files ------------------------------------------------------------------------------

PREFERRED = ["eps_p", "nop_p", "eps_v", "nop_v", "p_max", "p_max_ratio", "energy_ratio", "contact_episodes",
             "max_penetration"]


def indicators(r):
    """The indicator columns to draw: the primary contact's (no dotted per-contact names), the
    paper's four first, without the columns of the reference and of timing; only those that an
    ok point has."""
    names = [n for n, meta in r.meta.items() if text(meta.get("role", "")) == "indicator" and n not in NOT_DRAWN
             and "." not in n and not n.startswith("reference_")]
    order = {n: i for i, n in enumerate(names)}
    names.sort(key=lambda n: (PREFERRED.index(n) if n in PREFERRED else len(PREFERRED), order[n]))
    out = []
    for name in names:
        v = np.asarray(r.data[name], dtype=float)
        if v.shape == r.status.shape and np.any(np.isfinite(v[r.status == 0])):
            out.append(name)
    return out


def symbol(r, name):
    unit = text(r.meta.get(name, {}).get("units", ""))
    unit = "" if unit in ("", "1") else f" [{unit}]"
    return INDICATOR_SYMBOLS.get(name, name) + unit


def axis_label(r, dim):
    unit = text(r.meta.get(dim, {}).get("units", ""))
    return dim + ("" if unit in ("", "1") else f" [{unit}]")


def choice_words(r, dim):
    meanings = r.meta.get(dim, {}).get("flag_meanings")
    return text(meanings).split() if meanings is not None else None


def title(r, what):
    plan = text(r.attr("plan_name", r.path.stem))
    method = text(r.attr("method", ""))
    if text(r.attr("study_kind", "")) == "list" and len(set(list_methods(r))) > 1:
        method = ""  # a list of methods: each point names its own
    thresholds = practical_thresholds(r)
    return (f"{plan}: {what}" + (f" — {method_label(method, {})}" if method else "")
            + (f"\npractical: {thresholds}" if thresholds else ""))


def sweep_file(r, saver, kind):
    dims = [d for d in r.dims if d in r.data] or ["point"]
    keys = indicators(r)
    if not keys:
        raise BadFile(f"{r.path}: no ok point has an indicator to draw")
    if kind == "list" or len(dims) == 1:
        return lines_1d(r, saver, dims[0], keys, kind)
    return maps(r, saver, dims, keys)


def list_methods(r):
    """The method of each point of a list: its plan's points (`method = ...`), else the plan's."""
    points = r.plan.get("study", {}).get("points", [])
    default = text(r.attr("method", ""))
    if len(points) != r.status.size:
        return [default] * r.status.size
    return [text(p.get("method", default)) if isinstance(p, dict) else default for p in points]


def point_labels(r):
    """The points of a list: the method and the parameters its plan gives each point."""
    points = r.plan.get("study", {}).get("points", [])
    methods = list_methods(r)
    labels = []
    for i in range(r.status.size):
        given = points[i] if i < len(points) and isinstance(points[i], dict) else {}
        params = {k: v for k, v in given.items() if k != "method"}
        label = method_label(methods[i], params) if methods[i] else ""
        extra = [f"{k} = {num(v) if isinstance(v, (int, float)) else v}" for k, v in params.items()
                 if k not in ("alpha", "delta", "rho_inf", "theta", "p", "substep_ratio", "beta", "gamma")]
        labels.append(f"{i}: " + ", ".join([label] + extra) if label or extra else str(i))
    return labels


def lines_1d(r, saver, dim, keys, kind):
    n = len(keys)
    cols = min(n, 3)
    rows = -(-n // cols)
    if kind == "list":
        x = np.arange(r.status.size, dtype=float)
        xlabel, ticks = "point", point_labels(r)
    else:
        x = np.asarray(r.data[dim], dtype=float)
        xlabel, ticks = axis_label(r, dim), None
        words = choice_words(r, dim)
        if words:
            ticks = words
    fig, axes = plt.subplots(rows, cols, figsize=(4.8 * cols, 3.9 * rows + (1.2 if ticks else 0)),
                             layout="constrained", squeeze=False)
    status = np.asarray(r.status).ravel()
    for ax, key in zip(axes.ravel(), keys):
        sym = symbol(r, key)
        y = np.where(status == 0, np.asarray(r.data[key], dtype=float).ravel(), np.nan)
        shade_practical_1d(ax, r, x, dim)
        threshold_lines(ax, r, key, INDICATOR_SYMBOLS.get(key, key))
        methods = list_methods(r) if kind == "list" else None
        if methods and len(set(methods)) > 1:
            # a list of methods: each point in its method's colour
            ax.scatter(x, y, c=[method_color(m) for m in methods], s=28, zorder=3, edgecolors="white",
                       linewidths=0.5, label="ok points, each in its method's colour")
        else:
            ax.plot(x, y, "-o" if kind != "list" else "o", color=method_color(text(r.attr("method", ""))), ms=4,
                    lw=1.2, label="ok points", zorder=3)
        mark_not_ok(ax, x, status)
        fin = y[np.isfinite(y)]
        if key in LOG_INDICATORS and fin.size and np.all(fin > 0) and fin.max() >= 10 * fin.min():
            ax.set_yscale("log")
            ax.yaxis.set_major_locator(mticker.LogLocator(subs=(1.0, 2.0, 5.0)))
            log_axis_plain(ax.yaxis)
        if ticks:
            ax.set_xticks(x if kind == "list" else x)
            ax.set_xticklabels(ticks, rotation=60 if kind == "list" else 0, ha="right" if kind == "list" else "center",
                               fontsize=7.5)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(sym)
        ax.set_title(sym)
    for ax in axes.ravel()[n:]:
        ax.set_visible(False)
    # one key under the panels, so that no key hides a point; each entry once
    seen = {}
    for ax in axes.ravel()[:n]:
        for handle, label in zip(*ax.get_legend_handles_labels()):
            seen.setdefault(label, handle)
    ncol = max(1, min(len(seen), int(fig.get_figwidth() // 4.2)))
    fig.legend(list(seen.values()), list(seen.keys()), loc="lower center", bbox_to_anchor=(0.5, 0.0), ncol=ncol,
               fontsize=8, frameon=False)
    height = 0.32 * (-(-len(seen) // ncol) + 1) + 0.2
    fig.get_layout_engine().set(rect=(0, height / fig.get_figheight(), 1, 1 - height / fig.get_figheight()))
    fig.suptitle(title(r, "the indicators over " + ("the points" if kind == "list" else dim)))
    saver(fig, "indicators")
    return saver.written


def geometric(v):
    """Whether axis values are spread over decades, as log-spaced values are: positive, more than a
    factor 20 end to end, and more even in their logarithms than in themselves."""
    v = np.asarray(v, dtype=float)
    if v.size < 3 or np.any(v <= 0) or v.max() < 20 * v.min():
        return False
    return np.std(np.diff(np.log(v))) / abs(np.mean(np.diff(np.log(v)))) < np.std(np.diff(v)) / abs(np.mean(np.diff(v)))


def edges(v):
    """Cell edges of axis values, in their logarithms when they are geometric."""
    return np.exp(cell_edges(np.log(v))) if geometric(v) else cell_edges(v)


def heat(ax, fig, x, y, z, st, practical, log, xlabel, ylabel, xwords, ywords, norm=None):
    """One heat map of z[y, x]; cells that are not ok hatched and marked by their status; the
    practical cells outlined. Returns the mesh (None when no cell has a value)."""
    xe, ye = edges(x), edges(y)
    if geometric(x) and not xwords:
        ax.set_xscale("log")
        log_axis_plain(ax.xaxis)
    if geometric(y) and not ywords:
        ax.set_yscale("log")
        log_axis_plain(ax.yaxis)
    ax.add_patch(plt.Rectangle((xe.min(), ye.min()), np.ptp(xe), np.ptp(ye), facecolor="0.86", edgecolor="0.55",
                               hatch="///", lw=0, zorder=0))
    zm = np.ma.masked_where((st != 0) | ~np.isfinite(z), z)
    mesh = None
    if zm.count():
        if norm is None:
            lo, hi = float(zm.min()), float(zm.max())
            norm = mcolors.LogNorm(lo, hi) if log and lo > 0 and hi > lo else mcolors.Normalize(lo, hi if hi > lo else lo + 1)
        mesh = ax.pcolormesh(xe, ye, zm, cmap=CMAP, norm=norm, shading="flat", zorder=1)
    X, Y = np.meshgrid(x, y)
    for code, (marker, _) in STATUS_MARKS.items():
        sel = st == code
        if np.any(sel):
            ax.plot(X[sel], Y[sel], marker, color=NOT_OK_COLOR if code > 0 else "0.45", ms=6 if code > 0 else 3,
                    mew=1.6, ls="none", zorder=4)
    if practical is not None and np.any(practical == 1):
        fine = np.kron(np.where(practical == 1, 1.0, 0.0), np.ones((4, 4)))
        xf = np.interp(np.arange(fine.shape[1]) / 4 + 0.125, np.arange(len(xe)), xe)
        yf = np.interp(np.arange(fine.shape[0]) / 4 + 0.125, np.arange(len(ye)), ye)
        ax.contour(xf, yf, fine, levels=[0.5], colors=[PRACTICAL_COLOR], linewidths=2.0, zorder=5)
    ax.set_xlim(xe.min(), xe.max())
    ax.set_ylim(ye.min(), ye.max())
    if xwords:
        ax.set_xticks(x, xwords)
    if ywords:
        ax.set_yticks(y, ywords)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(False)
    return mesh


def legend_handles(st, practical):
    handles = [Patch(facecolor="0.86", edgecolor="0.55", hatch="///", label="no value (not ok or not done)")]
    for code, (marker, what) in STATUS_MARKS.items():
        count = int(np.sum(st == code))
        if count:
            handles.append(Line2D([], [], marker=marker, color=NOT_OK_COLOR if code > 0 else "0.45", ls="none",
                                  mew=1.6, label=f"{what} ({count})"))
    if practical is not None:
        count = int(np.sum(practical == 1))
        handles.append(Line2D([], [], color=PRACTICAL_COLOR, lw=2.0,
                              label=f"practical region ({count} points)" if count else "practical region: no point"))
    return handles


def maps(r, saver, dims, keys):
    """Heat maps over the last two dimensions; with more, one panel per value of the leading ones."""
    ydim, xdim = dims[-2], dims[-1]
    lead = dims[:-2]
    shape = tuple(len(np.atleast_1d(r.data[d])) for d in dims)
    combos = list(np.ndindex(*shape[:-2])) if lead else [()]
    if len(combos) > 24:
        raise BadFile(f"{r.path}: {len(combos)} panels of ({ydim}, {xdim}) maps for the axes {', '.join(lead)}: "
                      "more than 24; export it (impactid export --csv) and plot a slice")
    x = np.asarray(r.data[xdim], dtype=float)
    y = np.asarray(r.data[ydim], dtype=float)
    status = np.asarray(r.status).reshape(shape)
    practical = np.asarray(r.data["practical"], dtype=float).reshape(shape) if r.has("practical") else None
    cols = min(len(combos), 4)
    rows = -(-len(combos) // cols)
    for key in keys:
        z_all = np.asarray(r.data[key], dtype=float).reshape(shape)
        ok = (status == 0) & np.isfinite(z_all)
        log = key in LOG_INDICATORS and np.all(z_all[ok] > 0)
        vals = z_all[ok]
        if vals.size:
            lo, hi = float(vals.min()), float(vals.max())
            norm = mcolors.LogNorm(lo, hi) if log and hi > lo else mcolors.Normalize(lo, hi if hi > lo else lo + 1)
        else:
            norm = None
        fig, axes = plt.subplots(rows, cols, figsize=(5.6 * cols, 4.4 * rows + 0.9), layout="constrained",
                                 squeeze=False)
        mesh = None
        for ax, combo in zip(axes.ravel(), combos):
            st = status[combo]
            pr = practical[combo] if practical is not None else None
            m = heat(ax, fig, x, y, z_all[combo], st, pr, log, axis_label(r, xdim), axis_label(r, ydim),
                     choice_words(r, xdim), choice_words(r, ydim), norm)
            mesh = mesh or m
            if lead:
                ax.set_title(", ".join(f"{d} = {choice_words(r, d)[i] if choice_words(r, d) else num(float(np.atleast_1d(r.data[d])[i]))}"
                                       for d, i in zip(lead, combo)), fontsize=9)
            if vals.size and np.any(ok[combo]):
                zc = np.where(ok[combo], z_all[combo], np.inf)
                j, i = np.unravel_index(np.argmin(zc), zc.shape)
                ax.plot(x[i], y[j], "*", ms=13, color="white", mec="black", mew=1.0, zorder=6)
        for ax in axes.ravel()[len(combos):]:
            ax.set_visible(False)
        if mesh is not None:
            cb = fig.colorbar(mesh, ax=axes.ravel().tolist(), pad=0.02, shrink=0.9)
            cb.set_label(symbol(r, key))
            if log:  # 1, 2, 5 per decade; less than a decade gets every digit
                narrow = norm.vmax < 6 * norm.vmin
                cb.ax.yaxis.set_major_locator(mticker.LogLocator(subs=(1.0, 1.5, 2, 3, 4, 5, 6, 7, 8, 9) if narrow
                                                                 else (1.0, 2.0, 5.0)))
                log_axis_plain(cb.ax.yaxis)
        else:
            axes.ravel()[0].text(0.5, 0.5, f"no ok point has {key}", transform=axes.ravel()[0].transAxes,
                                 ha="center", va="center")
        handles = legend_handles(status, practical)
        if vals.size:
            handles.append(Line2D([], [], marker="*", ms=11, color="white", mec="black", ls="none",
                                  label=f"smallest {INDICATOR_SYMBOLS.get(key, key)} of a panel"))
        ncol = max(1, min(len(handles), int(fig.get_figwidth() // 2.9)))
        fig.legend(handles=handles, loc="lower center", bbox_to_anchor=(0.5, 0.0), ncol=ncol, fontsize=8,
                   frameon=False)
        rows_of_keys = -(-len(handles) // ncol)
        fig.get_layout_engine().set(rect=(0, 0.25 * (rows_of_keys + 1) / fig.get_figheight(), 1,
                                          1 - 0.25 * (rows_of_keys + 1) / fig.get_figheight()))
        fig.suptitle(title(r, f"{symbol(r, key)} over ({xdim}, {ydim})"))
        saver(fig, key)
    return saver.written


def optimize_file(r, saver):
    if not r.has("objective"):
        raise BadFile(f"{r.path}: an optimize file without its objective column")
    n = r.status.size
    k = np.arange(n)
    obj = np.asarray(r.data["objective"], dtype=float)
    feasible = np.asarray(r.data.get("feasible", np.ones(n)), dtype=float) == 1
    params = [p for p, m in r.meta.items() if text(m.get("role", "")) == "parameter" and r.param_varies(p)
              and p not in ("beta", "gamma")]
    fig, axes = plt.subplots(1, 2 if len(params) >= 2 else 1, figsize=(11 if len(params) >= 2 else 6, 4.6),
                             layout="constrained", squeeze=False)
    ax = axes[0, 0]
    ax.plot(k, obj, "-", color="0.6", lw=0.8, zorder=1)
    ax.plot(k[feasible], obj[feasible], "o", color="white", mec="black", ms=5, ls="none", label="feasible", zorder=2)
    ax.plot(k[~feasible], obj[~feasible], "o", color="black", ms=5, ls="none", label="infeasible", zorder=2)
    best = r.attr("best_evaluation")
    if best is not None:
        b = int(best)
        ax.plot(k[b], obj[b], "*", ms=15, color="white", mec="black", zorder=3,
                label=f"best: {num(round(float(obj[b]), 5))} at evaluation {b}")
    fin = obj[np.isfinite(obj)]
    if fin.size and np.all(fin > 0) and fin.max() >= 10 * fin.min():
        ax.set_yscale("log")
    ax.set_xlabel("evaluation")
    ax.set_ylabel("objective")
    ax.set_title("the objective in the order the optimiser asked")
    ax.legend(fontsize=8)
    if len(params) >= 2:
        ax = axes[0, 1]
        px, py = (np.asarray(r.data[p], dtype=float) for p in params[:2])
        ax.plot(px, py, "-", color="0.6", lw=0.8, zorder=1)
        sc = ax.scatter(px, py, c=k, cmap=CMAP, s=22, zorder=2, edgecolors=np.where(feasible, "none", "black"))
        fig.colorbar(sc, ax=ax, label="evaluation")
        if best is not None:
            ax.plot(px[int(best)], py[int(best)], "*", ms=16, color="white", mec="black", zorder=3)
        ax.set_xlabel(axis_label(r, params[0]))
        ax.set_ylabel(axis_label(r, params[1]))
        ax.set_title("the search in its first two parameters (outlined: infeasible)")
    fig.suptitle(title(r, f"NLopt search, {text(r.attr('algorithm', ''))}, {n} evaluations"))
    saver(fig, "search")
    return saver.written


def work_precision_file(r, saver):
    fig = work_precision.draw(r, f"Work–precision: {text(r.attr('plan_name', r.path.stem))}")
    saver(fig, "work-precision")
    return saver.written


# ---- spectral files -----------------------------------------------------------------------------

def spectral_file(path, saver):
    s = {}
    with h5py.File(path, "r") as f:
        for k in f:
            if isinstance(f[k], h5py.Dataset):
                v = f[k][()]
                s[k] = np.array(texts(v), dtype=object) if f[k].dtype.kind in ("S", "O", "U") else np.asarray(v)
        attrs = {k: f.attrs[k] for k in f.attrs}
    if "omega_dt" not in s or "spectral_radius" not in s:
        raise BadFile(f"{path}: a spectral file without omega_dt or spectral_radius")
    W = np.asarray(s["omega_dt"], dtype=float)
    names = list(s.get("method_name", s.get("method_label", [])))
    labels = list(s.get("method_label", names))
    groups = method_groups(names) if names else [[]]
    quantities = [("spectral_radius", "spectral radius ρ", False), ("damping_ratio", "damping ratio ξ̄", True),
                  ("period_error", "period error (T̄ − T)/T", False)]
    quantities = [q for q in quantities if q[0] in s]
    fig, axes = plt.subplots(len(groups), len(quantities), figsize=(5.0 * len(quantities), 3.6 * len(groups) + 0.6),
                             layout="constrained", squeeze=False)
    for row, group in enumerate(groups):
        for col, (key, name, log) in enumerate(quantities):
            ax = axes[row, col]
            styles = spectral_styles([names[i] for i in group])  # a repeated method: dashed
            for i, (color, dash) in zip(group, styles):
                y = np.asarray(s[key][i], dtype=float)
                if log:  # ξ̄ of a method without damping is round-off: not drawn
                    y = np.where(y > 1e-12, y, np.nan)
                ax.plot(W, y, color=color, ls=dash, lw=1.4, label=pretty_spectral_label(names[i], labels[i]))
            ax.set_xscale("log")
            if log:
                ax.set_yscale("log")
            # ρ past 1 (an unstable method) and the period error past 100 % say all there is to say
            if key in ("spectral_radius", "period_error"):
                values = np.asarray(s[key][group], dtype=float)
                values = values[np.isfinite(values)]
                lo, hi = (float(values.min()), float(values.max())) if values.size else (0.0, 1.0)
                top = 1.5 if key == "spectral_radius" else 1.0
                bottom = 0.0 if key == "spectral_radius" else max(lo, -1.0)
                pad = 0.04 * (min(hi, top) - bottom or 1.0)
                ax.set_ylim(bottom - pad, min(hi, top) + pad)
                if hi > top or lo < bottom:
                    ax.text(0.02, 0.97, f"clipped to [{num(bottom)}, {num(top)}]", transform=ax.transAxes, va="top",
                            fontsize=7.5, color="0.3")
            ax.set_xlabel("Ω = ω·Δt")
            ax.set_ylabel(name)
            if col == 0:
                ax.legend(fontsize=7.5, framealpha=0.9)
    fig.suptitle(f"{text(attrs.get('plan_name', path.stem))}: spectral properties on ü + ω²u = 0"
                 + (f" ({len(names)} methods, at most six a row)" if len(groups) > 1 else ""))
    saver(fig, "spectral")
    if "stable" in s and np.asarray(s["stable"]).size:
        A, D = np.asarray(s["alpha"], dtype=float), np.asarray(s["delta"], dtype=float)
        st = np.asarray(s["stable"], dtype=float)
        fig, ax = plt.subplots(figsize=(6.2, 4.8), layout="constrained")
        ax.pcolormesh(cell_edges(D), cell_edges(A), st, cmap=mcolors.ListedColormap(["#D55E00", "#F2F2F2"]),
                      vmin=0, vmax=1, shading="flat")
        ax.plot(-A, A, color="black", lw=1.4, ls=":", label="δ = −α (eq. 15)")
        ax.set_xlim(cell_edges(D).min(), cell_edges(D).max())
        ax.set_ylim(cell_edges(A).min(), cell_edges(A).max())
        ax.set_xlabel("δ")
        ax.set_ylabel("α")
        ax.legend(handles=[Patch(color="#F2F2F2", label="stable (ρ ≤ 1)"), Patch(color="#D55E00", label="unstable"),
                           *ax.get_legend_handles_labels()[0]], fontsize=8, loc="lower left")
        ax.set_title("HHT-α: stability over (δ, α)")
        saver(fig, "stability")
    return saver.written


# ---- history files ------------------------------------------------------------------------------

def history_file(path, saver):
    with h5py.File(path, "r") as f:
        attrs = {k: f.attrs[k] for k in f.attrs}
        data = {k: np.asarray(f[k][()], dtype=float) for k in f if isinstance(f[k], h5py.Dataset)
                and f[k].dtype.kind == "f"}
        units = {k: text(f[k].attrs.get("units", "")) for k in f if isinstance(f[k], h5py.Dataset)}
    t = data["t"]
    method = text(attrs.get("method", "?"))
    contacts = sorted({k.split(".", 1)[1] for k in data if k.startswith("pressure.")})
    # the primary contact: the one whose columns are the unnamed pressure's
    primary = next((c for c in contacts if "pressure" in data and np.array_equal(data["pressure"], data[f"pressure.{c}"],
                                                                                   equal_nan=True)), None)
    rows = []
    for q in ("pressure", "velocity"):
        if q not in data and primary is None:
            continue
        y = data.get(q, data.get(f"{q}.{primary}"))
        ref, ref_name = None, ""
        for key, name in ((f"exact_{q}", "exact"), (f"reference_{q}.{primary}", "reference"),
                          (f"exact_{q}.{primary}", "exact")):
            if key in data and np.any(np.isfinite(data[key])):
                ref, ref_name = data[key], name
                break
        unit = units.get(q, "")
        rows.append((q, y, ref, ref_name, unit))
    if not rows:
        raise BadFile(f"{path}: no pressure or velocity to draw")
    fig, axes = plt.subplots(len(rows), 2, figsize=(12, 3.6 * len(rows) + 0.6), layout="constrained", squeeze=False,
                             gridspec_kw={"width_ratios": [1.6, 1]})
    scale, tunit = (1e6, "µs") if t[-1] < 1e-2 else (1.0, "s")
    ts = t * scale
    p = rows[0][1]
    on = np.nonzero(np.abs(p) > 1e-9 * (np.nanmax(np.abs(p)) or 1.0))[0]
    dt = float(np.median(np.diff(t))) if t.size > 1 else 1.0
    first = ts[on[0]] if on.size else ts[0]
    lo, hi = first - 8 * dt * scale, first + 60 * dt * scale
    color = method_color(method)
    label = method_label(method, {k: v for k, v in attrs.items() if not isinstance(v, (bytes, str))})
    for row, (q, y, ref, ref_name, unit) in enumerate(rows):
        for col, ax in enumerate(axes[row]):
            ax.plot(ts, y, color=color, lw=1.1 if col == 0 else 1.3, label=label,
                    marker="." if col == 1 else None, ms=3)
            if ref is not None:
                ax.plot(ts, ref, color=EXACT_COLOR, ls="--", lw=1.2, label=ref_name)
            ax.set_xlabel(f"t [{tunit}]")
            ax.set_ylabel(f"{q}" + (f" [{unit}]" if unit else ""))
            if col == 1:
                ax.set_xlim(lo, hi)
                sel = (ts >= lo) & (ts <= hi)
                vals = np.concatenate([y[sel]] + ([ref[sel]] if ref is not None else []))
                vals = vals[np.isfinite(vals)]
                if vals.size:
                    pad = 0.08 * (np.ptp(vals) or abs(vals.max()) or 1.0)
                    ax.set_ylim(vals.min() - pad, vals.max() + pad)
                ax.set_title(f"zoom at the first contact, t = {num(round(first, 4))} {tunit}", fontsize=9)
            else:
                ax.set_title(f"{q}" + (f" at contact {primary}" if primary else "") + ": the whole run", fontsize=9)
                ax.legend(fontsize=8, framealpha=0.9)
    fig.suptitle(f"{path.name}: {label}" + ("" if rows[0][2] is not None else " (the file has no reference)"))
    saver(fig, "history")
    return saver.written
