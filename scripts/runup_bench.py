#!/usr/bin/env python3
"""Explicit against implicit on an FE-rotor run-up through its first critical with rub
(docs/PERFORMANCE.md §13): each scheme's error against its own converged run, and its time.

The scene is scenes/transients/friswell_runup_seal.toml (gyroscopic two-disk rotor, seal ring at
the 350 mm disk, 0.5 → 1.5 ω_n in 8 s), its shaft in ELEMENTS Timoshenko elements (default 24:
the explicit step is set by the finest element's stability limit, the implicit one by accuracy).
The error of a run is the largest difference of its tracked 1× amplitude (orders.csv, linearly
interpolated in time) from the converged run's, over the run, relative to the converged peak; the
converged run is the same scheme at a quarter of its finest step. Times are the loop's ("steps
in … s") and the whole process's (wall), best of REPEAT.

    python3 scripts/runup_bench.py [--bin target/release/rubsim] [--elements 24] [--repeat 3]
"""
import argparse
import csv
import os
import re
import subprocess
import tempfile
import time

SCENE = "scenes/transients/friswell_runup_seal.toml"


def sets(elements):
    """--set arguments that refine the shaft keeping the disks, bearings and station in place
    (nodes at 1/3 and 2/3 of the span, bearings at the ends)."""
    e = elements
    if e % 3:
        raise SystemExit("--elements must be a multiple of 3")
    pairs = {
        "rotor.shaft.0.elements": e,
        "rotor.disk.0.node": e // 3,
        "rotor.disk.1.node": 2 * e // 3,
        "rotor.bearing.1.node": e,
        "rotor.unbalance.0.node": 2 * e // 3,
        "station.0.node": 2 * e // 3,
        "output.node": 2 * e // 3,
    }
    out = []
    for k, v in pairs.items():
        out += ["--set", f"{k}={v}"]
    return out


def run(binary, elements, variant, dt, repeat):
    """(times of the 1× windows, amplitudes, loop seconds, wall seconds, steps, Δt)."""
    integrator, reduced = variant
    best = None
    for _ in range(repeat):
        with tempfile.TemporaryDirectory() as out:
            args = [binary, "run", SCENE, *sets(elements), "--set", f'run.integrator="{integrator}"']
            if reduced:
                args += ["--set", "run.reduction={}"]
            if dt is not None:
                args += ["--set", f"run.dt={dt:.6e}"]
            t0 = time.perf_counter()
            p = subprocess.run(args + ["--out", out], capture_output=True, text=True)
            wall = time.perf_counter() - t0
            if p.returncode != 0:
                raise SystemExit(f"{' '.join(args)}\n{p.stderr}")
            text = p.stdout + p.stderr
            m = re.search(r"(\d+) steps in ([0-9.]+) s", text)
            d = re.search(r"Δt = ([0-9.e+-]+) s", text)
            with open(os.path.join(out, "orders.csv")) as f:
                rows = list(csv.DictReader(f))
        t = [float(r["t_s"]) for r in rows]
        a = [float(r["amp_1x_m"]) for r in rows]
        res = (t, a, float(m.group(2)), wall, int(m.group(1)), float(d.group(1)))
        if best is None or res[2] < best[2]:
            best = res
    return best


def error(run_, ref):
    """Largest |A(t) − A_ref(t)| over the run relative to max A_ref (A_ref interpolated)."""
    (t, a), (tr, ar) = run_[:2], ref[:2]

    def interp(x):
        if x <= tr[0]:
            return ar[0]
        for i in range(1, len(tr)):
            if x <= tr[i]:
                w = (x - tr[i - 1]) / (tr[i] - tr[i - 1])
                return ar[i - 1] + w * (ar[i] - ar[i - 1])
        return ar[-1]

    peak = max(ar)
    return max(abs(y - interp(x)) for x, y in zip(t, a) if tr[0] <= x <= tr[-1]) / peak


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default="target/release/rubsim")
    ap.add_argument("--elements", type=int, default=24)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    print(f"{SCENE}, shaft in {args.elements} elements")
    print("scheme                Δt (s)      steps     error     loop (s)  wall (s)")
    variants = (
        (("collocated", False), [1.0]),
        (("newmark", False), [4.0, 2.0, 1.0, 0.5]),
        (("collocated", True), [1.0, 0.5]),
        (("newmark", True), [2.0, 1.0, 0.5]),
    )
    for variant, mults in variants:
        base = run(args.bin, args.elements, variant, None, 1)
        dt0 = base[5]
        levels = [(m, run(args.bin, args.elements, variant, dt0 * m, args.repeat)) for m in mults]
        finest = min(mults)
        ref = run(args.bin, args.elements, variant, dt0 * finest / 4.0, 1)
        label = variant[0] + (" reduced" if variant[1] else "")
        for m, r in levels:
            e = error(r, ref)
            print(f"{label:20s} {r[5]:.3e}  {r[4]:9d}  {e:.2e}  {r[2]:8.3f}  {r[3]:8.3f}")


if __name__ == "__main__":
    main()
