"""The figures' look, the same in every figure: one colour and one label per method (with the
parameters that tell its settings apart), the texts of the statuses and the indicators' symbols,
numbers in labels, and matplotlib's rcParams (set on import). Draws nothing and reads no file.
"""

import math

import matplotlib.pyplot as plt

from .results import text

DPI = 150

# One colour per method in every figure (Okabe & Ito's colour-blind-safe palette).
METHODS = {
    # plan name: (label, colour)
    "cdm": ("central difference", "#E69F00"),
    "backward-euler": ("backward Euler", "#56B4E9"),
    "newmark": ("Newmark", "#009E73"),
    "hht": ("HHT-α", "#0072B2"),
    "generalized-alpha": ("generalized-α", "#CC79A7"),
    "bathe": ("Bathe", "#44AA99"),
    "rho-bathe": ("ρ∞-Bathe", "#882255"),
    "tr-bdf2": ("TR-BDF2", "#332288"),
    "houbolt": ("Houbolt", "#999933"),
    "wilson-theta": ("Wilson-θ", "#AA4499"),
    "noh-bathe": ("Noh–Bathe explicit", "#661100"),
    "kim-explicit": ("Kim explicit", "#6699CC"),
    "kr-alpha": ("KR-α explicit", "#117733"),
}
UNKNOWN_COLORS = ["#999999", "#F0E442", "#000000"]
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
    method = text(method).strip().lower()
    if method in METHODS:
        return METHODS[method]
    for key, value in METHODS.items():  # a label such as "HHT-α (…)" or "hht, eq. 15"
        if method.startswith(key):
            return value
    return (method, UNKNOWN_COLORS[hash(method) % len(UNKNOWN_COLORS)])


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
