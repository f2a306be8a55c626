"""The rubsim Python package (issue 30), against the wheel installed in the test venv
(`scripts/test.sh` builds it from the checkout with `pip install ./python`) and the command
line ($RUBSIM_BIN, else target/release/rubsim): the same scene gives the same numbers from
Python and from `rubsim`, the tables are the CSV's, the series open in pyvista, ROSS 3 rotors
import with ROSS's own modal results, and bad input raises a Python exception naming the key.
"""

import json
import math
import os
import pathlib
import subprocess
import threading
import time

import numpy as np
import pytest

import rubsim

ROOT = pathlib.Path(__file__).resolve().parents[2]
BIN = os.environ.get("RUBSIM_BIN", str(ROOT / "target" / "release" / "rubsim"))
PAPER = ROOT / "scenes" / "paper" / "partial_rub.toml"
ROSS3 = ROOT / "tests" / "data" / "ross" / "ross3"
# A shorter paper case: every test here runs in well under a second of rubsim.
SHORT = {"run.revolutions": 140, "run.transient_revolutions": 100}


def cli(*args):
    assert os.path.exists(BIN), f"{BIN} missing: build with `cargo build --release` (or set RUBSIM_BIN)"
    r = subprocess.run([BIN, *map(str, args)], capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 0, r.stderr
    return r


def summary(folder):
    with open(pathlib.Path(folder) / "summary.json") as f:
        return json.load(f)


def without_wall(d):
    """A summary's numbers without the times measured (which differ run to run)."""
    if isinstance(d, dict):
        return {k: without_wall(v) for k, v in d.items() if "wall" not in k and k != "columns_s"}
    if isinstance(d, list):
        return [without_wall(v) for v in d]
    return d


def test_a_run_equals_the_command_line_run(tmp_path):
    scene = rubsim.Scene(PAPER, set=SHORT)
    r = scene.run(1.7, out=tmp_path / "py")
    sets = [a for k, v in SHORT.items() for a in ("--set", f"{k}={v}")]
    cli("run", PAPER, "--speed", "1.7", "--out", tmp_path / "cli", *sets)
    mine, theirs = summary(tmp_path / "py"), summary(tmp_path / "cli")
    assert without_wall(mine["result"]) == without_wall(theirs["result"])
    assert mine["regime"] == theirs["regime"] == r.regime == "1×"
    # The figures `rubsim run` draws, drawn here too.
    for name in ("orbit.png", "spectrum.png", "contact_force.png"):
        assert (tmp_path / "py" / name).is_file(), name
    # Without `out` nothing is written and the numbers are the same, to the bit.
    q = scene.run(1.7)
    assert q.dir is None
    assert np.array_equal(q.orbit, r.orbit) and np.array_equal(q.spectrum, r.spectrum)
    assert without_wall(q.result) == without_wall(r.result)
    # The arrays: the orbit over the analysed window in units of |Z0|, its extents the
    # summary's.
    x, y = r.orbit[:, 0], r.orbit[:, 1]
    ext = r.result["extents_nd"]
    assert np.isclose([x.min(), x.max(), y.min(), y.max()], ext, rtol=0, atol=1e-12).all()
    assert np.allclose(r.orbit_m, r.orbit * r.z0)
    assert r.period == 1 and r.poincare.shape[1] == 2 and r.error is not None and r.error < 1e-3


def test_a_sweep_table_is_its_csv_and_resumes(tmp_path):
    scene = rubsim.Scene(PAPER, set={**SHORT, "run.sweep.from": 1.5, "run.sweep.to": 2.5})
    done = []
    sw = scene.sweep(out=tmp_path / "s", progress=lambda d, n: done.append((d, n)))
    assert done[-1] == (11, 11) and len(done) == 11
    t = sw.table
    with open(tmp_path / "s" / "sweep.csv") as f:
        header = f.readline().strip().split(",")
        rows = [line.strip().split(",") for line in f]
    col = {name: [row[i] for row in rows] for i, name in enumerate(header)}
    assert np.allclose(t["speed_ratio"], np.array(col["speed_ratio"], float), atol=1e-4)
    for name in ("amp_1x_nd", "x_max_nd", "contact_force_max_nd"):
        assert np.allclose(t[name], np.array(col[name], float), rtol=0, atol=1e-6), name
    assert list(t["period"]) == [int(p) for p in col["period"]]
    assert list(t["regime"]) == col["regime"]
    assert t["label"][0] == "1×"
    assert (tmp_path / "s" / "bifurcation.png").is_file()
    # The regimes of the summary: period 1 below the doubling near 2.24, period 2 above.
    assert sw.regimes[0]["period"] == 1 and sw.regimes[0]["from"] == 1.5
    # A second call resumes every case from the store: no case runs again.
    again = []
    sw2 = scene.sweep(out=tmp_path / "s", progress=lambda d, n: again.append(d))
    assert again == [] and np.array_equal(sw2.table["amp_1x_nd"], t["amp_1x_nd"])
    # Without `out`: the same numbers, nothing kept.
    sw3 = scene.sweep(jobs=1)
    assert sw3.dir is None and np.array_equal(sw3.table["amp_1x_nd"], t["amp_1x_nd"])


def test_a_map_lays_out_its_cells(tmp_path):
    scene = rubsim.Scene(
        ROOT / "scenes" / "paper" / "regime_map.toml",
        set={
            **SHORT,
            "run.map.x": {"key": "speed_ratio", "from": 1.5, "to": 2.5, "step": 0.5},
            "run.map.y": {"key": "stator.0.clearance_nd", "from": 0.5, "to": 0.7, "step": 0.1},
        },
    )
    m = scene.map()
    assert m.grid("period").shape == (3, 3)
    assert np.allclose(m.x, [1.5, 2.0, 2.5]) and np.allclose(m.y, [0.5, 0.6, 0.7])
    # Each cell's own speed is its x.
    assert np.allclose(m.grid("speed_ratio"), np.tile(m.x, (3, 1)))
    assert sum(m.summary["map"]["regime_cells"].values()) == 9


def test_a_transient_run_up_with_its_series_in_pyvista(tmp_path):
    scene = rubsim.Scene(
        ROOT / "scenes" / "transients" / "paper_runup.toml",
        set={
            "run.speed_profile.duration": 2.0,
            "run.speed_profile.to": 2.0,
            "output.vtk": {"every": 2000},
        },
    )
    calls = []
    t = scene.transient(out=tmp_path / "t", progress=lambda d, n: calls.append((d, n)))
    assert 150 <= len(calls) <= 260 and calls[-1][0] <= calls[-1][1]
    assert len(t.t) == len(t.speed) == t.response.shape[0]
    # The profile: a ramp from 0.5 to 2 ω_n in 2 s.
    wn = t.omega_n
    assert math.isclose(t.speed[0] / wn, 0.5, rel_tol=1e-9)
    assert abs(t.speed[-1] / wn - 2.0) < 1e-2
    # The rub dissipates: the friction energy never decreases and ends at the summary's.
    assert np.all(np.diff(t.friction_energy) >= 0)
    assert math.isclose(t.friction_energy[-1], t.summary["friction_energy"], rel_tol=1e-12)
    reader = t.series("vtk")
    assert len(reader.time_values) > 5
    reader.set_active_time_point(len(reader.time_values) - 1)
    blocks = reader.read()
    assert blocks.n_blocks >= 1 and blocks[0].n_points > 0


def test_a_scene_from_a_dict_equals_its_file():
    import tomllib

    d = tomllib.loads(PAPER.read_text())
    a = rubsim.Scene(d, set=SHORT, base=PAPER.parent)
    b = rubsim.Scene(PAPER, set=SHORT)
    assert a.to_dict() == b.to_dict()
    assert a.natural_frequency == b.natural_frequency
    # numpy values are taken as numbers.
    c = b.set({"station.0.friction": np.float64(0.2), "run.revolutions": np.int64(150)})
    assert c.to_dict()["run"]["revolutions"] == 150
    # Keyword overrides: `__` for the dot.
    assert b.set(run__revolutions=150).to_dict()["run"]["revolutions"] == 150


def test_ross3_rotors_import_with_rosss_own_modes():
    """The ROSS 3.0 rotors saved by `Rotor.save` (tests/data/ross/ross3), imported from Python:
    ω_d and ζ of their first 12 modes at 0 and 1000 rad/s against ROSS 3's `run_modal` (stored
    by scripts/ross3_fixtures.py) to 1e-8, each ROSS mode matched to rubsim's nearest in ω_d
    among those with ζ < 0.5 (rubsim lists the overdamped pairs too, as ROSS's dense solver
    does; tests/suite/import_ross.rs compares the same way)."""
    ref = json.loads((ROSS3 / "modal_reference.json").read_text())
    assert ref["ross_version"].startswith("3.")
    for name, speeds in ref["rotors"].items():
        scene = rubsim.import_ross(ROSS3 / f"{name}.toml")
        for speed, want in speeds.items():
            got = scene.modal(float(speed), modes=200)
            keep = got.damping_ratio < 0.5
            gwd, gzeta = got.omega_d[keep], got.damping_ratio[keep]
            wd, zeta = np.array(want["wd"]), np.array(want["damping_ratio"])
            near = [int(np.argmin(np.abs(gwd - w))) for w in wd]
            assert np.max(np.abs(gwd[near] / wd - 1)) < 1e-8, (name, speed)
            assert np.max(np.abs(gzeta[near] / zeta - 1)) < 1e-8, (name, speed)


def test_the_gil_is_released_while_rubsim_computes():
    scene = rubsim.Scene(PAPER, set=SHORT)
    ticks = []
    done = threading.Event()

    def work():
        try:
            scene.sweep(jobs=1)
        finally:
            done.set()

    th = threading.Thread(target=work)
    t0 = time.perf_counter()
    th.start()
    while not done.is_set():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    th.join()
    wall = time.perf_counter() - t0
    # The main thread kept running: at least a tick every 20 ms of the sweep.
    assert wall > 0.1 and len(ticks) > wall / 0.02, (wall, len(ticks))


def test_a_callback_that_raises_stops_the_run():
    scene = rubsim.Scene(PAPER, set=SHORT)
    seen = []

    def stop(done, total):
        seen.append(done)
        if len(seen) == 3:
            raise KeyError("stop here")

    with pytest.raises(KeyError, match="stop here"):
        scene.run(1.7, progress=stop)
    assert len(seen) == 3


@pytest.mark.parametrize(
    "overrides,key",
    [
        ({"station.0.friction": float("nan")}, "station.0.friction"),
        ({"station.0.friction": float("inf")}, "station.0.friction"),
        ({"station.0.friction": None}, "station.0.friction"),
        ({"rotor.nosuch": 1.0}, "nosuch"),
        ({"run.revolutions": 10}, "run.revolutions"),
        ({"station.0.friction": -0.1}, "station.0.friction"),
    ],
)
def test_bad_values_raise_scene_errors_naming_the_key(overrides, key):
    with pytest.raises(rubsim.SceneError) as e:
        rubsim.Scene(PAPER, set=overrides)
    assert key in str(e.value)
    assert e.value.key is not None and key.split(".")[-1] in e.value.key


def test_bad_input_never_crashes_the_interpreter(tmp_path):
    with pytest.raises(TypeError, match="run.revolutions"):
        rubsim.Scene(PAPER, set={"run.revolutions": object()})
    with pytest.raises(rubsim.SceneError) as e:
        rubsim.Scene(tmp_path / "missing.toml")
    assert "missing.toml" in str(e.value) and e.value.file.endswith("missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text(PAPER.read_text().replace("[run]", "[run]\nrevolutions = [1, 2]\n", 1))
    with pytest.raises(rubsim.SceneError) as e:
        rubsim.Scene(bad)
    assert e.value.line is not None
    with pytest.raises(TypeError):
        rubsim.Scene(3.5)
    scene = rubsim.Scene(PAPER, set=SHORT)
    with pytest.raises(rubsim.RubsimError, match="speed"):
        scene.run(-1.0)
    with pytest.raises(rubsim.RubsimError, match="speed"):
        scene.run(float("nan"))
    with pytest.raises(rubsim.StudyError, match="speed_profile"):
        scene.transient()
    with pytest.raises(rubsim.StudyError, match="jobs"):
        scene.sweep(jobs=0)
    with pytest.raises(rubsim.RubsimError, match="out="):
        scene.run(1.7).series()
    # A folder rubsim did not make is refused, named, and left as it was.
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("keep")
    with pytest.raises(rubsim.OutputError, match="mine"):
        scene.run(1.7, out=mine)
    assert (mine / "notes.txt").read_text() == "keep" and not (mine / "summary.json").exists()


def test_an_unstable_run_stops_with_a_solve_error():
    scene = rubsim.Scene(PAPER, set={**SHORT, "run.dt": 5e-3, "run.auto_step": False})
    with pytest.raises(rubsim.SolveError):
        scene.run(1.7)


def test_periodic_orbits_and_their_branch(tmp_path):
    """Shooting and continuation from Python: the paper case's period-1 orbit at ν 1.7 is stable
    with the multipliers `rubsim periodic` prints, and its branch doubles its period near
    ν 2.2445 (docs/VALIDATION.md §19, §19.7)."""
    scene = rubsim.Scene(PAPER)
    p = scene.periodic(1.7)
    assert p.converged and p.stable and p.period == 1 and p.instability is None
    assert p.monodromy == "variational" and p.linearisation["contact_steps"] > 0
    assert np.all(np.abs(p.multipliers) < 1)
    cli("periodic", PAPER, "--speed", "1.7", "--out", tmp_path / "p")
    want = summary(tmp_path / "p")["periodic"]["multipliers"]
    assert np.array_equal(p.multipliers, np.array([complex(*m) for m in want]))
    b = scene.continuation(2.1, 2.5, 0.1, period=1)
    kinds = [x["kind"] for x in b.bifurcations]
    assert "period_doubling" in kinds, b.bifurcations
    pd = b.bifurcations[kinds.index("period_doubling")]
    assert abs(pd["speed_ratio"] - 2.2445) < 2e-3
    assert b.table["stable"][0] and not b.table["stable"][-1]
    assert p.refined is None
    # --refine: the multipliers at Δt/2 as the command writes them; in contact, no extrapolation.
    r = scene.periodic(1.7, refine=True).refined
    cli("periodic", PAPER, "--speed", "1.7", "--refine", "--out", tmp_path / "r")
    want = summary(tmp_path / "r")["refined"]
    assert np.array_equal(r["half_step"], np.array([complex(*m) for m in want["half_step"]]))
    assert r["order"] == 1 and r["extrapolated"] is None and r["stable"]
    with pytest.raises(rubsim.RubsimError, match="period"):
        scene.periodic(1.7, period=0)
    with pytest.raises(rubsim.RubsimError, match="step"):
        scene.continuation(2.1, 2.5, -0.1)
    # Branch switching: the period-2 branch from the doubling at 2.24, as `rubsim continue --switch`.
    d = scene.continuation(2.0, 2.6, 0.1, period=1, switch=True, max_period=4)
    assert [b.period for b in d.branches] == [1, 2, 4]
    assert all(len(p) == b.period for b in d.branches for p in b.poincare)
    assert d.switched[0]["parent"] == 0 and abs(d.switched[0]["at_speed_ratio"] - 2.2445) < 0.002
    cli("continue", PAPER, "--from", "2.0", "--to", "2.6", "--step", "0.1", "--period", "1",
        "--switch", "--max-period", "4", "--out", tmp_path / "sw")
    assert without_wall(summary(tmp_path / "sw")["switched"]) == without_wall(d.summary)
    # Switching on a pseudo-arclength branch, as `rubsim continue --arclength --switch`.
    a = scene.continuation(2.0, 2.6, 0.1, period=1, arclength=True, switch=True, max_period=2)
    assert [b.period for b in a.branches] == [1, 2]
    cli("continue", PAPER, "--from", "2.0", "--to", "2.6", "--step", "0.1", "--period", "1",
        "--arclength", "--switch", "--max-period", "2", "--out", tmp_path / "asw")
    assert without_wall(summary(tmp_path / "asw")["switched"]) == without_wall(a.summary)


def test_a_branch_in_a_scene_key_from_python(tmp_path):
    """`Scene.continuation(key=...)` continues the orbit in a scene key at one speed as
    `rubsim continue --key` does (docs/VALIDATION.md §19.2): the same branch, its column named
    by the key, and the refusals of a key it cannot continue."""
    scene = rubsim.Scene(PAPER)
    b = scene.continuation(0.1, 0.2, 0.05, key="station.0.friction", speed=2.0, period=1)
    assert b.parameter == "station.0.friction"
    assert np.allclose(b.table["parameter"], [0.1, 0.15, 0.2])
    assert np.all(b.table["speed_ratio"] == 2.0)
    cli("continue", PAPER, "--key", "station.0.friction", "--speed", "2.0", "--from", "0.1",
        "--to", "0.2", "--step", "0.05", "--period", "1", "--out", tmp_path / "k")
    assert without_wall(summary(tmp_path / "k")["branch"]) == without_wall(b.summary)
    with pytest.raises(rubsim.RubsimError, match="frictoin"):
        scene.continuation(0.1, 0.2, 0.05, key="station.0.frictoin", speed=2.0)
    with pytest.raises(ValueError, match="key="):
        scene.continuation(2.0, 2.2, 0.1, speed=2.0)


def test_the_thermal_spiral_from_python(tmp_path):
    """`Scene.thermal` runs `[thermal]` as `rubsim run` does (issue 27): the same spiral, and
    `run()` refuses such a scene instead of ignoring its heat."""
    scene = rubsim.Scene(ROOT / "scenes" / "thermal" / "newkirk_ring.toml", set={"thermal.duration": 10})
    th = scene.thermal(out=tmp_path / "py")
    cli("run", ROOT / "scenes" / "thermal" / "newkirk_ring.toml", "--set", "thermal.duration=10",
        "--out", tmp_path / "cli")
    want = summary(tmp_path / "cli")["thermal"]
    assert without_wall(summary(tmp_path / "py")["thermal"]) == without_wall(want)
    assert th.growth_rate == want["growth_rate"] > 0
    assert np.all(np.diff(np.abs(th.delta_t)[5:]) > 0)
    assert np.allclose(np.abs(th.bow), np.abs(th.delta_t) * want["bow_per_kelvin"])
    # Its error estimate (run.error_estimate): companions at 2h and 2Δt, as the command prints.
    assert th.error == want["error"] and 0 < th.error["delta_t"] < 0.1
    with pytest.raises(rubsim.StudyError, match="thermal"):
        scene.run()


def test_the_section_conduction_from_python(tmp_path):
    """A scene whose section conducts its heat (`[thermal.conduction]`) spirals from Python as
    from the command line, and its summary carries the section's figures."""
    path = ROOT / "scenes" / "thermal" / "newkirk_conduction.toml"
    sets = {"thermal.duration": 5, "run.error_estimate": False}
    th = rubsim.Scene(path, set=sets).thermal(out=tmp_path / "py")
    cli("run", path, "--set", "thermal.duration=5", "--set", "run.error_estimate=false",
        "--out", tmp_path / "cli")
    want = summary(tmp_path / "cli")["thermal"]
    assert without_wall(summary(tmp_path / "py")["thermal"]) == without_wall(want)
    assert th.growth_rate == want["growth_rate"]
    assert want["section"]["cells"] == 32 and 1.5 < want["section"]["slowest_time_s"] < 2.5


def test_the_thermal_stability_map_from_python(tmp_path):
    """`Scene.map` of a scene with `[thermal]` is the spiral's stability map, as `rubsim map`
    writes it: the same cells and classes, and a grid laid out along the axes."""
    sets = {"run.map.x.step": 0.7}
    scene = rubsim.Scene(ROOT / "scenes" / "thermal" / "newkirk_map.toml", set=sets)
    m = scene.map(out=tmp_path / "py")
    assert isinstance(m, rubsim.ThermalMap)
    cli("map", ROOT / "scenes" / "thermal" / "newkirk_map.toml", "--set", "run.map.x.step=0.7",
        "--out", tmp_path / "cli")
    want = summary(tmp_path / "cli")["thermal_map"]
    assert without_wall(summary(tmp_path / "py")["thermal_map"]) == without_wall(want)
    assert sum(m.classes.values()) == len(m.x) * len(m.y) == 12
    assert m.classes["not_synchronous"] == len(m.x)  # μ 0.3, past the dry whirl at every speed
    g = m.grid("stability")
    assert g.shape == (len(m.y), len(m.x)) and set(g[-1]) == {"not_synchronous"}
    assert np.all(np.isnan(m.grid("growth_rate")[-1])) and np.all(np.isfinite(m.grid("growth_rate")[0]))
    assert rubsim.Scene(ROOT / "scenes" / "thermal" / "newkirk_map.toml", set=sets).map().dir is None


def test_autonomous_orbits_from_python(tmp_path):
    """Dry whip from Python (docs/VALIDATION.md §19.5): `periodic(autonomous=True)` is the
    command's orbit — the same period and multipliers —, its whirl the closed form
    ξ/μ + √(1 + (ξ/μ)²) = 4.23607 ω_n backward; `continuation(autonomous=True, key=...)` in the
    friction is `rubsim continue --autonomous --key`'s branch row for row."""
    dry = ROOT / "scenes" / "periodic" / "dry_whip.toml"
    scene = rubsim.Scene(dry)
    a = scene.periodic(autonomous=True)
    assert isinstance(a, rubsim.Autonomous) and a.converged and not a.stable
    assert abs(a.whirl_ratio + 0.2 / 0.1 + math.sqrt(1 + 4.0)) < 1e-5
    assert abs(a.trivial_multiplier - 1) < 1e-5
    cli("periodic", dry, "--autonomous", "--out", tmp_path / "p")
    want = summary(tmp_path / "p")["autonomous"]
    assert a.period_s == want["period_s"]
    assert np.array_equal(a.multipliers, np.array([complex(*m) for m in want["multipliers"]]))
    b = scene.continuation(0.1, 0.2, 0.05, key="station.0.friction", speed=2.0, autonomous=True)
    assert isinstance(b, rubsim.AutonomousBranch) and b.ended is None
    cli("continue", dry, "--autonomous", "--key", "station.0.friction", "--speed", "2",
        "--from", "0.1", "--to", "0.2", "--step", "0.05", "--out", tmp_path / "c")
    rows = summary(tmp_path / "c")["autonomous_branch"]["points"]
    assert np.array_equal(b.table["whirl_ratio"], np.array([r["whirl_ratio"] for r in rows]))
    assert abs(b.table["whirl_ratio"][1] + 3.0) < 1e-4
    with pytest.raises(ValueError, match="period"):
        scene.periodic(autonomous=True, period=1)
    with pytest.raises(rubsim.RubsimError, match="rotor.unbalance"):
        rubsim.Scene(PAPER).periodic(2.0, autonomous=True)
