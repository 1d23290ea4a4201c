"""Plans as dicts: axes as lists and NumPy arrays; a file only where one is asked for."""

import os
import tomllib

import numpy as np
import pytest

import impactid


def plan(axes, **extra):
    return dict({"name": "dict-axes", "scene": {"elements": 30}, "method": {"name": "hht"},
                 "study": {"kind": "grid", "axes": axes}}, **extra)


def test_an_axis_may_be_a_numpy_array_or_a_list(tmp_path):
    alpha = np.linspace(-0.3, 0, 7)
    ds = impactid.run_plan(plan({"alpha": alpha, "delta": [0.3, np.float64(0.45)]}),
                           output=tmp_path / "a.h5", threads=1)
    np.testing.assert_array_equal(ds["alpha"].values, alpha)
    np.testing.assert_array_equal(ds["delta"].values, [0.3, 0.45])
    assert ds["eps_p"].shape == (7, 2)
    # The same plan with the axes written out.
    written = impactid.run_plan(plan({"alpha": {"values": alpha.tolist()},
                                      "delta": {"values": [0.3, 0.45]}}),
                                output=tmp_path / "b.h5", threads=1)
    np.testing.assert_array_equal(ds["eps_p"].values, written["eps_p"].values)
    assert ds.attrs["plan"] == written.attrs["plan"]
    text = impactid.plan_text(plan({"alpha": alpha}))
    assert tomllib.loads(text)["study"]["axes"]["alpha"] == {"values": alpha.tolist()}


def test_a_list_of_words_is_a_choice_axis(tmp_path):
    ds = impactid.run_plan(plan({"hht_contact": ["endpoint", "weighted"]}),
                           output=tmp_path / "c.h5", threads=1)
    assert ds.sizes["hht_contact"] == 2


def test_a_dict_without_output_writes_no_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    ds = impactid.run_plan(plan({"alpha": [-0.3, -0.2]}), threads=1)
    assert int((ds["status"] >= 0).sum()) == 2 and ds.attrs["points_done"] == 2
    assert ds.attrs["plan_name"] == "dict-axes"
    assert list(tmp_path.rglob("*")) == []  # no results/dict-axes.h5, nothing else either
    with pytest.raises(ValueError, match="give output="):
        impactid.run_plan(plan({"alpha": [-0.3]}), resume=True)


def test_a_dict_with_an_output_file_writes_it(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    impactid.run_plan(plan({"alpha": [-0.3]}, output={"file": "kept.h5"}), threads=1)
    assert os.path.exists(tmp_path / "kept.h5")
    impactid.run_plan(plan({"alpha": [-0.3]}), threads=1, output="asked.h5")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["asked.h5", "kept.h5"]
