"""What impactid's GetFEM example generators share (examples/block, examples/beam3d): GetFEM's
sparse matrices as SciPy's, Matrix Market files as impactid reads them, decimal rounding of the
time step and shortest round-trip number text. Imported by each generator from its parent
folder."""

import os
from decimal import Decimal

import numpy as np
import scipy.io
import scipy.sparse as sp


def round_sig(x, digits, rounding):
    """Round a positive float to `digits` significant digits (decimal)."""
    d = Decimal(repr(float(x)))
    quantum = Decimal(1).scaleb(d.adjusted() - digits + 1)
    return float(d.quantize(quantum, rounding=rounding))


def to_scipy(spmat):
    """getfem Spmat -> scipy CSC matrix with sorted indices."""
    n, m = (int(s) for s in spmat.size())
    jc, ir = spmat.csc_ind()
    val = spmat.csc_val()
    a = sp.csc_matrix((np.asarray(val, dtype=float), np.asarray(ir), np.asarray(jc)),
                      shape=(n, m))
    a.sum_duplicates()
    a.sort_indices()
    return a


def write_mtx(path, a):
    a = sp.coo_matrix(a)
    scipy.io.mmwrite(path, a, symmetry="symmetric", precision=17)


def fmt(x):
    """Shortest round-trip float text (valid TOML / CSV)."""
    return repr(float(x))


class Verdicts:
    """--check's verdicts: each a measured value against its limit, printed, all of them
    passed or not."""

    def __init__(self):
        self.ok = True

    def __call__(self, name, value, limit):
        good = bool(value <= limit)
        self.ok = self.ok and good
        print(f"  [{'ok' if good else 'FAIL'}] {name}: {value:.3e} (limit {limit:.0e})")

    def read_back(self, outdir, matrices):
        """Each (file, matrix): the Matrix Market file read back equals the matrix exactly."""
        for fn, a in matrices:
            b = sp.csc_matrix(scipy.io.mmread(os.path.join(outdir, fn)))
            self(f"{fn} read back: max |file - matrix|", abs(b - a).max(), 0.0)
