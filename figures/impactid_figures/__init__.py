"""impactid's figures, drawn from its HDF5 results: the package behind figures/make_figures.py.

Shared parts, which draw no figure of their own:
  results    reading results files (load, load_spectral), Skip, the plan that produces a file
  style      one colour and label per method, status texts, indicator symbols, rcParams
  scene      the scene in a title: the paper's rod, scenes of bodies
  model      user models (examples/block): description, contacts, units, reference
  plot       common helpers: save, practical range, threshold lines, not-ok marks, paper's stage
  hht_plane  the HHT (δ, α) plane: grids, maps, the lines of eqs. 15 and 19, predicted stability
  histories  time-history files and their folder

One module per figure family; each figure is a function (results_dir, out_dir) -> [paths written]
that raises results.Skip when its data are missing, registered in FIGURES of make_figures.py:
  sweeps_1d            Fig. 3, two rods, the period-error line (one parameter)
  hht_maps             Fig. 4, Hopkinson, the block over (δ, α)
  time_histories       Figs 5-6, the stepped rod
  block_contact_force  the block's total contact force
  comparison_bars      Figs 7-8
  spectral             the spectral analysis
  optimize             the NLopt search
  stability_map        the HHT stability map over Courant numbers
  work_precision       work-precision, on the rod and on the block
  contact_laws         the contact laws over the penalty stiffness
  restitution          Paoli–Schatzman's law over its coefficient of restitution
  parameter_maps       the other methods' own parameters
and, outside FIGURES, one module that draws any single file by its kind:
  own_results          `impactid plot FILE.h5` and impactid.plot (figures/plot_results.py)
What each figure shows: figures/README.md.
"""

import importlib
import sys

try:
    importlib.import_module("h5py")  # imported by the modules; here so that its absence is explained
    import matplotlib
except ImportError as error:  # pragma: no cover - environment problem
    sys.exit(
        f"make_figures.py: {error}. Run it with Debian's /usr/bin/python3 (python3-matplotlib,"
        " python3-h5py), e.g. through scripts/figures."
    )

matplotlib.use("Agg")  # before any module imports pyplot: files only, no display
