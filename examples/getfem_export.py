"""What impactid's GetFEM example generators share (examples/block, examples/beam3d): GetFEM's
sparse matrices as SciPy's, Matrix Market files as impactid reads them, decimal rounding of the
time step and shortest round-trip number text. Imported by each generator from its parent
folder."""

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
