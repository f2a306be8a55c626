#!/usr/bin/env python3
"""Orbits and spectrum cascade from rubsim's HDF5 time series.

    .venv/bin/python post/orbit_cascade.py out/sweep/speed_*/results.vtkhdf --png cascade.png

    .venv/bin/python post/orbit_cascade.py out/run/results.vtkhdf --node 0 --png drive.png

Each argument is one run's `results.vtkhdf` (a `rubsim run`, or the per-speed folders of a
`rubsim sweep` with `output.per_speed` and `output.hdf5`). For each run the steady window
(after `run.transient_revolutions`) of one rotor node is used: its orbit (x, y in µm) and the
Hann-windowed amplitude spectrum of `output.component` against f/ω_n, drawn as a waterfall over
ω/ω_n. The node is `--node N` (any node of the rotor, found through the file's DOF map
`/rotor/node_dofs`), by default the node the run's analysis observed (`output.node`, else the
first station's node). The frames must be evenly spaced with a whole number per revolution (the
default `every`). Prints one line per run: ω/ω_n and the 1×, 1/2×, 1/3× amplitudes (m) — at the
default node the numbers `summary.json` gives as `amp_*_nd` × `z0` when the run kept the scene's
transient (summary.json `transient_revolutions`; a run that went on to reach its steady state
analysed a later window than the scene's) and its period divides 6.

Renders with pyvista off screen (works headless).
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rubsim_results as rr  # noqa: E402


def lines(series, node=None, period=1):
    """{order: amplitude (m)} of the 1×, 1/2× and 1/3× lines at a rotor node (default: the
    observed node, `Series.observed_node`), read as rubsim reads them: at their exact
    frequencies over the last multiple of lcm(6, period) revolutions of the steady window."""
    node = series.observed_node() if node is None else node
    comp = series.scene.get("output", {}).get("component", "y")
    a, b = series.steady()
    per_rev = series.frames_per_rev()
    x = series.node_disp(node)[a:b, 0 if comp == "x" else 1]
    nrev = len(x) // per_rev
    lrev = rr.lines_revolutions(nrev, period)
    x = x[(nrev - lrev) * per_rev:nrev * per_rev]
    return {o: rr.line_exact(x, per_rev, o) for o in (1.0, 0.5, 1.0 / 3.0)}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("results", nargs="+", help="results.vtkhdf files, one per speed")
    ap.add_argument("--png", required=True, help="output picture")
    ap.add_argument("--fmax", type=float, help="top frequency of the cascade (f/ω_n; default: top speed)")
    ap.add_argument("--size", type=int, nargs=2, default=[1400, 640])
    ap.add_argument("--node", type=int,
                    help="rotor node (default: the analysed node, output.node or the first station's)")
    args = ap.parse_args(argv)
    import pyvista as pv

    runs = sorted((rr.Series(p) for p in args.results), key=lambda s: s.speed_ratio)
    nodes = [s.observed_node() if args.node is None else args.node for s in runs]
    for s, n in zip(runs, nodes):
        if s.u is None:
            ap.error(f"{s.path} holds no rotor displacement (output.hdf5.fields without \"displacement\")")
        if not 0 <= n < s.num_nodes:
            ap.error(f"--node {n}: {s.path} has rotor nodes 0…{s.num_nodes - 1}")
    label = f"node {nodes[0]}" if len(set(nodes)) == 1 else "nodes " + ", ".join(map(str, nodes))
    fmax = args.fmax or max(max(s.speed_ratio for s in runs), 1.0)
    pl = pv.Plotter(off_screen=True, shape=(1, 2), window_size=args.size)
    pl.set_background("white")
    # Orbits, µm, side by side along x.
    pl.subplot(0, 0)
    pl.add_text(f"orbits of rotor {label} (um), steady window; label: w/wn", font_size=10)
    out = []
    offset = 0.0
    cmap = pv.LookupTable("viridis")
    for i, (s, node) in enumerate(zip(runs, nodes)):
        a, b = s.steady()
        xy = s.node_disp(node)[a:b] * 1e6
        w = float(np.ptp(xy[:, 0])) if len(xy) else 1.0
        pts = np.c_[xy[:, 0] - xy[:, 0].min() + offset, xy[:, 1], np.zeros(len(xy))]
        color = cmap.map_value(i / max(len(runs) - 1, 1))
        pl.add_mesh(pv.lines_from_points(pts), color=color, line_width=2)
        pl.add_point_labels([pts[0] + [0.0, 0.0, 0.0]], [f"{s.speed_ratio:g}"], font_size=10, point_size=1, shape=None)
        offset += w * 1.2 + 1e-9
        amp = lines(s, node)
        out.append((s.speed_ratio, amp[1.0], amp[0.5], amp[1.0 / 3.0]))
    pl.view_xy()
    pl.show_bounds(xtitle="x (um, shifted per speed)", ytitle="y (um)", color="black", font_size=8)
    # Cascade: amplitude (µm) over f/ω_n (x) and ω/ω_n (y).
    pl.subplot(0, 1)
    pl.add_text(f"spectrum cascade of rotor {label} (um)", font_size=10)
    top = max((rr.spectrum(s, node=n)[1].max() for s, n in zip(runs, nodes)), default=1.0) * 1e6 or 1.0
    zs = (fmax / top) * 0.5
    for s, node in zip(runs, nodes):
        f, spec, _ = rr.spectrum(s, node=node)
        keep = f <= fmax
        pts = np.c_[f[keep], np.full(keep.sum(), s.speed_ratio), spec[keep] * 1e6 * zs]
        pl.add_mesh(pv.lines_from_points(pts), color="navy", line_width=2)
    pl.show_bounds(xtitle="f / wn", ytitle="w / wn", ztitle=f"amplitude (um x{zs:.3g})", color="black", font_size=8)
    pl.view_vector((0.35, -1.0, 0.8))
    pl.screenshot(args.png)
    pl.close()
    for v, a1, a2, a3 in out:
        print(f"ω/ωn = {v:g}, {label}: 1× {a1:.6e} m, 1/2× {a2:.6e} m, 1/3× {a3:.6e} m")
    print(args.png)
    return out


if __name__ == "__main__":
    main()
