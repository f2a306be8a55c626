#!/usr/bin/env python3
"""A run-up with rub, driven from Python: the seed paper's Jeffcott rotor run up through its
critical speed against the elastic rod above it (scenes/transients/paper_runup.toml), its
response, contact force and friction energy against speed plotted with matplotlib, and the rotor
section rubbing the rod animated with pyvista (post/animate.py's frames) into a GIF.

    .venv/bin/pip install ./python           # once: the rubsim package from this checkout
    .venv/bin/python python/examples/runup.py [--out out/py_runup] [--quick]

Writes <out>/run/ (everything `rubsim run` writes for the scene: summary.json, CSV, PNG and the
VTK series), <out>/runup.png and <out>/runup.gif. --quick runs 0.5 → 2.5 ω_n in 3 s instead of
the scene's 0.5 → 6 ω_n in 30 s (the tests run it so).
"""
import argparse
import pathlib
import sys

import numpy as np

import rubsim

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENE = ROOT / "scenes" / "transients" / "paper_runup.toml"


def progress(done, total, _shown=[-1]):
    """The run's progress on stderr, every tenth of its steps."""
    tenth = 10 * done // total
    if tenth != _shown[0]:
        _shown[0] = tenth
        print(f"  {10 * tenth:3d} % of {total} steps", file=sys.stderr)


def plot(t, path):
    """Response radius (µm), contact force (N) and friction energy (J) against Ω/ω_n."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    nu = t.speed / t.omega_n
    radius = np.hypot(t.response[:, 0], t.response[:, 1])
    fig, ax = plt.subplots(3, 1, sharex=True, figsize=(7, 7))
    ax[0].plot(nu, radius * 1e6, lw=0.6)
    ax[0].set_ylabel("radius (µm)")
    ax[1].plot(nu, t.contact_force, lw=0.6, color="tab:red")
    ax[1].set_ylabel("contact force (N)")
    ax[2].plot(nu, t.friction_energy, color="tab:green")
    ax[2].set_ylabel("friction energy (J)")
    ax[2].set_xlabel("Ω/ωn")
    fig.suptitle("Paper case run-up with rub (rubsim from Python)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def animate(t, path, frames):
    """The series' frames as a GIF: post/animate.py draws each with pyvista, off screen."""
    sys.path.insert(0, str(ROOT / "post"))
    import animate as movie  # post/animate.py

    reader = t.series("vtk")
    every = max(1, len(reader.time_values) // frames)
    movie.main([str(t.dir / "results.pvd"), "--movie", str(path), "--every", str(every),
                "--fps", "12", "--size", "480", "360"])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="out/py_runup", help="output folder")
    ap.add_argument("--quick", action="store_true", help="0.5 → 2.5 ωn in 3 s")
    ap.add_argument("--frames", type=int, default=60, help="frames of the GIF")
    args = ap.parse_args(argv)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    duration = 3.0 if args.quick else 30.0
    sets = {"output.vtk": {"fields": ["displacement", "contact_force"], "every": 200}}
    if args.quick:
        sets.update({"run.speed_profile.duration": duration, "run.speed_profile.to": 2.5})
    scene = rubsim.Scene(SCENE, set=sets)
    print(f"{scene.title}\n  ωn = {scene.natural_frequency:.2f} rad/s", file=sys.stderr)
    t = scene.transient(out=out / "run", force=True, progress=progress)
    s = t.summary
    peak, at = s["peak_1x"]
    print(f"{len(t.t)} samples over {s['duration']} s, {s['revolutions']:.0f} revolutions; "
          f"peak 1× {peak * 1e6:.1f} µm at Ω/ωn = {at / t.omega_n:.3f}; "
          f"largest contact force {s['contact_force_max']:.1f} N; "
          f"friction energy {s['friction_energy']:.4g} J")
    plot(t, out / "runup.png")
    animate(t, out / "runup.gif", args.frames)
    print(f"figures in {out}/runup.png and {out}/runup.gif; rubsim's own outputs in {t.dir}")


if __name__ == "__main__":
    main()
