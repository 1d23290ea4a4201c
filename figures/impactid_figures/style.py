"""The figures' look, the same in every figure: one colour and one label per method (with the
parameters that tell its settings apart; both from the program's method registry), the texts of the statuses and the indicators' symbols,
numbers in labels, and matplotlib's rcParams (set on import). Draws nothing and reads no file.
"""

import math
import re
import textwrap

import matplotlib.pyplot as plt

from .results import text

DPI = 150

# One palette for the project. The methods, their order and their labels come from the program's
# registry (`impactid methods --json`, or the Python module's copy of it): method i of the
# registry gets PALETTE[i], so a new method gets a colour and a label without a line here. The colours are from the Okabe &
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
# The symbols of the methods' parameters, in the order a label names them (the paper's: HHT's α
# before its δ). A parameter not here is named by its key, after these.
PARAMETER_SYMBOLS = {"alpha": "α", "delta": "δ", "beta": "β", "gamma": "γ", "rho_inf": "ρ∞",
                     "substep_ratio": "γ", "theta": "θ", "p": "p"}
_GREEK = {"alpha": "α", "beta": "β", "gamma": "γ", "delta": "δ", "theta": "θ", "rho_inf": "ρ∞"}
_registry = None


def pretty(label):
    """A registry label in the figures' typography: Greek letters for their ASCII names
    ("HHT-alpha" -> "HHT-α", "rho_inf-Bathe" -> "ρ∞-Bathe") and an en dash between two names
    ("Noh-Bathe" -> "Noh–Bathe")."""
    label = re.sub(r"(?<![A-Za-z])(rho_inf|alpha|beta|gamma|delta|theta)(?![A-Za-z_])",
                   lambda m: _GREEK[m.group(1)], label)
    return re.sub(r"\b([A-Z][a-z]+)-(?=[A-Z][a-z])", "\\1–", label)


def set_registry(methods):
    """The program's registry, in its order: the list `impactid methods --json` prints (the
    Python module passes its own), or bare method names (then labels are the names)."""
    global _registry
    _registry = [m if isinstance(m, dict) else {"name": text(m)} for m in methods]


def registry_entries():
    """The methods of the program's registry, in its order, as `impactid methods --json` prints
    them (name, label, parameters, derived): from the program named by IMPACTID_EXECUTABLE
    (`impactid plot` and figures/check_figures.py set it), else the build's build/study/impactid,
    else `impactid` on PATH. Without a program, none, with a warning: every method is then named
    by its registry name, in a colour of UNKNOWN_COLORS."""
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
                entries = json.loads(out.stdout)
                _registry = [dict(m, name=m["name"]) for m in entries]
                break
            except (OSError, subprocess.SubprocessError, ValueError, KeyError, TypeError):
                continue
        if _registry is None:
            print("impactid_figures: no impactid program found for the method list (set IMPACTID_EXECUTABLE); "
                  "methods are named by their registry names, in grey", file=sys.stderr)
            _registry = []
    return _registry


def registry():
    """The method names of the program's registry, in its order."""
    return [m["name"] for m in registry_entries()]


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
    entries = registry_entries()
    i = registry_index(method)
    if i < len(entries):
        entry = entries[i]
        return pretty(entry.get("label", entry["name"])), PALETTE[i % len(PALETTE)]
    return (method, UNKNOWN_COLORS[sum(map(ord, method)) % len(UNKNOWN_COLORS)])


def method_color(method):
    return method_info(method)[1]


def method_params(method, params, sep=", "):
    """The parameters that tell one setting of a method from another, as text: the numbers among
    the method's registry parameters that `params` gives, in PARAMETER_SYMBOLS' order (one it also
    derives, as Newmark's β and γ from δ, only when no other number is given), then its choice
    parameters that differ from their defaults ("backward velocity" for cdm_velocity = backward).
    A method the registry does not know: every parameter of PARAMETER_SYMBOLS that `params` gives."""
    method = text(method)

    def get(name):
        v = params.get(name)
        if v is None:
            return None
        if isinstance(v, (str, bytes)):
            return text(v)
        v = float(v)
        return None if not math.isfinite(v) else v

    entry = next((m for m in registry_entries() if m["name"] == method), None)
    if entry is None:
        taken = [{"name": n, "kind": "real"} for n in PARAMETER_SYMBOLS]
        derived = set()
    else:
        taken = entry.get("parameters", [])
        derived = set(entry.get("derived", []))
    order = list(PARAMETER_SYMBOLS)

    def rank(p):
        return order.index(p["name"]) if p["name"] in order else len(order)

    numbers = [p for p in sorted(taken, key=rank) if p.get("kind") != "choice" and get(p["name"]) is not None]
    if any(p["name"] not in derived for p in numbers):
        numbers = [p for p in numbers if p["name"] not in derived]
    parts = [f"{PARAMETER_SYMBOLS.get(p['name'], p['name'])} = {num(round(get(p['name']), 4))}" for p in numbers]
    for p in taken:
        value = get(p["name"]) if p.get("kind") == "choice" else None
        if value is not None and value != p.get("default"):
            parts.append(f"{value} {p['name'].rsplit('_', 1)[-1]}")
    return sep.join(parts)


def method_label(method, params, sep=", "):
    """The method's label with its parameters: "HHT-α (α = −0.3, δ = 0.45)"; with sep = "\n", for
    the narrow tick labels of a bar chart, a name of several words is broken into lines too."""
    name = method_info(method)[0]
    if sep == "\n":
        name = textwrap.fill(name, width=10, break_long_words=False, break_on_hyphens=False)
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
    # HHT-α's spectral run given α alone takes δ = −α (eq. 15), which its label says.
    if method == "hht" and "alpha" in params and "delta" not in params:
        out = out[:-1] + ", δ = −α: eq. 15)" if out.endswith(")") else out + " (δ = −α: eq. 15)"
    return out
