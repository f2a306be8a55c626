#!/usr/bin/env python3
"""Animate a rubsim run: the stator deforming, the rotor section moving and the contact forces.

    .venv/bin/python post/animate.py out/run/results.pvd --png frame.png [--frame K | --time T]
    .venv/bin/python post/animate.py out/run/results.vtkhdf --movie rub.mp4 [--every 2] [--fps 24]

Reads the `.pvd` collection (`.vtu` frames) or the HDF5 file (`results.vtkhdf`, its VTKHDF
group). The picture is the station plane seen from +z (x right, y up):

* stator elements on the displaced nodes, coloured by the bar stress (Pa; |displacement| when
  the run wrote no stress);
* the rotor section as a circle around the displaced station centre;
* contact forces on the stator nodes as arrows (length ∝ force);
* the frame's time and, from its field data, its speed Ω/ω_n and spin angle φ (revolutions) in
  the title — a speed transient (run-up, coast-down, blade-off) changes them frame by frame;
* displacements are magnified by `--scale` (default: the gap is drawn 0.25 (r+δ)/δ times too
  large) and the section radius is reduced by (scale − 1)·δ, so the drawn gap is the true gap
  times the scale: a contact is drawn touching.

Renders off screen (works headless); a movie is `.mp4` (imageio-ffmpeg) or `.gif` (imageio).
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rubsim_results as rr  # noqa: E402


class Frames:
    """The frames of a `.pvd` or `.vtkhdf` as pyvista grids (points undeformed)."""

    def __init__(self, path):
        import pyvista as pv

        self.path = path
        if path.endswith(".pvd"):
            self.items = rr.pvd_frames(path)
            self.times = [t for t, _ in self.items]
            self._get = lambda i: pv.read(self.items[i][1])
        elif path.endswith(".vtkhdf") or path.endswith(".hdf"):
            self.reader = pv.get_reader(path)
            n = self.reader.reader.GetNumberOfSteps()
            import h5py

            with h5py.File(path, "r") as f:
                self.times = list(f["VTKHDF/Steps/Values"][:n])

            def get(i):
                self.reader.reader.SetStep(i)
                return self.reader.read()

            self._get = get
        else:
            raise SystemExit(f"{path}: expected a .pvd or .vtkhdf file written by rubsim")
        if not self.times:
            raise SystemExit(f"{path}: no frames")

    def __len__(self):
        return len(self.times)

    def __getitem__(self, i):
        return self._get(i)

    def index_of_time(self, t):
        return int(np.argmin(np.abs(np.asarray(self.times) - t)))


def stations(scene):
    """[(rotor node, radius)] of the scene's stations."""
    return [(s.get("node", 0), s["radius"]) for s in (scene or {}).get("station", [])]


def clearance(grid, rotor_point, radius):
    """Smallest undeformed distance from a station centre to a stator node, minus the radius."""
    part = np.asarray(grid.cell_data["part"])
    ids = set()
    for c in np.nonzero(part == rr.PART_STATOR)[0]:
        ids.update(grid.get_cell(int(c)).point_ids)
    if not ids:
        return None
    d = np.linalg.norm(grid.points[sorted(ids)][:, :2] - grid.points[rotor_point][:2], axis=1)
    gap = float(d.min()) - radius
    return gap if gap > 0 else None


def auto_scale(grid, scene, umax):
    """Gap drawn 0.25 (r+δ)/δ times too large, but no displacement drawn larger than 0.15 r
    (the drawn gap is the true gap times the scale only while scale·|u| ≪ r)."""
    st = stations(scene)
    nrot = rotor_nodes(grid)
    first = grid.n_points - nrot
    for node, r in st:
        g = clearance(grid, first + node, r)
        if g:
            s = 0.25 * (r + g) / g
            return max(min(s, 0.15 * r / umax), 1.0) if umax > 0 else s
    return 1.0


def rotor_nodes(grid):
    part = np.asarray(grid.cell_data["part"])
    c = np.nonzero(part == rr.PART_ROTOR)[0]
    return len(grid.get_cell(int(c[0])).point_ids) if len(c) else 0


def color_field(grid):
    if "stress" in grid.cell_data:
        s = np.asarray(grid.cell_data["stress"])
        part = np.asarray(grid.cell_data["part"])
        if np.isfinite(s[part == rr.PART_STATOR]).any():
            return "stress", "cell"
    return "|displacement| (m)", "point"


def stress_limits(frames, idx):
    """Colour range and map of the stator's `stress` over frames `idx`: signed stresses (bars'
    axial stress) get a range symmetric about zero on a diverging map, so tension and
    compression read apart; a field that is never negative (von Mises of meshed cells) gets
    0 … max on a sequential map, so its whole colour range carries information."""
    lo, hi = 0.0, 0.0
    for i in idx:
        g = frames[i]
        if "stress" in g.cell_data:
            s = np.asarray(g.cell_data["stress"])
            s = s[np.isfinite(s)]
            if len(s):
                lo, hi = min(lo, float(s.min())), max(hi, float(s.max()))
    if hi <= 0 and lo >= 0:
        return None
    if lo < 0:
        m = max(-lo, hi)
        return ((-m, m), "coolwarm")
    return ((0.0, hi), "viridis")


def draw(pl, grid, scene, scale, clim, fscale, t, title):
    """Adds one frame to plotter `pl` (actors named, so a new frame replaces the last)."""
    import pyvista as pv

    part = np.asarray(grid.cell_data["part"])
    disp = np.asarray(grid.point_data["displacement"]) if "displacement" in grid.point_data else np.zeros((grid.n_points, 3))
    warped = grid.copy()
    warped.points = grid.points + scale * disp
    stator = warped.extract_cells(np.nonzero(part == rr.PART_STATOR)[0])
    name, assoc = color_field(grid)
    if stator.n_cells:
        if assoc == "cell":
            lim, cmap = clim if clim else (None, "viridis")
            pl.add_mesh(stator, scalars="stress", clim=lim, cmap=cmap, line_width=3,
                        point_size=6, render_points_as_spheres=True, name="stator",
                        scalar_bar_args={"title": "stress (Pa)", "fmt": "%.2e"})
        else:
            stator.point_data[name] = np.linalg.norm(np.asarray(stator.point_data.get("displacement", np.zeros((stator.n_points, 3)))), axis=1)
            pl.add_mesh(stator, scalars=name, line_width=3, name="stator")
    nrot = rotor_nodes(grid)
    first = grid.n_points - nrot
    for k, (node, r) in enumerate(stations(scene)):
        c = warped.points[first + node]
        g = clearance(grid, first + node, r) or 0.0
        rv = max(r - (scale - 1.0) * g, 0.05 * r)
        a = np.linspace(0.0, 2.0 * np.pi, 181)
        circle = pv.lines_from_points(np.c_[c[0] + rv * np.cos(a), c[1] + rv * np.sin(a), np.full_like(a, c[2])])
        pl.add_mesh(circle, color="black", line_width=2, name=f"section{k}")
        pl.add_mesh(pv.PolyData(c[None, :]), color="black", point_size=8, render_points_as_spheres=True, name=f"centre{k}")
    if "contact_force" in grid.point_data:
        f = np.asarray(grid.point_data["contact_force"])
        idx = [i for i in range(first) if np.linalg.norm(f[i]) > 0.0]
        if idx:
            # Slightly towards the viewer (+z) so the arrows are drawn over the stator.
            pts = pv.PolyData(warped.points[idx] + [0.0, 0.0, 1e-3 * fscale * float(np.linalg.norm(f, axis=1).max())])
            pts["force"] = f[idx]
            arrows = pts.glyph(orient="force", scale="force", factor=fscale)
            pl.add_mesh(arrows, color="red", name="forces")
            # The resultant on the rotor section, from its centre.
            c = pv.PolyData(warped.points[[first]] + [0.0, 0.0, 1e-6])
            c["force"] = f[[first]]
            pl.add_mesh(c.glyph(orient="force", scale="force", factor=fscale), color="blue", name="resultant")
        else:
            pl.remove_actor("forces")
            pl.remove_actor("resultant")
    pl.add_text(f"{title}{spin_text(grid)}t = {t:.5f} s   displacements x{scale:.3g}", font_size=10, name="title")


def spin_text(grid):
    """The frame's own speed and spin angle (its field data `speed_ratio`, `phi`; a speed
    transient changes them frame by frame), or "" for frames written without them."""
    fd = grid.field_data
    if "speed_ratio" not in fd or "phi" not in fd:
        return ""
    w, phi = float(np.asarray(fd["speed_ratio"]).ravel()[0]), float(np.asarray(fd["phi"]).ravel()[0])
    return f"w/wn = {w:.3f}   phi = {phi / (2 * np.pi):.2f} rev   "


def frame_indices(frames, args):
    if args.frame is not None:
        return [args.frame % len(frames)]
    if args.time is not None:
        return [frames.index_of_time(args.time)]
    return list(range(0, len(frames), max(args.every, 1)))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("results", help="results.pvd or results.vtkhdf")
    ap.add_argument("--png", help="write one frame as PNG")
    ap.add_argument("--movie", help="write an .mp4 or .gif of the frames")
    ap.add_argument("--frame", type=int, help="frame index for --png (default: the last)")
    ap.add_argument("--time", type=float, help="time (s) for --png: the nearest frame")
    ap.add_argument("--every", type=int, default=1, help="movie: use every n-th frame")
    ap.add_argument("--fps", type=int, default=24, help="movie frame rate")
    ap.add_argument("--scale", type=float, help="displacement magnification (default: automatic)")
    ap.add_argument("--size", type=int, nargs=2, default=[1024, 768], help="picture size in pixels")
    args = ap.parse_args(argv)
    if not args.png and not args.movie:
        ap.error("give --png or --movie")
    import pyvista as pv

    frames = Frames(args.results)
    scene = rr.find_scene(args.results)
    if args.png and args.frame is None and args.time is None:
        args.frame = len(frames) - 1
    idx = frame_indices(frames, args) if args.png else list(range(0, len(frames), max(args.every, 1)))
    g0 = frames[idx[0]]
    every_frame = list(range(len(frames)))
    umax = 0.0
    for i in (idx if args.png else every_frame[:: len(every_frame) // 200 + 1]):
        g = frames[i]
        if "displacement" in g.point_data:
            umax = max(umax, float(np.linalg.norm(np.asarray(g.point_data["displacement"]), axis=1).max()))
    scale = args.scale or auto_scale(g0, scene, umax)
    clim = stress_limits(frames, every_frame[:: len(every_frame) // 200 + 1])
    # Arrow scale: the largest resultant on the rotor is drawn 0.6 section radii long.
    fmax = 0.0
    first = g0.n_points - rotor_nodes(g0)
    for i in every_frame[:: len(every_frame) // 200 + 1]:
        g = frames[i]
        if "contact_force" in g.point_data:
            fmax = max(fmax, float(np.linalg.norm(np.asarray(g.point_data["contact_force"])[first:], axis=1).max()))
    radius = min((r for _, r in stations(scene)), default=float(np.ptp(g0.points[:, :2], axis=0).max()) or 1.0)
    fscale = 0.6 * radius / fmax if fmax > 0 else 1.0
    # A speed transient: each frame's title carries its own speed (`spin_text`).
    title = "" if "speed_ratio" in g0.field_data else (
        f"speed w/wn = {scene_speed(args.results)}   " if scene_speed(args.results) else "")
    pl = pv.Plotter(off_screen=True, window_size=args.size)
    pl.set_background("white")
    out = []
    if args.movie:
        if args.movie.endswith(".gif"):
            pl.open_gif(args.movie, fps=args.fps)
        else:
            pl.open_movie(args.movie, framerate=args.fps)
    for n, i in enumerate(idx):
        draw(pl, frames[i], scene, scale, clim, fscale, frames.times[i], title)
        if n == 0:
            pl.view_xy()
            pl.reset_camera()
            pl.camera.zoom(0.95)
        if args.movie:
            pl.write_frame()
    if args.png:
        pl.screenshot(args.png)
        out.append(args.png)
    if args.movie:
        out.append(args.movie)
    pl.close()
    for o in out:
        print(o)
    return out


def scene_speed(path):
    """ω/ω_n of a run from its HDF5 attributes, when there is a results.vtkhdf."""
    h = path if path.endswith(".vtkhdf") else os.path.join(os.path.dirname(os.path.abspath(path)), "results.vtkhdf")
    if not os.path.exists(h):
        return None
    import h5py

    with h5py.File(h, "r") as f:
        return f"{float(f.attrs['speed_ratio']):.3g}"


if __name__ == "__main__":
    main()
