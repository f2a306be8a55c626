#!/usr/bin/env python3
"""Print the regime map of a rubsim sweep.csv (and plot it when matplotlib is installed).

Reads only the CSV written by `rubsim sweep`; columns are documented in README.md.
"""
import csv
import sys


def regimes(rows):
    """Group consecutive speeds by Poincaré period: [(period, from, to), ...]."""
    out = []
    for r in rows:
        v, p = float(r["speed_ratio"]), int(r["period"])
        if out and out[-1][0] == p:
            out[-1][2] = v
        else:
            out.append([p, v, v])
    return out


def main(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for p, a, b in regimes(rows):
        name = "not periodic" if p == 0 else ("1x" if p == 1 else f"1/{p}x")
        print(f"{name:>13}  {a:.2f} - {b:.2f}")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    v = [float(r["speed_ratio"]) for r in rows]
    fig, ax = plt.subplots()
    ax.plot(v, [float(r["y_max_nd"]) - float(r["y_min_nd"]) for r in rows], label="vertical orbit size")
    ax.plot(v, [float(r["amp_half_nd"]) for r in rows], label="1/2x")
    ax.plot(v, [float(r["amp_third_nd"]) for r in rows], label="1/3x")
    ax.set_xlabel("omega/omega_n")
    ax.legend()
    fig.savefig(path.replace(".csv", "_regimes.png"), dpi=120)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/partial_rub/sweep.csv")
