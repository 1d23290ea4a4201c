"""impactid.plot: any file impactid writes, drawn as `impactid plot FILE.h5` draws it, by the same
figure package (figures/impactid_figures/own_results.py), in this process."""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

from . import _impactid
from ._paths import FIGURES_DIR


def _figures_dir() -> Path:
    """IMPACTID_FIGURES_DIR, else where the build or the installation put the figure package."""
    folder = Path(os.environ.get("IMPACTID_FIGURES_DIR") or FIGURES_DIR)
    if not (folder / "impactid_figures" / "own_results.py").is_file():
        raise FileNotFoundError(
            f"impactid.plot: the figure package is not in {folder} (impactid_figures/own_results.py); "
            "set IMPACTID_FIGURES_DIR to the figures/ folder of impactid's source")
    return folder


def plot(file, out=None, format: str = "png") -> list[Path]:
    """Draw a results file of any study kind, a spectral file or a history file (`impactid plot`).

    file:   the HDF5 file (`impactid run`, `simulate --history`, a plan's [output] histories)
    out:    folder for the figures, created; default: the file's name without .h5, plus -figures,
            beside it
    format: "png" or "pdf"

    Returns the paths written. A file that is not impactid's raises ValueError naming it; a
    missing file FileNotFoundError; matplotlib or h5py missing, ImportError.
    """
    if format not in ("png", "pdf"):
        raise ValueError(f"impactid.plot: format = {format!r}: must be 'png' or 'pdf'")
    path = Path(file)
    if not path.is_file():
        raise FileNotFoundError(f"impactid.plot: {path}: no such file")
    folder = str(_figures_dir())
    if folder not in sys.path:
        sys.path.insert(0, folder)
    try:
        import matplotlib  # noqa: F401
        import h5py  # noqa: F401
    except ImportError as error:
        raise ImportError(f"impactid.plot needs matplotlib and h5py (Debian: python3-matplotlib, "
                          f"python3-h5py): {error}") from None
    from impactid_figures import style
    from impactid_figures.own_results import BadFile, plot_file
    from impactid_figures.results import Skip

    # The methods' order (their colours), labels and parameters: this module's own registry.
    style.set_registry(json.loads(_impactid.methods_json()))
    try:
        return plot_file(path, out, format)
    except (BadFile, Skip) as why:
        raise ValueError(str(why)) from None
    finally:
        import matplotlib.pyplot as plt

        plt.close("all")
