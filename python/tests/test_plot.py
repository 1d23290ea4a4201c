"""impactid.plot: the same figures as `impactid plot`, from the figure package, in this process."""

import pathlib

import pytest

import impactid

PLAN = {
    "name": "python-plot",
    "scene": {"elements": 20},
    "method": {"name": "newmark"},
    "study": {"kind": "grid", "axes": {"delta": {"values": [0.0, 0.3, 0.6]}}},
}


def test_plots_a_results_file(tmp_path):
    results = tmp_path / "grid.h5"
    impactid.run_plan(PLAN, output=str(results))
    written = impactid.plot(results, out=tmp_path / "figures", format="pdf")
    assert written, "no figure"
    for path in written:
        assert pathlib.Path(path).read_bytes().startswith(b"%PDF")
        assert pathlib.Path(path).stat().st_size > 10_000


def test_refuses_what_is_not_impactid_s(tmp_path):
    with pytest.raises(FileNotFoundError, match="missing.h5: no such file"):
        impactid.plot(tmp_path / "missing.h5")
    (tmp_path / "notes.h5").write_text("not HDF5\n")
    with pytest.raises(ValueError, match="notes.h5: not an HDF5 file"):
        impactid.plot(tmp_path / "notes.h5")
    with pytest.raises(ValueError, match="must be 'png' or 'pdf'"):
        impactid.plot(tmp_path / "notes.h5", format="svg")
