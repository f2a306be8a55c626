#!/usr/bin/env python3
"""rubsim beside ROSS on ROSS's rub example (issue 15; figures in docs/PERFORMANCE.md).

Runs ROSS's `rotor.run_rubbing` (full model and its 12-mode pseudo-modal reduction) and rubsim
(`examples/ross_rub.rs` on `scenes/fe/ross_rub_example.toml`: explicit collocated, Newmark,
generalised-α) on the same case, each at several steps and against its own converged run,
and prints per run: Δt, wall time per call (ROSS after a warm-up call that compiles it; rubsim
setup + loop, the process start left out), the rms orbit error of node 12 against its own
reference, and the orbit difference between the two converged runs.

The case: ROSS's `rubbing_example` with friction 0 (ROSS's friction term is not Coulomb's:
component by component |F|, not along the tangent) and, because the example as published never
touches (largest radius 53.7 µm < δ = 79.5 µm, in ROSS and rubsim alike), an unbalance of
UNBALANCE kg·m instead of 2e-4.

    python3.13 -m venv /tmp/ross313 && /tmp/ross313/bin/pip install ross-rotordynamics
    cargo build --release --example ross_rub
    /tmp/ross313/bin/python scripts/ross_compare.py [--quick | --cross]

`--cross` runs only the two converged runs (ROSS's full model at 5e-6 s, rubsim generalised-α
at 1e-6 s) and prints how far apart their orbits are (ROSS 3.0.0 on Python 3.12 does too).
`--rubsim` runs only rubsim's rows (no ROSS needed: numpy only).
"""

import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
SCENE = REPO / "scenes/fe/ross_rub_example.toml"
EXAMPLE = REPO / "target/release/examples/ross_rub"
UNBALANCE = 6e-4
T_END = 0.5
SAMPLE = 1e-4  # the common output grid (s): ROSS's default step


def ross_run(dt, modes=None):
    """ROSS's rub example at step dt (modes: pseudo-modal reduction); (t, x, y, wall s)."""
    import ross as rs
    from ross.units import Q_

    rotor = rs.rotor_example_with_damping()
    t = np.arange(0, T_END, dt)
    kw = {} if modes is None else {"model_reduction": {"num_modes": modes}}
    start = time.perf_counter()
    res = rotor.run_rubbing(
        n=12, distance=7.95e-5, contact_stiffness=1.1e6, contact_damping=40,
        friction_coeff=0.0, torque=False, node=[12, 24],
        unbalance_magnitude=[UNBALANCE, 0], unbalance_phase=[-np.pi / 2, 0],
        speed=Q_(1200, "RPM"), t=t, **kw)
    wall = time.perf_counter() - start
    d = rotor.number_dof
    every = max(1, round(SAMPLE / dt))
    return t[::every], res.yout[::every, d * 12], res.yout[::every, d * 12 + 1], wall


def rubsim_run(integrator, dt=None):
    """rubsim on the scene; (t, x, y, wall s) with wall = setup + loop."""
    sets = [f"run.integrator=\"{integrator}\"", f"rotor.unbalance.0.mass={UNBALANCE}",
            "station.0.friction=0", "run.samples_per_rev=500"]
    if dt is not None:
        sets.append(f"run.dt={dt!r}")
    out = subprocess.run([str(EXAMPLE), str(SCENE), *sets], capture_output=True, text=True,
                         check=True)
    info = dict(kv.split("=") for kv in out.stderr.split())
    data = np.loadtxt(out.stdout.splitlines()[1:], delimiter=",")
    wall = float(info["setup_s"]) + float(info["loop_s"])
    return data[:, 0], data[:, 1], data[:, 2], wall, float(info["dt"])


def grid(t, x, y):
    """x, y on the common grid k × SAMPLE, k = 0 … < T_END/SAMPLE."""
    tk = np.arange(0, round(T_END / SAMPLE)) * SAMPLE
    return np.interp(tk, t, x), np.interp(tk, t, y)


def rms_error(run, ref):
    """rms |orbit − reference| over 0 … 0.5 s, relative to the reference's rms radius."""
    (x, y), (xr, yr) = grid(*run[:3]), grid(*ref[:3])
    return float(np.sqrt(np.mean((x - xr) ** 2 + (y - yr) ** 2) / np.mean(xr**2 + yr**2)))


def window_errors(run, ref, windows=10):
    """rms_error over each of `windows` equal parts of 0 … T_END (the same normalisation)."""
    (x, y), (xr, yr) = grid(*run[:3]), grid(*ref[:3])
    d2 = ((x - xr) ** 2 + (y - yr) ** 2).reshape(windows, -1).mean(axis=1)
    return [float(v) for v in np.sqrt(d2 / np.mean(xr**2 + yr**2))]


def cross_only():
    """The converged runs only: their orbits' rms distance over ROSS's rms radius."""
    import ross as rs

    ref_full = ross_run(5e-6)
    ref_rs = rubsim_run("generalized_alpha", 1e-6)
    out = dict(ross_version=rs.__version__, rubsim_vs_ross_full=rms_error(ref_rs, ref_full),
               ross_vs_rubsim=rms_error(ref_full, ref_rs), ross_wall_s=ref_full[3],
               largest_radius_um=float(np.hypot(ref_rs[1], ref_rs[2]).max() * 1e6),
               ross_largest_radius_um=float(np.hypot(ref_full[1], ref_full[2]).max() * 1e6))
    print(json.dumps(out))


def main():
    if "--cross" in sys.argv:
        return cross_only()
    if "--rubsim" in sys.argv:
        rows, ref_rs = rubsim_rows()
        radius = float(np.hypot(ref_rs[1], ref_rs[2]).max() * 1e6)
        return report(rows, dict(largest_radius_um=radius), "ross_compare_rubsim.json")
    quick = "--quick" in sys.argv
    rows = []
    # ROSS: a warm-up call (import and numba compile), then the runs.
    ross_run(1e-4)
    ross_dts = [1e-4, 5e-5, 2e-5] if quick else [1e-4, 5e-5, 2e-5, 1e-5]
    ross_ref_dt = 5e-6 if not quick else 1e-5
    ref_full = ross_run(ross_ref_dt)
    ref_red = ross_run(ross_ref_dt, modes=12)
    for modes, ref, name in [(None, ref_full, "ROSS full"), (12, ref_red, "ROSS 12 modes")]:
        for dt in ross_dts:
            r = ross_run(dt, modes)
            rows.append(dict(code=name, dt=dt, wall_s=r[3], error=rms_error(r, ref)))
    rs_rows, ref_rs = rubsim_rows()
    rows += rs_rows
    cross = dict(rubsim_vs_ross_full=rms_error(ref_rs, ref_full),
                 ross_12_vs_full=rms_error(ref_red, ref_full),
                 largest_radius_um=float(np.hypot(ref_rs[1], ref_rs[2]).max() * 1e6))
    report(rows, cross, "ross_compare.json")


def rubsim_rows():
    """rubsim's rows, each scheme and step against rubsim's own reference; (rows, reference)."""
    rows = []
    # rubsim: its own reference is generalised-α at 1e-6 s (checked against collocated).
    ref_rs = rubsim_run("generalized_alpha", 1e-6)
    ref_col = rubsim_run("collocated", 2.5e-7)
    rows.append(dict(code="rubsim reference check: collocated 2.5e-7 vs g-α 1e-6", dt=2.5e-7,
                     wall_s=ref_col[3], error=rms_error(ref_col, ref_rs)))
    for integ in ["collocated"]:
        r = rubsim_run(integ)
        rows.append(dict(code=f"rubsim {integ}", dt=r[4], wall_s=r[3],
                         error=rms_error(r, ref_rs)))
    for integ in ["newmark", "generalized_alpha"]:
        for dt in [1e-4, 5e-5, 2e-5, 1e-5]:
            best = min((rubsim_run(integ, dt) for _ in range(3)), key=lambda r: r[3])
            rows.append(dict(code=f"rubsim {integ}", dt=best[4], wall_s=best[3],
                             error=rms_error(best, ref_rs),
                             window_errors=window_errors(best, ref_rs)))
    return rows, ref_rs


def report(rows, cross, name):
    for r in rows:
        print(f"{r['code']:<58} dt {r['dt']:.2e}  wall {r['wall_s']:8.3f} s  error {r['error']:.2e}")
        if "window_errors" in r:
            print(f"{'':<12}per {T_END / len(r['window_errors']):g} s: "
                  + " ".join(f"{e:.1e}" for e in r["window_errors"]))
    print(json.dumps(cross))
    (REPO / "target" / name).write_text(json.dumps(dict(rows=rows, cross=cross),
                                                              indent=1))


if __name__ == "__main__":
    main()
