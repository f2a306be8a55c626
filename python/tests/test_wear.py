"""Wear from Python (issue 27, docs/VALIDATION.md §23): the rub of scenes/wear/rod_wears_free.toml
wears the rod's tip until the rub ends; the Transient's `wear` holds the history and the worn
nodes as wear.csv and worn_depth.csv do."""

import pathlib

import numpy as np

import rubsim

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_a_rub_wears_itself_free_from_python(tmp_path):
    t = rubsim.Scene(ROOT / "scenes" / "wear" / "rod_wears_free.toml").transient(out=tmp_path / "run")
    w = t.wear
    summary = t.summary["wear"]
    assert summary["free_at_end"]
    # One worn node, the rod's tip, its depth the run's largest and its volume over the area.
    assert list(w["stator"]) == ["rod"] and w["depth"][0] == summary["max_depth_m"]
    assert abs(w["depth"][0] * w["area"][0] / summary["volume_m3"] - 1.0) < 1e-12
    # The history only grows, and ends at the summary's figures.
    h = w["history"]
    assert np.all(np.diff(h[:, 2]) >= 0.0) and h[-1, 2] == summary["max_depth_m"]
    # The same as the command line's files.
    table = np.genfromtxt(tmp_path / "run" / "worn_depth.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    assert abs(float(np.atleast_1d(table["depth_m"])[0]) / w["depth"][0] - 1.0) < 1e-6


def test_an_abradable_casing_is_cut_from_python(tmp_path):
    """scenes/wear/abradable_casing.toml (docs/VALIDATION.md §23.1): the coating's cut as
    worn_depth.csv's `abraded_m` column has it, and the plastic work σ_y × the cut volume."""
    scene = ROOT / "scenes" / "wear" / "abradable_casing.toml"
    t = rubsim.Scene(scene).transient(out=tmp_path / "run")
    w = t.wear
    a = t.summary["wear"]["abradable"]
    assert t.summary["wear"]["free_at_end"] and len(w["abraded"]) == 64
    assert np.array_equal(w["abraded"], w["depth"]) and w["abraded"].max() == a["max_depth_m"]
    assert abs(a["plastic_work_j"] / (20e3 * a["volume_m3"]) - 1.0) < 1e-9
    table = np.genfromtxt(tmp_path / "run" / "worn_depth.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    assert np.allclose(table["abraded_m"], w["abraded"], rtol=1e-6, atol=0)
