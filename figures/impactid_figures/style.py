"""The figures' look, the same in every figure: one colour and one label per method (with the
parameters that tell its settings apart), the texts of the statuses and the indicators' symbols,
numbers in labels, and matplotlib's rcParams (set on import). Draws nothing and reads no file.
"""

import math

import matplotlib.pyplot as plt

from .results import text

DPI = 150

# One palette for the project. The methods and their order come from the program's registry
# (`impactid methods --json`, or the Python module's list): method i of the registry gets
# PALETTE[i], so a new method gets a colour without a line here. The colours are from the Okabe &
# Ito and Tol colour-blind-safe sets, no two alike; the nearest pairs (Newmark's green and KR-α's,
# backward Euler's sky and Noh–Bathe's cyan) sit far apart in the registry, so they fall into
# different panels of the small multiples (at most SERIES_PER_PANEL methods a panel).
PALETTE = [
    "#E69F00",  # orange
    "#56B4E9",  # sky blue
    "#009E73",  # bluish green
    "#0072B2",  # blue
    "#CC79A7",  # reddish purple
    "#D55E00",  # vermillion
    "#882255",  # wine
    "#332288",  # indigo
    "#999933",  # olive
    "#AA4499",  # purple
    "#33BBEE",  # cyan
    "#555555",  # dark grey
    "#117733",  # dark green
]
SERIES_PER_PANEL = 6
# How a method is named in a figure: typography only (the registry's names are ASCII). A method
# of the registry without an entry here is named by its registry name.
LABELS = {
    "cdm": "central difference",
    "backward-euler": "backward Euler",
    "newmark": "Newmark",
    "hht": "HHT-α",
    "generalized-alpha": "generalized-α",
    "bathe": "Bathe",
    "rho-bathe": "ρ∞-Bathe",
    "tr-bdf2": "TR-BDF2",
    "houbolt": "Houbolt",
    "wilson-theta": "Wilson-θ",
    "noh-bathe": "Noh–Bathe explicit",
    "kim-explicit": "Kim explicit",
    "kr-alpha": "KR-α explicit",
}
_registry = None


def set_registry(names):
    """The registry's method names in its order (the Python module passes impactid.methods())."""
    global _registry
    _registry = [text(n) for n in names]


def registry():
    """The method names of the program's registry, in its order: from the program named by
    IMPACTID_EXECUTABLE (`impactid plot` and figures/check_figures.py set it), else the build's
    build/study/impactid, else `impactid` on PATH. Without a program the labels' order stands in,
    with a warning (the colours of methods added since then are then not the program's)."""
    global _registry
    if _registry is None:
        import json
        import os
        import shutil
        import subprocess
        import sys

        from .results import PROJECT_ROOT

        candidates = [os.environ.get("IMPACTID_EXECUTABLE"), str(PROJECT_ROOT / "build" / "study" / "impactid"),
                      shutil.which("impactid")]
        for exe in candidates:
            if not exe or not os.access(exe, os.X_OK):
                continue
            try:
                out = subprocess.run([exe, "methods", "--json"], capture_output=True, text=True, timeout=60, check=True)
                _registry = [m["name"] for m in json.loads(out.stdout)]
                break
            except (OSError, subprocess.SubprocessError, ValueError, KeyError, TypeError):
                continue
        if _registry is None:
            print("impactid_figures: no impactid program found for the method list (set IMPACTID_EXECUTABLE); "
                  "colours follow the figures' own list", file=sys.stderr)
            _registry = list(LABELS)
    return _registry


def method_groups(methods):
    """`methods` (names, in drawing order) split into panels of at most SERIES_PER_PANEL, in
    registry order, as evenly as possible: [[indices into methods], ...]."""
    order = sorted(range(len(methods)), key=lambda i: (registry_index(methods[i]), i))
    panels = max(1, -(-len(order) // SERIES_PER_PANEL))
    size = -(-len(order) // panels)
    return [order[k:k + size] for k in range(0, len(order), size)] or [[]]


def registry_index(method):
    names = registry()
    method = text(method).strip().lower()
    if method in names:
        return names.index(method)
    for i, name in enumerate(names):  # a label such as "hht alpha=-0.3"
        if method.startswith(name):
            return i
    return len(names)


UNKNOWN_COLORS = ["#999999", "#BBBB00"]  # a name the registry does not know
EXACT_COLOR = "black"
NOT_OK_COLOR = "0.15"  # near black: points that are not ok (grey hatching on maps)
CHATTER_COLOR = "#B00000"  # not ok although the spectral analysis predicts stability
PRACTICAL_COLOR = "#D55E00"
PAPER_COLOR = "0.35"
CMAP = "viridis"

STATUS_TEXT = {
    -1: "not done",
    1: "not ok: unstable (energy growth)",
    2: "not ok: failed (singular matrix)",
}

plt.rcParams.update(
    {
        "font.size": 9.5,
        "axes.titlesize": 10,
        "axes.labelsize": 10,
        "legend.fontsize": 8.5,
        "figure.titlesize": 11,
        "axes.grid": True,
        "grid.alpha": 0.3,
        "grid.linewidth": 0.6,
        "savefig.dpi": DPI,
    }
)


INDICATOR_SYMBOLS = {"eps_p": "ε_p", "eps_v": "ε_v", "nop_p": "NoP_p", "nop_v": "NoP_v", "p_max": "p_max",
                     "p_max_ratio": "p_max/(ρcv0)", "contact_episodes": "contact episodes", "energy_ratio": "energy ratio"}


def num(s):
    """A number for a label: 4 significant digits, a true minus sign."""
    if isinstance(s, str):
        return s
    s = float(s)
    if s == int(s) and abs(s) < 1e6:
        out = str(int(s))
    else:
        out = f"{s:.4g}"
    return out.replace("-", "−")


def method_info(method):
    """(label, colour) of a method name (or of a label that starts with one)."""
    method = text(method).strip().lower()
    names = registry()
    i = registry_index(method)
    if i < len(names):
        name = names[i]
        return LABELS.get(name, name), PALETTE[i % len(PALETTE)]
    return (method, UNKNOWN_COLORS[sum(map(ord, method)) % len(UNKNOWN_COLORS)])


def method_color(method):
    return method_info(method)[1]


def method_params(method, params, sep=", "):
    """The parameters that tell one setting of a method from another, as text."""
    method = text(method)

    def get(name):
        v = params.get(name)
        if v is None:
            return None
        if isinstance(v, (str, bytes)):
            return text(v)
        v = float(v)
        return None if not math.isfinite(v) else v

    parts = []
    if method == "hht" and get("alpha") is not None:
        parts.append(f"α = {num(round(get('alpha'), 4))}")
    if method in ("newmark", "hht"):
        if get("delta") is not None:
            parts.append(f"δ = {num(round(get('delta'), 4))}")
        elif get("beta") is not None and get("gamma") is not None:
            parts.append(f"β = {num(round(get('beta'), 4))}")
            parts.append(f"γ = {num(round(get('gamma'), 4))}")
    if method == "rho-bathe" and get("rho_inf") is not None:
        parts.append(f"ρ∞ = {num(round(get('rho_inf'), 4))}")
        if get("substep_ratio") is not None:
            parts.append(f"γ = {num(round(get('substep_ratio'), 4))}")
    if method == "wilson-theta" and get("theta") is not None:
        parts.append(f"θ = {num(round(get('theta'), 4))}")
    if method in ("noh-bathe", "kim-explicit") and get("p") is not None:
        parts.append(f"p = {num(round(get('p'), 4))}")
    if method in ("generalized-alpha", "kr-alpha") and get("rho_inf") is not None:
        parts.append(f"ρ∞ = {num(round(get('rho_inf'), 4))}")
    if method == "cdm" and get("cdm_velocity") not in (None, "central"):
        parts.append(f"{get('cdm_velocity')} velocity")
    if method in ("hht", "generalized-alpha") and get("hht_contact") not in (None, "endpoint"):
        parts.append(f"{get('hht_contact')} contact")
    return sep.join(parts)


SHORT_NAMES = {"cdm": "central\ndifference", "backward-euler": "backward\nEuler"}


def method_label(method, params, sep=", "):
    name = method_info(method)[0]
    if sep == "\n":
        name = SHORT_NAMES.get(text(method), name)
    p = method_params(method, params, sep)
    if not p:
        return name
    return f"{name} ({p})" if sep == ", " else f"{name}{sep}{p}"


def pretty_spectral_label(method, label):
    """'hht alpha=-0.3 delta=0.45' -> 'HHT-α (α = −0.3, δ = 0.45)'; other labels unchanged."""
    words = label.split()
    if not words or words[0] != method or not all("=" in w for w in words[1:]):
        return label
    params = {}
    for w in words[1:]:
        key, value = w.split("=", 1)
        try:
            params[key] = float(value)
        except ValueError:
            params[key] = value
    out = method_label(method, params)
    if method == "hht" and "alpha" in params and "delta" not in params:
        out = out[:-1] + ", δ = −α: eq. 15)" if out.endswith(")") else out + " (δ = −α: eq. 15)"
    return out
