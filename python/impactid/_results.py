"""Results files (results/README.md) as xarray Datasets."""

from __future__ import annotations

import os


def open_results(path) -> "xarray.Dataset":
    """An impactid results file (`impactid run`'s HDF5, any study kind) as an xarray.Dataset.

    Read into memory and closed, so that the file can be resumed or replaced while the Dataset
    lives. Dimensions are the study's axes (dimension scales); per-point variables are `status`
    (-1 not done, 0 ok, 1 unstable, 2 failed), the varied parameters and the indicators, with
    their units, long_name and definition; the root attributes (plan: the plan's whole text,
    plan_name, study_kind, method, points_done, ...) are the Dataset's attrs. An indicator of a
    point that is not ok is NaN in the file: use ds[name].where(ds.status == 0).

    The file is checked as `impactid export` and `run --resume` check it, with their messages,
    before it is loaded: a file that is not a results file (a history file, a spectral file), a
    checksum that does not match its data (a damaged file), a status outside -1, 0, 1, 2, or
    axes that do not match `status` raise ValueError naming the file. A file written before
    checksums were stored is loaded unverified, with a note on stderr.
    """
    import xarray

    from . import _impactid

    path = os.fspath(path)
    if not os.path.exists(path):
        raise FileNotFoundError(path)
    _impactid.check_results(path)
    with xarray.open_dataset(path, engine="h5netcdf") as ds:
        ds = ds.load()
    # The checksum describes the storage, not the study (impactid's readers leave it out too).
    ds.attrs.pop("impactid_checksum", None)
    return ds
