"""rubsim's VTK and HDF5 time series read back with the real clients (pyvista/VTK, meshio, h5py)
and compared with the run's own numbers (summary.json); the post/ scripts rendered off screen.

Run with the project's venv after a release build (scripts/test.sh does both):

    .venv/bin/python -m pytest tests/post

The rubsim binary is $RUBSIM_BIN, else target/release/rubsim.
"""
import json
import os
import subprocess
import sys

import h5py
import meshio
import numpy as np
import pytest
import pyvista as pv

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "post"))
import animate  # noqa: E402
import orbit_cascade  # noqa: E402
import rubsim_results as rr  # noqa: E402

SCENES = os.path.join(ROOT, "tests", "data", "scenes")
BIN = os.environ.get("RUBSIM_BIN", os.path.join(ROOT, "target", "release", "rubsim"))


def rubsim(*args):
    assert os.path.exists(BIN), f"{BIN} missing: build with `cargo build --release` (or set RUBSIM_BIN)"
    r = subprocess.run([BIN, *args], capture_output=True, text=True)
    assert r.returncode == 0, f"rubsim {args} failed:\n{r.stderr}"
    return r.stdout


@pytest.fixture(scope="module")
def arc(tmp_path_factory):
    """The meshed truss arc (300 nodes, 448 bars): 16 revolutions (a 6-revolution window, the
    transient held at 10), the last as VTK frames every 2 steps, the whole run in HDF5 at the
    recording interval."""
    out = tmp_path_factory.mktemp("arc") / "out"
    rubsim(
        "run", os.path.join(SCENES, "fe_arc.toml"), "--out", str(out),
        "--set", "run.revolutions=16", "--set", "run.transient_revolutions=10",
        "--set", "run.max_transient_revolutions=10",
        "--set", "output.vtk={ every = 2, from_revolution = 15 }",
        "--set", "output.hdf5={}",
    )
    with open(out / "summary.json") as f:
        summary = json.load(f)
    return out, summary


def test_hdf5_reproduces_the_summary(arc):
    out, summary = arc
    res = summary["result"]
    s = rr.Series(str(out / "results.vtkhdf"))
    assert s.frames_per_rev() == 64
    assert len(s.t) == 16 * 64 + 1
    a, b = s.steady()
    assert (a, b) == (10 * 64, 16 * 64)
    xy = s.station_disp(0)[a:b] / res["z0"]
    ext = [xy[:, 0].min(), xy[:, 0].max(), xy[:, 1].min(), xy[:, 1].max()]
    np.testing.assert_allclose(ext, res["extents_nd"], rtol=1e-12, atol=1e-12)
    # The summary's peak is taken at every step of the window (issue 13), the file holds one
    # step in `record_every`: the recorded peak is at most the summary's, and here below it.
    fmax = np.linalg.norm(s.station_force[a:b, 0], axis=1).max() / res["unbalance_force"]
    assert int(s.attrs["steps_per_rev"]) > s.frames_per_rev()
    assert 0.5 * res["contact_force_max_nd"] < fmax <= res["contact_force_max_nd"] * (1 + 1e-12)
    steady = res["stats"]["steady"]
    assert steady["force_max"] / res["unbalance_force"] == pytest.approx(
        res["contact_force_max_nd"], rel=1e-15)
    assert res["contact_fraction"] == steady["contact_instants"] / steady["instants"]
    amp = orbit_cascade.lines(s)
    assert amp[1.0] / res["z0"] == pytest.approx(res["amp_1x_nd"], rel=1e-9)
    assert amp[0.5] / res["z0"] == pytest.approx(res["amp_half_nd"], rel=1e-9, abs=1e-12)
    # The resolved scene and the units travel with the file.
    assert s.scene["run"]["revolutions"] == 16
    assert s.units["force"] == "N"
    # The station force on the rotor is minus the sum of the pair forces.
    np.testing.assert_allclose(s.station_force[:, 0], -s.pair_force.sum(axis=1), atol=1e-9)
    # Multipliers are non-negative, and several nodes of the arc carry load at once.
    assert (s.p >= 0).all() and (s.p > 0).sum(axis=1).max() >= 2


def test_pvd_and_vtkhdf_step_through_the_same_states(arc):
    out, _ = arc
    s = rr.Series(str(out / "results.vtkhdf"))
    pvd = pv.get_reader(str(out / "results.pvd"))
    times = np.asarray(pvd.time_values)
    # One revolution (15 → 16) every 2 steps: steps_per_rev / 2 + 1 frames.
    spr = int(s.attrs["steps_per_rev"])
    assert len(times) == spr // 2 + 1
    assert np.all(np.diff(times) > 0)
    h = pv.get_reader(str(out / "results.vtkhdf"))
    assert h.reader.GetNumberOfSteps() == len(s.t)
    dt = float(s.attrs["dt_s"])
    checked = 0
    for i, t in enumerate(times):
        pvd.set_active_time_point(i)
        g = pvd.read()[0]
        step = int(round(t / dt))
        assert step % 2 == 0
        # Frames on the recording interval are also in the HDF5 series: compare everything.
        k = np.nonzero(s.step == step)[0]
        if len(k) == 0:
            continue
        k = int(k[0])
        assert s.t[k] == pytest.approx(t, rel=1e-15)
        h.reader.SetStep(k)
        hg = h.read()
        np.testing.assert_array_equal(g.points, hg.points)
        np.testing.assert_array_equal(g.point_data["displacement"], hg.point_data["displacement"])
        np.testing.assert_array_equal(g.point_data["contact_force"], hg.point_data["contact_force"])
        rotor = g.point_data["displacement"][-1]
        np.testing.assert_array_equal(rotor[:2], s.u[k])
        # .vtu: only pairs in contact; VTKHDF: every pair, open ones with zero force.
        part = g.cell_data["part"]
        ncontact = int((part == rr.PART_CONTACT).sum())
        assert ncontact == int((s.p[k] > 0).sum())
        np.testing.assert_array_equal(np.sort(g.cell_data["normal_force"][part == rr.PART_CONTACT]),
                                      np.sort(s.p[k][s.p[k] > 0]))
        body = part != rr.PART_CONTACT
        np.testing.assert_array_equal(g.cell_data["stress"][body], hg.cell_data["stress"][: body.sum()])
        checked += 1
    every = int(s.attrs["every"])
    assert checked == sum(1 for t in times if int(round(t / dt)) % every == 0) == 65


def test_stress_strain_and_forces_are_consistent(arc):
    out, _ = arc
    s = rr.Series(str(out / "results.vtkhdf"))
    bars = s.scene["stator"][0]["elements"]
    frames = rr.pvd_frames(str(out / "results.pvd"))
    g = pv.read(frames[len(frames) // 2][1])
    part = g.cell_data["part"]
    idx = g.cell_data["index"][part == rr.PART_STATOR]
    e = np.array([bars[i]["youngs_modulus"] for i in idx])
    a = np.array([bars[i]["area"] for i in idx])
    stress = g.cell_data["stress"][part == rr.PART_STATOR]
    np.testing.assert_allclose(g.cell_data["strain"][part == rr.PART_STATOR] * e, stress, rtol=1e-12)
    np.testing.assert_allclose(g.cell_data["axial_force"][part == rr.PART_STATOR], stress * a, rtol=1e-12)
    # Fixed outer nodes (150 … 299) do not move.
    assert not np.any(g.point_data["displacement"][150:300])


def test_meshio_reads_a_frame(arc):
    out, _ = arc
    frames = rr.pvd_frames(str(out / "results.pvd"))
    m = meshio.read(frames[0][1])
    assert len(m.points) == 301
    lines = sum(len(c.data) for c in m.cells if c.type == "line")
    verts = sum(len(c.data) for c in m.cells if c.type == "vertex")
    assert verts == 1  # the Jeffcott rotor
    assert lines >= 448  # the bars, plus the pairs in contact
    assert m.point_data["displacement"].shape == (301, 3)


def test_animate_renders_a_png_and_a_movie(arc, tmp_path):
    out, _ = arc
    png = tmp_path / "frame.png"
    animate.main([str(out / "results.pvd"), "--png", str(png), "--frame", "10"])
    img = pv.read(str(png))
    rgb = np.asarray(img.point_data[img.point_data.keys()[0]])
    assert img.dimensions[:2] == (1024, 768)
    # Not blank: white background with drawn stator, section and text.
    assert (rgb[:, :3] < 200).any() and len(np.unique(rgb[:, :3], axis=0)) > 10
    gif = tmp_path / "rub.gif"
    animate.main([str(out / "results.vtkhdf"), "--movie", str(gif), "--every", "200", "--size", "320", "240"])
    import imageio.v3 as iio

    assert iio.improps(str(gif)).shape[0] == len(range(0, 16 * 64 + 1, 200))


def test_sweep_per_speed_and_cascade(tmp_path):
    out = tmp_path / "sweep"
    # The post scripts take the steady window from the scene and read the lines over its last
    # multiple of 6 revolutions: hold the transient at the scene's (no sliding window) and
    # compare at two speeds whose period divides 6 (rubsim reads a period p over lcm(6, p)
    # revolutions); a window that is not periodic is not lengthened for the 0-1 test either.
    rubsim("sweep", os.path.join(SCENES, "sweep.toml"), "--out", str(out),
           "--set", "output.hdf5={}", "--set", "output.per_speed=[1.5, 2.0]",
           "--set", "run.max_transient_revolutions=10", "--set", "run.classify_revolutions=0")
    assert sorted(p.name for p in out.iterdir() if p.name.startswith("speed_")) == ["speed_1.5", "speed_2"]
    with open(out / "summary.json") as f:
        speeds = {round(r["speed_ratio"], 6): r for r in json.load(f)["sweeps"][0]["speeds"]}
    png = tmp_path / "cascade.png"
    rows = orbit_cascade.main([str(out / "speed_2" / "results.vtkhdf"), str(out / "speed_1.5" / "results.vtkhdf"),
                               "--png", str(png)])
    assert [r[0] for r in rows] == [1.5, 2.0]
    for v, a1, a2, a3 in rows:
        r = speeds[v]
        assert r["period"] in (0, 1, 2, 3, 6) and r["transient_revolutions"] == 10
        assert a1 / r["z0"] == pytest.approx(r["amp_1x_nd"], rel=1e-9)
        assert a2 / r["z0"] == pytest.approx(r["amp_half_nd"], rel=1e-9, abs=1e-12)
        assert a3 / r["z0"] == pytest.approx(r["amp_third_nd"], rel=1e-9, abs=1e-12)
    assert png.stat().st_size > 10_000
    # The existing sweep script still reads sweep.csv.
    r = subprocess.run([sys.executable, os.path.join(ROOT, "post", "plot_sweep.py"), str(out / "sweep.csv")],
                       capture_output=True, text=True)
    assert r.returncode == 0 and "1.50" in r.stdout


@pytest.fixture(scope="module", params=[1, 2], ids=["tet4", "tet10"])
def seal(request, tmp_path_factory):
    """The coarse one-tooth 3-D labyrinth seal (tests/data/scenes/seal3d.toml) in linear (Tet4)
    or quadratic (Tet10) tetrahedra: one revolution, frames every 960 steps in both formats."""
    order = request.param
    if os.environ.get("RUBSIM_SKIP_GMSH"):
        pytest.skip("RUBSIM_SKIP_GMSH set: no meshed stator")
    out = tmp_path_factory.mktemp(f"seal_order{order}") / "out"
    rubsim(
        "run", os.path.join(SCENES, "seal3d.toml"), "--out", str(out),
        "--set", f"stator.0.order={order}",
        "--set", "run.revolutions=1", "--set", "run.transient_revolutions=0",
        "--set", "output.vtk={ every = 960 }", "--set", "output.hdf5={ every = 960 }",
    )
    return out, order


def _seal_volume(scene):
    """Exact volume (m³) of the one-tooth seal of geometry/labyrinth_seal.geo: the carrier tube
    (rc…ro over L = tooth + 2 margin) and the fin (rt…rc over the tooth's thickness)."""
    p = {"rc": 0.064, "ro": 0.068, "margin": 0.002, **scene["stator"][0]["parameters"]}
    assert p["teeth"] == 1
    length = p["tooth"] + 2 * p["margin"]
    return np.pi * ((p["ro"] ** 2 - p["rc"] ** 2) * length + (p["rc"] ** 2 - p["rt"] ** 2) * p["tooth"])


def test_tetrahedral_stator_reads_back_with_positive_volumes(seal):
    out, order = seal
    vtk_type, meshio_type = {1: (pv.CellType.TETRA, "tetra"), 2: (pv.CellType.QUADRATIC_TETRA, "tetra10")}[order]
    with h5py.File(out / "results.vtkhdf", "r") as f:
        st = f["stators/0"]
        mesh_file = st.attrs["mesh_file"]
        mesh_file = mesh_file.decode() if isinstance(mesh_file, bytes) else str(mesh_file)
        assert int(st.attrs["dim"]) == 3
        nodes = int(st.attrs["num_nodes"])
        axial = st["axial_dofs"][:]
        scene = json.loads(f.attrs["scene"])
    # gmsh's mesh as meshio reads it (meshio converts gmsh's Tet10 order to VTK's).
    msh = meshio.read(mesh_file)
    ref = msh.cells_dict[meshio_type]
    frames = rr.pvd_frames(str(out / "results.pvd"))
    g = pv.read(frames[-1][1])
    stator = g.cell_data["part"] == rr.PART_STATOR
    assert stator.sum() == len(ref)
    assert (g.celltypes[stator] == vtk_type).all()
    # Points: the mesh's nodes with their own z (the mesh sits at axial_origin = 0).
    assert nodes == len(msh.points)
    np.testing.assert_array_equal(g.points[:nodes], msh.points)
    assert g.points[:nodes, 2].min() < -2e-3 and g.points[:nodes, 2].max() > 2e-3
    # Same cells, node for node, as meshio's reading of the .msh.
    np.testing.assert_array_equal(g.cells_dict[vtk_type], ref)
    # Positive volumes (VTK's cell size filter) summing to the seal's volume: Tet4 facets the
    # curved surfaces, Tet10 follows them closely.
    vol = g.compute_cell_sizes(length=False, area=False, vertex_count=False).cell_data["Volume"][stator]
    assert (vol > 0).all()
    exact = _seal_volume(scene)
    assert vol.sum() == pytest.approx(exact, rel=5e-3 if order == 1 else 1e-3)
    # meshio reads the .vtu frame with the same cells.
    m = meshio.read(frames[-1][1])
    np.testing.assert_array_equal(m.cells_dict[meshio_type], ref)
    # u_z is written: zero where fixed, not zero everywhere.
    uz = g.point_data["displacement"][:nodes, 2]
    assert (uz[axial < 0] == 0).all() and np.abs(uz).max() > 0
    # The VTKHDF grid holds the same cells, points, volumes and fields.
    h = pv.get_reader(str(out / "results.vtkhdf"))
    assert h.reader.GetNumberOfSteps() == len(frames)
    h.reader.SetStep(len(frames) - 1)
    hg = h.read()
    hs = hg.cell_data["part"] == rr.PART_STATOR
    assert (hg.celltypes[hs] == vtk_type).all()
    np.testing.assert_array_equal(hg.points, g.points)
    np.testing.assert_array_equal(hg.cells_dict[vtk_type], ref)
    hvol = hg.compute_cell_sizes(length=False, area=False, vertex_count=False).cell_data["Volume"][hs]
    np.testing.assert_allclose(hvol, vol, rtol=1e-12)
    np.testing.assert_array_equal(hg.point_data["displacement"], g.point_data["displacement"])
    np.testing.assert_array_equal(hg.cell_data["stress"][hs], g.cell_data["stress"][stator])
    assert np.isfinite(g.cell_data["stress"][stator]).all() and g.cell_data["stress"][stator].max() > 0


def test_ring_stator_is_a_circle_around_its_displaced_centre(tmp_path):
    """A ring stator with mass (tests/data/scenes/ring.toml): its contact circle, warped by the
    displacement, lies at its inner radius around the displaced ring centre in every frame."""
    out = tmp_path / "ring"
    rubsim("run", os.path.join(SCENES, "ring.toml"), "--out", str(out), "--set", "output.vtk={ every = 16 }")
    with open(out / "summary.json") as f:
        summary = json.load(f)
    frames = rr.pvd_frames(str(out / "results.pvd"))
    radius = summary["scene"]["station"][0]["radius"]
    moved = 0.0
    rubbing = 0
    for _, path in frames:
        g = pv.read(path)
        part = g.cell_data["part"]
        circle = np.nonzero((part == rr.PART_STATOR) & (g.cell_data["index"] == -1))[0]
        assert len(circle) == 1
        ids = g.get_cell(int(circle[0])).point_ids
        assert g.celltypes[circle[0]] == pv.CellType.POLY_LINE and ids[0] == ids[-1] and len(ids) == 65
        warped = g.warp_by_vector("displacement", factor=1.0)
        centre = warped.points[0]
        r = np.linalg.norm(warped.points[ids[:-1], :2] - centre[:2], axis=1)
        big_r = float(np.linalg.norm(g.points[ids[0], :2] - g.points[0, :2]))
        np.testing.assert_allclose(r, big_r, rtol=1e-12)
        assert big_r > radius
        moved = max(moved, float(np.linalg.norm(g.point_data["displacement"][0, :2])))
        contact = np.nonzero(part == rr.PART_CONTACT)[0]
        if len(contact):
            rubbing += 1
            a, b = g.get_cell(int(contact[0])).point_ids
            # From the section centre to the ring's surface point facing it.
            n = warped.points[a, :2] - centre[:2]
            n /= np.linalg.norm(n)
            np.testing.assert_allclose(warped.points[b, :2], centre[:2] + big_r * n, rtol=0, atol=1e-12 * big_r)
    assert moved > 0 and 0 < rubbing < len(frames)


TORSION_SCENE = os.path.join(ROOT, "scenes", "fe", "paper_rotor_rub_torsion.toml")


@pytest.fixture(scope="module")
def torsion(tmp_path_factory):
    """The paper rotor as FE model with torsional DOFs rubbing the rod, at ω/ω_n = 1.7: 20
    revolutions (steady window 10…20), the last two as VTK frames, the whole run in HDF5, both
    at the recording interval."""
    out = tmp_path_factory.mktemp("torsion") / "out"
    rubsim(
        "run", TORSION_SCENE, "--speed", "1.7", "--out", str(out),
        "--set", "run.revolutions=20", "--set", "run.transient_revolutions=10",
        "--set", "run.error_estimate=false",
        "--set", "output.vtk={ from_revolution = 18 }", "--set", "output.hdf5={}",
    )
    with open(out / "summary.json") as f:
        summary = json.load(f)
    return out, summary


def _rotor_points(grid):
    """Point ids of the rotor polyline (the rotor nodes in node order)."""
    rotor = np.nonzero(grid.cell_data["part"] == rr.PART_ROTOR)[0]
    assert len(rotor) == 1 and grid.celltypes[rotor[0]] == pv.CellType.POLY_LINE
    return np.asarray(grid.get_cell(int(rotor[0])).point_ids)


def test_twist_reads_back_with_pyvista_and_h5py(torsion):
    out, _ = torsion
    s = rr.Series(str(out / "results.vtkhdf"))
    # The DOF map: [u_x, u_y, θ_x, θ_y, u_z, θ_z] per node; lateral 4i…4i+3, no u_z, θ_z after
    # every lateral DOF.
    nd = s.node_dofs
    assert nd.shape == (9, 6)
    with h5py.File(out / "results.vtkhdf", "r") as f:
        cols = rr._plain(f["rotor/node_dofs"].attrs["columns"])
    assert tuple(cols.split()) == rr.ROTOR_DOFS
    np.testing.assert_array_equal(nd[:, :4], 4 * np.arange(9)[:, None] + np.arange(4))
    assert (nd[:, 4] == -1).all() and (nd[:, 5] >= 36).all() and len(set(nd[:, 5])) == 9
    disk = s.station_node(0)
    assert disk == 4
    theta_z = s.u[:, nd[:, 5]]
    np.testing.assert_array_equal(s.twist(disk), theta_z[:, disk])

    pvd = pv.get_reader(str(out / "results.pvd"))
    times = np.asarray(pvd.time_values)
    assert len(times) == 2 * 64 + 1
    h = pv.get_reader(str(out / "results.vtkhdf"))
    assert h.reader.GetNumberOfSteps() == len(s.t)
    for i, t in enumerate(times):
        k = np.nonzero(s.t == t)[0]
        assert len(k) == 1, f"frame at t = {t} in the HDF5 series"
        k = int(k[0])
        pvd.set_active_time_point(i)
        g = pvd.read()[0]
        h.reader.SetStep(k)
        hg = h.read()
        for grid in (g, hg):
            ids = _rotor_points(grid)
            assert len(ids) == 9
            tw = grid.point_data["twist"]
            np.testing.assert_array_equal(tw[ids], theta_z[k])
            np.testing.assert_array_equal(grid.point_data["twist_rate"][ids], s.v[k, nd[:, 5]])
            # NaN off the rotor (the rod's two nodes).
            off = np.setdiff1d(np.arange(grid.n_points), ids)
            assert len(off) == 2 and np.isnan(tw[off]).all()
            # Rotor displacement: [u_x, u_y] of the DOF vector, u_z = 0 (no axial DOFs).
            d = grid.point_data["displacement"][ids]
            np.testing.assert_array_equal(d[:, :2], s.u[k][nd[:, :2]])
            assert not d[:, 2].any()
            # Rotor points on the axis at the nodes' axial positions.
            np.testing.assert_allclose(grid.points[ids, 2], np.linspace(0.0, 0.4, 9), atol=1e-15)
        np.testing.assert_array_equal(g.point_data["twist"], hg.point_data["twist"])

    # Over the steady window the friction torque −R μ p (against the spin) winds the disk back,
    # more than the drive end on its coupling.
    a, b = s.steady()
    mean = theta_z[a:b].mean(axis=0)
    assert mean[disk] < 0
    assert abs(mean[disk]) > abs(mean[0])
    assert (s.p[a:b] > 0).any()


def test_orbit_cascade_at_any_node(torsion, tmp_path):
    out, summary = torsion
    res = summary["result"]
    path = str(out / "results.vtkhdf")
    s = rr.Series(path)
    a, b = s.steady()
    # Default: the analysed node (the first station's, the disk): the summary's numbers.
    png = tmp_path / "disk.png"
    (row,) = orbit_cascade.main([path, "--png", str(png)])
    assert row[1] / res["z0"] == pytest.approx(res["amp_1x_nd"], rel=1e-9)
    assert png.stat().st_size > 10_000
    # --node 0 (the drive-end journal): the y spectrum of its own DOF, found through the map.
    (row0,) = orbit_cascade.main([path, "--node", "0", "--png", str(tmp_path / "n0.png")])
    y0 = s.u[a:b, s.node_dofs[0, 1]]
    per_rev = s.frames_per_rev()
    nrev = (b - a) // per_rev
    lrev = rr.lines_revolutions(nrev)
    y0 = y0[(nrev - lrev) * per_rev:nrev * per_rev]
    assert row0[1] == pytest.approx(rr.line_exact(y0, per_rev, 1.0), rel=1e-12)
    # The journal on its 1e8 N/m bearing barely moves next to the disk.
    assert 0 < row0[1] < 0.1 * row[1]
    with pytest.raises(SystemExit):
        orbit_cascade.main([path, "--node", "9", "--png", str(tmp_path / "bad.png")])


def test_stress_colour_range_is_signed_only_for_signed_stress():
    """Bars' axial stress (signed) gets a range symmetric about 0 on a diverging map; von Mises
    (never negative) gets 0 … max on a sequential map; no stress, no range."""

    def grid(values):
        g = pv.UnstructuredGrid({pv.CellType.VERTEX: np.arange(len(values)).reshape(-1, 1)}, np.zeros((len(values), 3)))
        g.cell_data["stress"] = np.asarray(values, dtype=float)
        return g

    signed = [grid([-3.0, 1.0]), grid([2.0, np.nan])]
    assert animate.stress_limits(signed, [0, 1]) == ((-3.0, 3.0), "coolwarm")
    mises = [grid([0.0, 5.0]), grid([7.0, 1.0])]
    assert animate.stress_limits(mises, [0, 1]) == ((0.0, 7.0), "viridis")
    assert animate.stress_limits([grid([0.0])], [0]) is None
