"""The VTK and HDF5 time series of a speed transient read back with pyvista/VTK and h5py: every
frame carries the spin state (time, Ω, Ω/ω_n, φ, Ω̇) as field data, equal to the run's own
speed history (speed_history.csv), and φ is the time integral of Ω.

Run with the project's venv after a release build:

    .venv/bin/python -m pytest tests/post/test_transient_series.py

The rubsim binary is $RUBSIM_BIN, else target/release/rubsim.
"""
import csv
import json
import os
import subprocess

import h5py
import numpy as np
import pytest
import pyvista as pv

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BIN = os.environ.get("RUBSIM_BIN", os.path.join(ROOT, "target", "release", "rubsim"))
SCENE = os.path.join(ROOT, "scenes", "transients", "blade_off_coastdown.toml")
FIELDS = ["TimeValue", "omega", "speed_ratio", "phi", "omega_dot"]


def rubsim(*args):
    assert os.path.exists(BIN), f"{BIN} missing: build with `cargo build --release` (or set RUBSIM_BIN)"
    r = subprocess.run([BIN, *args], capture_output=True, text=True)
    assert r.returncode == 0, f"rubsim {args} failed:\n{r.stderr}"
    return r.stdout


@pytest.fixture(scope="module")
def coast(tmp_path_factory):
    """The driven FE rotor of the blade-off scene, shortened to 0.8 s: blade off at 0.2 s, the
    drive off at 0.5 s, rubbing on the rod. HDF5 at every recorded sample, VTK every tenth."""
    out = tmp_path_factory.mktemp("coast") / "out"
    rubsim("run", SCENE, "--out", str(out), "--set", "run.speed_profile.duration=0.8",
           "--set", "output.hdf5={}", "--set", "output.vtk={ every = 380 }")
    with open(out / "summary.json") as f:
        summary = json.load(f)
    with open(out / "speed_history.csv") as f:
        rows = list(csv.DictReader(f))
    hist = {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}
    return out, summary, hist


def test_hdf5_spin_equals_the_speed_history(coast):
    out, summary, hist = coast
    with h5py.File(out / "results.vtkhdf") as f:
        t = f["time"][:]
        spin = {k: f["spin"][k][:] for k in ("omega", "speed_ratio", "phi", "omega_dot")}
        assert f["spin/omega"].attrs["unit"] == "rad/s"
        assert f["spin/phi"].attrs["unit"] == "rad"
        # VTKHDF field data: one tuple per step at offset k.
        for name in FIELDS:
            np.testing.assert_array_equal(f["VTKHDF/Steps/FieldDataOffsets"][name][:],
                                          np.arange(len(t)))
        np.testing.assert_array_equal(f["VTKHDF/FieldData/TimeValue"][:], t)
        np.testing.assert_array_equal(f["VTKHDF/FieldData/phi"][:], spin["phi"])
    # Default HDF5 frames are the recorded samples: the same instants as speed_history.csv.
    assert len(t) == len(hist["t_s"])
    np.testing.assert_allclose(t, hist["t_s"], rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(spin["omega"], hist["omega_rad_s"], rtol=1e-9)
    np.testing.assert_allclose(spin["phi"], hist["phi_rad"], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(spin["speed_ratio"], hist["speed_ratio"], rtol=1e-6)
    np.testing.assert_allclose(spin["omega_dot"], hist["omega_dot_rad_s2"], rtol=1e-6, atol=1e-9)
    wn = summary["transient"]["omega_n"]
    np.testing.assert_allclose(spin["speed_ratio"], spin["omega"] / wn, rtol=1e-12)
    # The coast-down: the rotor slows after the drive is switched off at 0.5 s.
    assert spin["omega"][-1] < 0.95 * spin["omega"][0]


def test_phi_is_the_integral_of_omega(coast):
    out, _, _ = coast
    with h5py.File(out / "results.vtkhdf") as f:
        t, w, phi = f["time"][:], f["spin/omega"][:], f["spin/phi"][:]
    assert phi[0] == 0.0
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(t))])
    # Trapezoid rule at the recording interval (≈ 0.1 rad per sample): O(h²) against the
    # central-difference spin DOF, far below a revolution over the whole run.
    assert np.abs(integral - phi).max() < 1e-6 * phi[-1]
    assert phi[-1] / (2 * np.pi) > 50


def test_vtk_frames_carry_the_spin_and_the_stress(coast):
    out, _, hist = coast
    r = pv.get_reader(str(out / "results.pvd"))
    times = np.asarray(r.time_values)
    with h5py.File(out / "results.vtkhdf") as f:
        t, w, phi = f["time"][:], f["spin/omega"][:], f["spin/phi"][:]
        dt = f.attrs["dt_s"]
    assert len(times) > 20
    stressed = 0
    for i in range(0, len(times), 7):
        r.set_active_time_point(i)
        g = r.read()[0]
        fd = {k: float(np.asarray(g.field_data[k])[0]) for k in FIELDS}
        assert fd["TimeValue"] == times[i]
        k = int(np.argmin(np.abs(t - times[i])))
        assert abs(t[k] - times[i]) < 1e-3 * dt, "a VTK frame that is not a recorded sample"
        assert fd["omega"] == w[k] and fd["phi"] == phi[k]
        part = np.asarray(g.cell_data["part"])
        s = np.asarray(g.cell_data["stress"])[part == 0]
        assert np.isfinite(s).all()
        stressed += int(np.abs(s).max() > 0)
    assert stressed > 0, "no frame with stress in the rod"
    # The VTKHDF reader gives the same field data per step.
    h = pv.get_reader(str(out / "results.vtkhdf"))
    h.reader.SetStep(len(t) // 2)
    hg = h.read()
    assert float(np.asarray(hg.field_data["phi"])[0]) == phi[len(t) // 2]
    assert float(np.asarray(hg.field_data["omega"])[0]) == w[len(t) // 2]


def test_animate_titles_each_frame_with_its_speed(coast, tmp_path):
    import sys

    sys.path.insert(0, os.path.join(ROOT, "post"))
    import animate

    out, _, _ = coast
    frames = animate.Frames(str(out / "results.vtkhdf"))
    first, last = animate.spin_text(frames[0]), animate.spin_text(frames[len(frames) - 1])
    assert first.startswith("w/wn = 3.000") and first != last
    png = str(tmp_path / "coast.png")
    assert animate.main([str(out / "results.vtkhdf"), "--png", png]) == [png]
    assert os.path.getsize(png) > 1000
