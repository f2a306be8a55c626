#!/usr/bin/env python3
"""Compare two rotor histories written by `cargo run --release --example stator_mass_bench`
(CSV `t,x,y,fx,fy`, one row per recorded sample): RUN against REFERENCE over the samples both
hold at the same instants (the recording instants are k/samples_per_rev of a revolution in
both, whatever their Δt).

Prints, relative to the reference's largest |u| (orbit radius) and largest |F|:
  displacement: rms and max of |u_run − u_ref|, the largest |u| of each;
  contact force: rms and max of |F_run − F_ref|, the largest |F| of each.
`--tol REL` exits with status 1 when the largest displacement difference exceeds REL.

Usage: scripts/compare_history.py REFERENCE.csv RUN.csv [--tol REL]
"""
import csv
import math
import sys


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{path}: no samples")
    return [{k: float(v) for k, v in r.items()} for r in rows]


def main(argv):
    tol = None
    if "--tol" in argv:
        i = argv.index("--tol")
        tol = float(argv[i + 1])
        argv = argv[:i] + argv[i + 2:]
    if len(argv) != 2:
        sys.exit(__doc__)
    ref, run = read(argv[0]), read(argv[1])
    n = min(len(ref), len(run))
    for a, b in zip(ref[:n], run[:n]):
        if abs(a["t"] - b["t"]) > 1e-9 * max(abs(a["t"]), 1e-12) + 1e-15:
            sys.exit(f"sample instants differ: {a['t']} against {b['t']}")
    du = [math.hypot(b["x"] - a["x"], b["y"] - a["y"]) for a, b in zip(ref[:n], run[:n])]
    df = [math.hypot(b["fx"] - a["fx"], b["fy"] - a["fy"]) for a, b in zip(ref[:n], run[:n])]
    umax = max(math.hypot(a["x"], a["y"]) for a in ref[:n])
    umax_run = max(math.hypot(b["x"], b["y"]) for b in run[:n])
    fmax = max(math.hypot(a["fx"], a["fy"]) for a in ref[:n])
    fmax_run = max(math.hypot(b["fx"], b["fy"]) for b in run[:n])
    rms = lambda v: math.sqrt(sum(x * x for x in v) / len(v))
    print(f"samples {n} over t = 0 … {ref[n - 1]['t']:.6e} s")
    print(
        f"displacement: max |u| ref {umax:.6e} m, run {umax_run:.6e} m; "
        f"|du| rms {rms(du) / umax:.3e}, max {max(du) / umax:.3e} (of max |u| ref)"
    )
    if fmax > 0:
        print(
            f"contact force: max |F| ref {fmax:.6e} N, run {fmax_run:.6e} N; "
            f"|dF| rms {rms(df) / fmax:.3e}, max {max(df) / fmax:.3e} (of max |F| ref)"
        )
    if tol is not None and max(du) / umax > tol:
        print(f"FAILED: largest displacement difference {max(du) / umax:.3e} > {tol:g}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
