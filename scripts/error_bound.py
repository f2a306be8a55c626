#!/usr/bin/env python3
"""How well rubsim's error report bounds the true error of a sweep (docs/VALIDATION.md §15).

    python3 scripts/error_bound.py DEFAULT_DIR REFERENCE_DIR

DEFAULT_DIR holds a sweep at its default settings, REFERENCE_DIR the same sweep converged far
beyond it, e.g.

    rubsim sweep SCENE --out A
    rubsim sweep SCENE --out R --set run.harmonics=64 --tol 1e-7 --set run.error_estimate=false

Every `sweep.csv` below DEFAULT_DIR (one per variant of a parameter study) is paired with the
file at the same place below REFERENCE_DIR. Per speed:

- the reported estimate `err_extents_rel + transient_residual × span / max|extent|` (the 2Δt/4Δt
  estimate of the extents, relative to their largest magnitude, plus what the stationarity
  test says is left of the transient, `span = max(x_max − x_min, y_max − y_min)`);
- the true error `max |extent − extent_ref| / max |extent_ref|` over the four extents;
- whether the period agrees with the reference's.

Prints one line per file and the totals: the share of speeds whose estimate is not below a
third of the true error (the goal: ≥ 95 %), the share within a factor 3 either way, the median
estimate / true, and the periods that agree. Speeds whose true error is below the CSV's print
resolution (1e-6) count as bounded when their estimate is too.
"""
import csv
import math
import os
import statistics
import sys

EXTENTS = ("x_min_nd", "x_max_nd", "y_min_nd", "y_max_nd")
RESOLUTION = 1e-6


def rows(path):
    with open(path, newline="") as f:
        return {r["speed_ratio"]: r for r in csv.DictReader(f)}


def compare(a, r):
    """Per speed: (speed, estimate, true, same period)."""
    out = []
    for speed, ra in a.items():
        rr = r.get(speed)
        if rr is None:
            raise SystemExit(f"speed {speed} missing from the reference")
        ea = [float(ra[k]) for k in EXTENTS]
        er = [float(rr[k]) for k in EXTENTS]
        big = max(abs(v) for v in er)
        span = max(ea[1] - ea[0], ea[3] - ea[2])
        est = float(ra["err_extents_rel"])
        res = float(ra["transient_residual"] or 0.0)
        if math.isfinite(res):
            est += res * span / max(abs(v) for v in ea)
        true = max(abs(x - y) for x, y in zip(ea, er)) / big
        out.append((float(speed), est, true, ra["period"] == rr["period"]))
    return out


def main():
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    base, ref = sys.argv[1], sys.argv[2]
    files = sorted(
        os.path.relpath(os.path.join(d, f), base)
        for d, _, fs in os.walk(base)
        for f in fs
        if f == "sweep.csv"
    )
    if not files:
        raise SystemExit(f"no sweep.csv below {base}")
    every = []
    for rel in files:
        res = compare(rows(os.path.join(base, rel)), rows(os.path.join(ref, rel)))
        every += res
        below = [s for s, e, t, _ in res if e < t / 3 and t > RESOLUTION]
        print(f"{rel}: {len(res)} speeds, estimate below true/3 at {below or 'none'}")
    n = len(every)
    bounded = sum(1 for _, e, t, _ in every if e >= t / 3 or t <= RESOLUTION)
    within = sum(
        1
        for _, e, t, _ in every
        if t <= RESOLUTION and e <= 3 * RESOLUTION or t > RESOLUTION and t / 3 <= e <= 3 * t
    )
    ratios = [e / t for _, e, t, _ in every if t > RESOLUTION]
    same = sum(1 for *_, p in every if p)
    print(f"speeds: {n}")
    print(f"estimate not below true/3: {bounded} of {n} ({100 * bounded / n:.0f} %)")
    print(f"estimate within a factor 3 either way: {within} of {n} ({100 * within / n:.0f} %)")
    if ratios:
        print(f"median estimate / true: {statistics.median(ratios):.2f}")
    print(f"period as the reference's: {same} of {n}")


if __name__ == "__main__":
    main()
