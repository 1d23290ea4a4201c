#!/usr/bin/python3
"""Draw any file impactid writes: the body of `impactid plot`.

    figures/plot_results.py FILE.h5 [--out DIR] [--format png|pdf]

A results file is drawn by its study kind (grid, list, optimize, work-precision), a spectral file
as its curves, a history file as its histories against its reference
(impactid_figures/own_results.py says what each figure shows). Prints `wrote PATH` per figure.
Exit status 0; 2 when the file is not one impactid writes or has nothing to draw; 1 when Python
lacks matplotlib or h5py, or a figure fails.

Needs Debian's python3 with python3-matplotlib (>= 3.6), python3-h5py and numpy; `impactid plot`
runs it with /usr/bin/python3.
"""

import argparse
import sys
import traceback
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))  # the package impactid_figures beside it

PROG = "impactid plot"


def main(argv=None):
    parser = argparse.ArgumentParser(prog=PROG, description="Draw an impactid HDF5 file as PNG or PDF figures.")
    parser.add_argument("file", help="a results, spectral or history file (.h5)")
    parser.add_argument("--out", default=None, help="folder for the figures (default: FILE without .h5, plus -figures)")
    parser.add_argument("--format", default="png", choices=("png", "pdf"))
    args = parser.parse_args(argv)
    missing = []
    for module, package in (("numpy", "python3-numpy"), ("h5py", "python3-h5py"), ("matplotlib", "python3-matplotlib")):
        try:
            __import__(module)
        except ImportError:
            missing.append(f"{module} (Debian: {package})")
    if missing:
        print(f"{PROG}: {sys.executable} has no {', '.join(missing)}; scripts/install-deps installs "
              "them, or set IMPACTID_PYTHON to a Python that has them", file=sys.stderr)
        return 1
    from impactid_figures.own_results import BadFile, plot_file
    from impactid_figures.results import Skip

    if not Path(args.file).is_file():
        print(f"{PROG}: {args.file}: no such file", file=sys.stderr)
        return 2
    try:
        written = plot_file(args.file, args.out, args.format)
    except (BadFile, Skip) as why:
        print(f"{PROG}: {why}", file=sys.stderr)
        return 2
    except Exception as error:  # a defect of the figure code: say which file, keep the trace
        traceback.print_exc()
        print(f"{PROG}: {args.file}: drawing failed: {type(error).__name__}: {error}", file=sys.stderr)
        return 1
    for path in written:
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
