"""Reading impactid's results files, which every figure is drawn from. Draws nothing.

`load(results_dir, name)` reads results/<name>.h5 (format impactid-results-1, layout:
results/README.md) and `load_spectral` reads results/spectral.h5 (impactid-spectral-1). A file
that is missing, of another format or without a finished point raises `Skip`, whose message
names the file and the command that produces it (`run_command`: plans/<name>.toml, or the plan
of PLAN_FILES for the shipped models' files).
"""

import tomllib
from pathlib import Path

import h5py
import numpy as np

PROJECT_ROOT = Path(__file__).resolve().parent.parent.parent  # this file is figures/impactid_figures/results.py
RUN = "build/study/impactid run {}"  # how a results file is produced (project root)
# The plans that are not plans/<name>.toml: the shipped models' (examples/<model>/), by the
# results file they write (their `name`).
PLAN_FILES = {
    "block-hht-delta-alpha": "examples/block/hht-delta-alpha.toml",
    "block-identical-dissipation": "examples/block/identical-dissipation.toml",
    "block-work-precision": "examples/block/work-precision.toml",
}


def run_command(name):
    """The command that produces results/<name>.h5, from the project root."""
    return RUN.format(PLAN_FILES.get(name, f"plans/{name}.toml"))


class Skip(Exception):
    """A figure that cannot be drawn from the results at hand; the message says why."""


def text(value):
    """An HDF5 attribute or string element as str."""
    if isinstance(value, bytes):
        return value.decode("utf-8")
    if isinstance(value, np.ndarray) and value.shape == ():
        return text(value[()])
    return str(value)


def texts(value):
    """A string attribute or dataset that may be a scalar or 1-D: a list of str."""
    if isinstance(value, (str, bytes)):
        return [text(value)]
    return [text(v) for v in np.atleast_1d(value)]


class Results:
    """An impactid-results-1 file read into memory."""

    def __init__(self, path):
        self.path = Path(path)
        with h5py.File(self.path, "r") as f:
            self.attrs = {k: f.attrs[k] for k in f.attrs}
            self.data = {}
            self.meta = {}
            for name, ds in f.items():
                if not isinstance(ds, h5py.Dataset):
                    continue
                value = ds[()]
                if ds.dtype.kind in ("S", "O", "U"):
                    value = np.array(texts(value), dtype=object)
                self.data[name] = value
                self.meta[name] = {k: ds.attrs[k] for k in ds.attrs if k not in ("DIMENSION_LIST", "REFERENCE_LIST")}
            self.dims = []
            if "status" in f:
                for dim in f["status"].dims:
                    if len(dim):
                        self.dims.append(dim[0].name.lstrip("/"))
        fmt = text(self.attrs.get("format", ""))
        if fmt != "impactid-results-1":
            raise Skip(f"{self.path}: format is {fmt!r}, not 'impactid-results-1'")
        try:
            self.plan = tomllib.loads(text(self.attrs.get("plan", "")))
        except tomllib.TOMLDecodeError:
            self.plan = {}
        self.status = np.asarray(self.data.get("status"), dtype=int)

    def attr(self, name, default=None):
        return self.attrs[name] if name in self.attrs else default

    def has(self, name):
        return name in self.data

    def param_varies(self, name):
        if name not in self.data:
            return False
        v = np.asarray(self.data[name], dtype=float)
        v = v[np.isfinite(v)]
        return v.size > 1 and np.ptp(v) > 0


def load(results_dir, name):
    path = Path(results_dir) / f"{name}.h5"
    if not path.exists():
        raise Skip(f"{path} not found; produce it with: {run_command(name)}")
    r = Results(path)
    if r.status is None or r.status.size == 0:
        raise Skip(f"{path} holds no points")
    if np.all(r.status == -1):
        raise Skip(f"{path}: no point is done yet (status −1 everywhere); finish it with: {run_command(name)} --resume")
    return r


def load_spectral(results_dir):
    path = Path(results_dir) / "spectral.h5"
    if not path.exists():
        raise Skip(f"{path} not found; produce it with: {run_command('spectral')}")
    s = {}
    with h5py.File(path, "r") as f:
        fmt = text(f.attrs.get("format", ""))
        if fmt != "impactid-spectral-1":
            raise Skip(f"{path}: format is {fmt!r}, not 'impactid-spectral-1'")
        s["attrs"] = {k: f.attrs[k] for k in f.attrs}
        for k in f:
            if isinstance(f[k], h5py.Dataset):
                v = f[k][()]
                s[k] = np.array(texts(v), dtype=object) if f[k].dtype.kind in ("S", "O", "U") else np.asarray(v)
    # the method names: `method_name` (strings; `method` is then the dimension 0..M-1), or
    # `method` itself when it holds strings
    if "method_name" in s:
        s["method"] = s["method_name"]
    elif "method" in s and s["method"].dtype != object:
        s["method"] = s.get("method_label")
    for key in ("omega_dt", "method", "spectral_radius", "period_error"):
        if key not in s or s[key] is None:
            raise Skip(f"{path}: dataset {key!r} missing")
    return path, s
