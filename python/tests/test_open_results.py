"""open_results checks a file as `impactid export` and `run --resume` do (issue 38, item 5): the
checksums of its values and text, its status codes, its kind; with the command line's words."""

import shutil
import subprocess

import h5py
import numpy as np
import pytest

import impactid

SPECTRAL_PLAN = """name = "small-spectral"
[study]
kind = "spectral"
omega_dt = { from = 0.1, to = 10.0, points = 5 }
methods = [{ method = "newmark", delta = 0.3 }]
alpha = { from = -0.3, to = 0.0, partitions = 2 }
delta = { from = 0.0, to = 1.0, partitions = 2 }
"""


@pytest.fixture(scope="module")
def results(tmp_path_factory, executable, source_dir):
    path = tmp_path_factory.mktemp("results") / "demo.h5"
    subprocess.run([executable, "run", str(source_dir / "plans" / "demo.toml"), "--output",
                    str(path)], check=True, capture_output=True)
    return path


@pytest.fixture
def copy(results, tmp_path):
    path = tmp_path / "copy.h5"
    shutil.copy(results, path)
    return path


def stored_offset(path, name, index):
    """The file offset of element `index` of a dataset's first (uncompressed) chunk."""
    with h5py.File(path, "r") as f:
        d = f[name]
        assert d.fletcher32 and d.compression is None
        return d.id.get_chunk_info(0).byte_offset + index * d.dtype.itemsize


def flip(path, offset, mask):
    data = bytearray(path.read_bytes())
    data[offset] ^= mask
    path.write_bytes(bytes(data))


def test_a_good_file_loads_its_values(results):
    ds = impactid.open_results(results)
    with h5py.File(results, "r") as f:
        np.testing.assert_array_equal(ds.status.values, f["status"][()])
        np.testing.assert_array_equal(ds.eps_p.values, f["eps_p"][()])
    assert "impactid_checksum" not in ds.attrs  # storage, not the study: left out


def test_a_global_heap_that_crashes_hdf5_is_refused_and_python_lives_on(copy):
    # The first variable-length string's length made 2^40 bytes: HDF5 1.10.8 would copy that
    # much (SIGSEGV) before any checksum is compared. The reader walks the heap first.
    data = bytearray(copy.read_bytes())
    at = data.find(b"GCOL")  # the collection's header is 16 bytes; the length is at +8 in the object's
    data[at + 24:at + 32] = (1 << 40).to_bytes(8, "little")
    copy.write_bytes(bytes(data))
    with pytest.raises(ValueError, match=f"{copy}: damaged: its global heap collection at byte"):
        impactid.open_results(copy)


def test_a_flipped_value_is_refused_naming_file_and_dataset(copy):
    flip(copy, stored_offset(copy, "eps_p", 5) + 7, 0x01)  # the exponent: eps_p[5] doubles
    with pytest.raises(ValueError, match="data corrupted") as raised:
        impactid.open_results(copy)
    assert str(raised.value).startswith(f"{copy}: eps_p: ")


def test_a_status_flipped_from_ok_to_failed_is_refused(copy):
    with h5py.File(copy, "r") as f:
        i = int(np.flatnonzero(f["status"][()] == 0)[0])
    flip(copy, stored_offset(copy, "status", i), 0x02)  # 0 -> 2, a "failed" point with values
    with pytest.raises(ValueError, match="data corrupted") as raised:
        impactid.open_results(copy)
    assert str(raised.value).startswith(f"{copy}: status: ")


@pytest.mark.parametrize("code", [64, np.iinfo(np.int32).min])
def test_a_status_that_is_no_status_code_is_refused(copy, code):
    # Written through HDF5, so that the checksum matches: the status check refuses it.
    with h5py.File(copy, "r+") as f:
        f["status"][3] = code
    with pytest.raises(ValueError) as raised:
        impactid.open_results(copy)
    assert str(raised.value) == f"{copy}: status[3] = {code} is not a status code (-1, 0, 1, 2)"


def test_damaged_plan_text_is_refused(copy):
    at = copy.read_bytes().find(b'name = "demo"')
    assert at >= 0
    flip(copy, at + len('name = "d'), 0x01)
    with pytest.raises(ValueError, match="impactid_checksum.*data corrupted"):
        impactid.open_results(copy)


def test_a_history_file_is_refused_by_name(tmp_path, executable):
    history = tmp_path / "history.h5"
    subprocess.run([executable, "simulate", "--history", str(history)], check=True,
                   capture_output=True)
    with pytest.raises(ValueError) as raised:
        impactid.open_results(history)
    assert str(raised.value) == (f"{history}: not an impactid results file: a history file "
                                 "(impactid simulate --history)")


def test_a_spectral_file_is_refused_by_name(tmp_path, executable):
    plan = tmp_path / "spectral.toml"
    plan.write_text(SPECTRAL_PLAN)
    spectral = tmp_path / "spectral.h5"
    subprocess.run([executable, "run", str(plan), "--output", str(spectral)], check=True,
                   capture_output=True)
    with pytest.raises(ValueError) as raised:
        impactid.open_results(spectral)
    assert str(raised.value) == (f"{spectral}: not an impactid results file: a spectral file "
                                 '(format "impactid-spectral-1", impactid spectral)')


def test_a_file_without_checksums_loads_with_a_note(copy, capfd):
    with h5py.File(copy, "r+") as f:
        del f.attrs["impactid_checksum"]
    ds = impactid.open_results(copy)
    assert ds.sizes["delta"] == 11
    assert f"{copy}: no checksums" in capfd.readouterr().err
