"""The periodic orbit of `rubsim periodic` written as a time series (issue 29, item 3), read back
with pyvista/VTK and h5py: one period of k revolutions integrated from the fixed point, its first
frame on the fixed point and its last, one period on, equal to it to the shooting tolerance; the
`.pvd` and the VTKHDF file hold the same frames at the times k T … 2k T (the first period is a
lead-in, docs/OUTPUTS.md "Periodic orbits").

Run with the project's venv after a release build (scripts/test.sh does both):

    .venv/bin/python -m pytest tests/post/test_orbit_series.py

The rubsim binary is $RUBSIM_BIN, else target/release/rubsim. Fast tier (about a second).
"""
import json
import math
import os
import subprocess

import h5py
import numpy as np
import pytest
import pyvista as pv

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BIN = os.environ.get("RUBSIM_BIN", os.path.join(ROOT, "target", "release", "rubsim"))
SCENE = os.path.join(ROOT, "scenes", "paper", "partial_rub.toml")
# The paper case at ν 4.1 settles on its stable period-2 partial rub (docs/VALIDATION.md §19).
NU = 4.1
PERIOD = 2
# The orbit's Newton converges to a residual of 1e-9 of the state or better (measured 2.6e-13);
# the written frames are the same numbers.
CLOSE = 1e-9


def rubsim(*args):
    assert os.path.exists(BIN), f"{BIN} missing: build with `cargo build --release` (or set RUBSIM_BIN)"
    r = subprocess.run([BIN, *args], capture_output=True, text=True)
    assert r.returncode == 0, f"rubsim {args} failed:\n{r.stderr}"
    return r.stdout


@pytest.fixture(scope="module")
def orbit(tmp_path_factory):
    out = tmp_path_factory.mktemp("orbit") / "out"
    rubsim("periodic", SCENE, "--speed", str(NU), "--period", str(PERIOD), "--out", str(out),
           "--set", "output.vtk={}", "--set", "output.hdf5={}", "--set", "output.png=false")
    with open(out / "summary.json") as f:
        summary = json.load(f)
    return out, summary


def rotor_track(grid_of_frame, n):
    """The rotor centre's displacement (the last point of the paper case's grid) in frames 0…n-1."""
    return np.array([grid_of_frame(i)["displacement"][-1] for i in range(n)])


def test_the_orbit_series_closes_after_one_period(orbit):
    out, summary = orbit
    p = summary["periodic"]
    assert p["converged"] and p["stable"] and p["period"] == PERIOD
    series = summary["orbit_series"]
    assert series["folder"] == "orbit/"
    n_steps, dt = series["period_steps"], series["dt"]
    # VTK: k N / every + 1 frames at times k T … 2k T.
    r = pv.get_reader(str(out / "orbit" / "results.pvd"))
    times = np.array(r.time_values)
    every = p["orbit"]["plan"]["record_every"]
    assert len(times) == n_steps // every + 1
    assert times[0] == pytest.approx(n_steps * dt, rel=1e-12)
    assert times[-1] == pytest.approx(2 * n_steps * dt, rel=1e-12)

    def frame(i):
        r.set_active_time_point(i)
        return r.read()[0]

    u = rotor_track(frame, len(times))
    size = np.abs(u).max()
    gap = np.abs(u[-1] - u[0]).max() / size
    print(f"VTK: last frame against first {gap:.2e} of the orbit's size")
    assert gap <= CLOSE
    # The orbit is not a point: it moves by its size within the period.
    assert np.abs(u - u[0]).max() > 0.1 * size
    # The extents of the written period are the orbit's (summary: extents / |Z0| over 6k
    # revolutions of the same orbit, sampled at the same instants).
    z0 = summary["periodic"]["orbit"]["z0"]
    ext = p["orbit"]["extents_nd"]
    assert u[:, 0].min() / z0 == pytest.approx(ext[0], abs=1e-9)
    assert u[:, 1].max() / z0 == pytest.approx(ext[3], abs=1e-9)

    # HDF5: the same frames (VTKHDF point data and the plain /rotor/u).
    with h5py.File(out / "orbit" / "results.vtkhdf", "r") as f:
        t = f["time"][:]
        ru = f["rotor/u"][:]
        assert len(t) == len(times)
        assert np.allclose(t, times, rtol=1e-12, atol=0)
        assert np.abs(ru[-1] - ru[0]).max() / size <= CLOSE
        assert np.allclose(ru[:, :2], u[:, :2], rtol=0, atol=1e-15 * size + 1e-300)
    assert math.isfinite(gap)
