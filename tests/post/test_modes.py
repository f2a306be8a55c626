"""`rubsim modal`'s mode shapes read back with pyvista/VTK and h5py (off screen) and compared
with rubsim's own tables: `modes.csv` (frequency, damping, whirl) and `mode_shapes.csv` (the
normalised complex shape per node).

    .venv/bin/python -m pytest tests/post/test_modes.py

The rubsim binary is $RUBSIM_BIN, else target/release/rubsim.
"""
import csv
import os
import subprocess

import h5py
import numpy as np
import pytest
import pyvista as pv

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BIN = os.environ.get("RUBSIM_BIN", os.path.join(ROOT, "target", "release", "rubsim"))
SCENE = os.path.join(ROOT, "scenes", "fe", "ross_rotor_example.toml")
MODES = 6
FRAMES = 36


@pytest.fixture(scope="module")
def modal(tmp_path_factory):
    """ROSS's rotor_example (free axial and torsional DOFs) at 500 rad/s, 6 modes."""
    out = tmp_path_factory.mktemp("modal") / "out"
    assert os.path.exists(BIN), f"{BIN} missing: build with `cargo build --release`"
    r = subprocess.run(
        [BIN, "modal", SCENE, "--speed", "500", "--unit", "rad/s", "--modes", str(MODES),
         "--out", str(out)],
        capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    with open(out / "modes.csv") as f:
        modes = list(csv.DictReader(f))
    with open(out / "mode_shapes.csv") as f:
        rows = list(csv.DictReader(f))
    shapes = {}
    for r in rows:
        shapes.setdefault(int(r["mode"]), []).append(r)
    return out, modes, shapes


def complex_shape(rows):
    """(nodes, 4) complex [u_x, u_y, θ_x, θ_y] from mode_shapes.csv."""
    cols = ["ux", "uy", "theta_x", "theta_y"]
    return np.array([[float(r[c + "_re"]) + 1j * float(r[c + "_im"]) for c in cols] for r in rows])


def test_every_mode_has_its_files(modal):
    out, modes, shapes = modal
    assert len(modes) == MODES and sorted(shapes) == list(range(1, MODES + 1))
    for k in range(1, MODES + 1):
        for name in [f"mode_{k:02}.png", f"mode_{k:02}_3d.png", f"modes/mode_{k:02}.vtu",
                     f"modes/mode_{k:02}.pvd", f"modes/mode_{k:02}.vtkhdf"]:
            p = out / name
            assert p.is_file() and p.stat().st_size > 0, name
        with open(out / f"mode_{k:02}.png", "rb") as f:
            assert f.read(8) == b"\x89PNG\r\n\x1a\n"


def test_vtu_holds_the_normalised_shape_of_the_csv(modal):
    out, modes, shapes = modal
    for k in range(1, MODES + 1):
        phi = complex_shape(shapes[k])
        g = pv.read(str(out / f"modes/mode_{k:02}.vtu"))
        z = np.array([float(r["z_m"]) for r in shapes[k]])
        np.testing.assert_allclose(g.points[:, 2], z, rtol=0, atol=1e-12)
        np.testing.assert_allclose(g.points[:, :2], 0.0)
        assert g.n_cells == 1 and g.celltypes[0] == pv.CellType.POLY_LINE
        for c, name in enumerate(["ux", "uy", "theta_x", "theta_y"]):
            np.testing.assert_allclose(g.point_data[name + "_re"], phi[:, c].real, atol=1e-9)
            np.testing.assert_allclose(g.point_data[name + "_im"], phi[:, c].imag, atol=1e-9)
        np.testing.assert_allclose(g.point_data["shape_re"][:, :2], phi[:, :2].real, atol=1e-9)
        # Normalised: the largest entry of the mode (lateral, axial or torsional) is 1.
        big = max(np.abs(phi[:, :2]).max(),
                  np.abs(g.point_data.get("uz_re", np.zeros(1))).max(),
                  np.abs(g.point_data.get("theta_z_re", np.zeros(1))
                         + 1j * g.point_data.get("theta_z_im", np.zeros(1))).max())
        assert big == pytest.approx(1.0, rel=1e-9)
        # The major semi-axis of each node's whirl ellipse, |F| + |B|.
        f = 0.5 * np.abs(phi[:, 0] + 1j * phi[:, 1])
        b = 0.5 * np.abs(np.conj(phi[:, 0]) + 1j * np.conj(phi[:, 1]))
        np.testing.assert_allclose(g.point_data["major"], f + b, atol=1e-9)
        np.testing.assert_allclose(g.point_data["minor"], f - b, atol=1e-9)
        w = modes[k - 1]["whirl"]
        if w in ("FW", "BW"):
            assert np.sign((f - b)[np.argmax(f + b)]) == (1 if w == "FW" else -1)


def test_pvd_animates_one_period_of_the_mode(modal):
    out, modes, shapes = modal
    for k in (1, 2, MODES):
        wd = float(modes[k - 1]["omega_d_rad_s"])
        phi = complex_shape(shapes[k])
        r = pv.get_reader(str(out / f"modes/mode_{k:02}.pvd"))
        t = np.array(r.time_values)
        assert len(t) == FRAMES
        # modes.csv holds ω_d to 9 digits.
        np.testing.assert_allclose(t, 2 * np.pi * np.arange(FRAMES) / FRAMES / wd, rtol=1e-8)
        for i in (0, 5, 17):
            r.set_active_time_point(i)
            g = r.read()[0]
            a = 2 * np.pi * i / FRAMES
            d = g.point_data["displacement"]
            np.testing.assert_allclose(d[:, 0], (phi[:, 0] * np.exp(1j * a)).real, atol=1e-9)
            np.testing.assert_allclose(d[:, 1], (phi[:, 1] * np.exp(1j * a)).real, atol=1e-9)
            # Warped by its displacement the line is the deformed shaft.
            warped = g.warp_by_vector("displacement")
            np.testing.assert_allclose(warped.points[:, 0], d[:, 0], atol=1e-12)


def test_vtkhdf_matches_the_csv_and_animates(modal):
    out, modes, shapes = modal
    for k in range(1, MODES + 1):
        path = str(out / f"modes/mode_{k:02}.vtkhdf")
        phi = complex_shape(shapes[k])
        with h5py.File(path) as f:
            assert f.attrs["omega_d_rad_s"] == pytest.approx(
                float(modes[k - 1]["omega_d_rad_s"]), rel=1e-8)
            assert f.attrs["damping_ratio"] == pytest.approx(
                float(modes[k - 1]["damping_ratio"]), rel=1e-6, abs=1e-12)
            assert f.attrs["whirl"] == modes[k - 1]["whirl"]
            assert f.attrs["speed_rad_s"] == pytest.approx(500.0)
            sh = f["mode/shape_re"][:] + 1j * f["mode/shape_im"][:]
            np.testing.assert_allclose(sh, phi, atol=1e-9)
            assert f["VTKHDF/Steps"].attrs["NSteps"] == FRAMES
        r = pv.get_reader(path)
        assert r.reader.GetNumberOfSteps() == FRAMES
        r.reader.SetStep(9)
        g = r.read()
        a = 2 * np.pi * 9 / FRAMES
        np.testing.assert_allclose(g.point_data["displacement"][:, 1],
                                   (phi[:, 1] * np.exp(1j * a)).real, atol=1e-9)
        np.testing.assert_allclose(g.point_data["uy_im"], phi[:, 1].imag, atol=1e-9)
