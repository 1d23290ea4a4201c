"""Time-history files (the layout of `impactid simulate --history`; a list study's
results/histories/<plan>/point-<k>.h5, from its [output] histories): reading them, finding their
folder, and the indicators of their points from results/<plan>.h5. Draws nothing.
"""

import math
from pathlib import Path

import h5py
import numpy as np

from .results import PROJECT_ROOT, Results, Skip, run_command, text
from .style import INDICATOR_SYMBOLS, method_label


class History:
    def __init__(self, path):
        self.path = Path(path)
        with h5py.File(self.path, "r") as f:
            self.attrs = {k: (text(f.attrs[k]) if isinstance(f.attrs[k], (bytes, str)) else f.attrs[k]) for k in f.attrs}
            self.data = {k: np.asarray(f[k][()], dtype=float) for k in f if isinstance(f[k], h5py.Dataset)}
        for key in ("t", "pressure", "velocity", "exact_pressure", "exact_velocity"):
            if key not in self.data:
                raise Skip(f"{self.path}: dataset {key!r} missing (layout of `impactid simulate --history`)")
        self.method = text(self.attrs.get("method", "?"))
        self.t_us = self.data["t"] * 1e6

    def label(self):
        return method_label(self.method, self.attrs)

    def jump_times(self):
        """(t_impact, t_release) in µs: from the scene attributes, or from the exact pressure."""
        a = self.attrs
        try:
            c = math.sqrt(float(a["youngs_modulus"]) / float(a["density"]))
            t_imp = float(a["gap"]) / float(a["velocity"])
            return t_imp * 1e6, (t_imp + 2 * float(a["length"]) / c) * 1e6
        except (KeyError, ValueError, ZeroDivisionError):
            on = np.nonzero(self.data["exact_pressure"] > 0)[0]
            if on.size == 0:
                raise Skip(f"{self.path}: the exact pressure is zero throughout: no impact")
            return self.t_us[on[0]], self.t_us[on[-1]]


def find_history_dir(results_dir, name):
    """The folder of a list study's per-point histories: results/histories/<name>/,
    results/<name>-histories/ (where `impactid run --output results/<name>.h5` puts them), or the
    plan's [output] histories (relative to the project root or to the results folder's parent)."""
    results_dir = Path(results_dir)
    candidates = [results_dir / "histories" / name, results_dir / f"{name}-histories"]
    path = results_dir / f"{name}.h5"
    if path.exists():
        try:
            r = Results(path)
            h = r.plan.get("output", {}).get("histories")
            if h:
                h = Path(h)
                candidates += [h] if h.is_absolute() else [PROJECT_ROOT / h, results_dir.parent / h, Path.cwd() / h]
        except Skip:
            pass
    for c in candidates:
        if (c / "point-0.h5").exists():
            return c
    raise Skip(f"no time histories: {candidates[0]}/point-*.h5 not found; produce them with: {run_command(name)}")


def load_histories(results_dir, name="identical-dissipation"):
    folder = find_history_dir(results_dir, name)
    files = sorted(folder.glob("point-*.h5"), key=lambda p: int(p.stem.split("-")[1]))
    # keep only the points of the results file, if there is one with status
    hist = [History(p) for p in files]
    for h, p in zip(hist, files):
        h.point = int(p.stem.split("-")[1])
        h.indicators = {}
    path = Path(results_dir) / f"{name}.h5"
    if path.exists():  # keep only the points of the results file, and take their indicators
        r = Results(path)
        n = r.status.size
        hist = [h for h in hist if h.point < n]
        for h in hist:
            if r.status[h.point] == 0:
                h.indicators = {k: float(np.atleast_1d(r.data[k])[h.point]) for k in INDICATOR_SYMBOLS if r.has(k)}
    return folder, hist
