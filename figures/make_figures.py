#!/usr/bin/python3
"""Regenerate every figure of impactid from its HDF5 results.

    figures/make_figures.py [--results DIR] [--out DIR]

reads the results files of the plans in plans/ and examples/block/ (layout: results/README.md)
from DIR (default results/) and writes one PNG per figure to --out (default DIR/figures/). It prints one line per
figure: `wrote PATH` or `skipped NAME: WHY`, where WHY names the missing file and the command
that produces it. The exit status is 0 unless a figure failed with an unexpected error (1) or
the arguments are wrong (2). What each figure shows: figures/README.md.

This file is the command line and the one list of figures (FIGURES); the figures are drawn by
the package impactid_figures/ beside it, one module per figure family (its __init__.py lists them).

Needs Debian's python3 with python3-matplotlib (>= 3.6), python3-h5py and numpy; no other
package. Run it as /usr/bin/python3, or through scripts/figures.
"""

import argparse
import sys
import traceback
from pathlib import Path

from impactid_figures import (block_contact_force, comparison_bars, contact_laws, hht_maps, parameter_maps, optimize, restitution,
                              spectral, stability_map, sweeps_1d, time_histories, work_precision)
from impactid_figures.results import PROJECT_ROOT, Skip

import matplotlib.pyplot as plt  # after impactid_figures, which selects the Agg backend

# Every figure, in the order they are drawn: (PNG file name, function of its family's module).
# A new figure is a function in its family's module (a new family: a new module) and one line here.
FIGURES = [
    ("fig3_newmark_delta.png", sweeps_1d.fig3),
    ("fig_two_rods.png", sweeps_1d.fig_two_rods),
    ("fig4_hht_delta_alpha.png", hht_maps.fig4),
    ("fig_hopkinson.png", hht_maps.fig_hopkinson),
    ("fig_clamped_bar.png", hht_maps.fig_clamped_bar),
    ("fig_bouncing_bar.png", hht_maps.fig_bouncing_bar),
    ("block-hht-delta-alpha.png", hht_maps.fig_block_hht),
    ("fig_period_error_line.png", sweeps_1d.fig_period_error_line),
    ("fig5_pressure_history.png", time_histories.fig5),
    ("fig6_velocity_history.png", time_histories.fig6),
    ("fig_stepped_rod_pressure.png", time_histories.fig_stepped_rod_pressure),
    ("fig_stepped_rod_velocity.png", time_histories.fig_stepped_rod_velocity),
    ("block-contact-force.png", block_contact_force.fig_block_contact_force),
    ("fig7_compare_pressure.png", comparison_bars.fig7),
    ("fig8_compare_velocity.png", comparison_bars.fig8),
    ("fig_spectral.png", spectral.fig_spectral),
    ("fig_optimize.png", optimize.fig_optimize),
    ("fig_multistart.png", optimize.fig_multistart),
    ("fig_stability_map.png", stability_map.fig_stability_map),
    ("fig_work_precision.png", work_precision.fig_work_precision),
    ("block-work-precision.png", work_precision.fig_block_work_precision),
    ("fig_contact_laws.png", contact_laws.fig_contact_laws),
    ("fig_paoli_schatzman.png", restitution.fig_paoli_schatzman),
    ("fig_rho_bathe.png", parameter_maps.fig_rho_bathe),
    ("fig_noh_bathe.png", parameter_maps.fig_noh_bathe),
    ("fig_kim_explicit.png", parameter_maps.fig_kim_explicit),
    ("fig_kr_alpha.png", parameter_maps.fig_kr_alpha),
]


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="make_figures.py",
        description="Regenerate every impactid figure (PNG) from the HDF5 results files.",
    )
    parser.add_argument("--results", default=None, help="folder of the results files (default: results/ of the project)")
    parser.add_argument("--out", default=None, help="folder for the PNG files (default: RESULTS/figures/)")
    parser.add_argument("--only", action="append", default=None, metavar="NAME",
                        help="draw only this figure (file name, with or without .png); may repeat")
    args = parser.parse_args(argv)
    results_dir = Path(args.results) if args.results else PROJECT_ROOT / "results"
    out_dir = Path(args.out) if args.out else results_dir / "figures"
    if not results_dir.is_dir():
        parser.error(f"--results {results_dir}: not a folder")
    out_dir.mkdir(parents=True, exist_ok=True)
    wanted = None
    if args.only:
        wanted = {w if w.endswith(".png") else w + ".png" for w in args.only}
        unknown = wanted - {n for n, _ in FIGURES}
        if unknown:
            parser.error(f"--only {', '.join(sorted(unknown))}: no such figure ({', '.join(n for n, _ in FIGURES)})")
    failed = 0
    for name, draw in FIGURES:
        if wanted and name not in wanted:
            continue
        try:
            for path in draw(results_dir, out_dir):
                print(f"wrote   {path}")
        except Skip as why:
            print(f"skipped {name}: {why}")
        except Exception as error:  # keep drawing the others; report and fail at the end
            failed += 1
            print(f"FAILED  {name}: {type(error).__name__}: {error}")
            traceback.print_exc(file=sys.stderr)
        finally:
            plt.close("all")
        sys.stdout.flush()
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
