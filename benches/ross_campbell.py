"""Time `rubsim campbell` beside ROSS's `Rotor.run_campbell` on the same 100-element rotor.

The rotor is ROSS's `rotor_example` refined to 100 Timoshenko elements (shear, rotary
inertia and gyroscopic effects on; 6 DOFs per node as in ROSS 2), disks at nodes 33 and 67,
bearings kxx = 1 MN/m, kyy = 0.8 MN/m at the ends — the rotor of
`scenes/fe/ross_rotor_100.toml`. Both programs compute the Campbell diagram over the same 200
speeds from 0 to 1000 rad/s with 12 modes; every run is a whole `rubsim` process (scene read,
model built, CSV, PNG and summary written) and a whole `run_campbell` call (the ROSS rotor is
built once, outside the timing). The runs alternate, rubsim then ROSS, `--repeat` times; the
script prints every time (wall and the process's CPU time: user + system, of the rubsim child
and of this process for ROSS), the medians and the load average, then checks that the two programs
computed the same rotor: ω_d of the lowest modes at 0, 500 and 1000 rad/s side by side.

    python benches/ross_campbell.py --rubsim target/release/rubsim --repeat 5

Needs `ross-rotordynamics` (2.3.0 on Python 3.11 was measured, docs/PERFORMANCE.md).
"""

import argparse
import csv
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import ross as rs

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "scenes", "fe", "ross_rotor_100.toml")


def ross_rotor(elements=100):
    """The rotor of `scenes/fe/ross_rotor_100.toml`, built with ROSS."""
    steel = rs.materials.steel
    shaft = [
        rs.ShaftElement(
            1.5 / elements,
            0.0,
            0.05,
            material=steel,
            shear_effects=True,
            rotary_inertia=True,
            gyroscopic=True,
        )
        for _ in range(elements)
    ]
    disk = dict(m=32.58972765304033, Id=0.17808928257067666, Ip=0.32956362089137037)
    disks = [rs.DiskElement(n=33, **disk), rs.DiskElement(n=67, **disk)]
    bearings = [
        rs.BearingElement(0, kxx=1e6, kyy=0.8e6, cxx=0),
        rs.BearingElement(elements, kxx=1e6, kyy=0.8e6, cxx=0),
    ]
    return rs.Rotor(shaft, disks, bearings)


def time_rubsim(binary, out, points, modes):
    cmd = [
        binary, "campbell", SCENE, "--from", "0", "--to", "1000", "--unit", "rad/s",
        "--points", str(points), "--modes", str(modes), "--out", out,
    ]
    c0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (c1.ru_utime - c0.ru_utime) + (c1.ru_stime - c0.ru_stime)


def time_ross(rotor, points, modes):
    speeds = np.linspace(0.0, 1000.0, points)
    c0 = time.process_time()
    t0 = time.perf_counter()
    camp = rotor.run_campbell(speeds, frequencies=modes)
    return time.perf_counter() - t0, time.process_time() - c0, camp


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rubsim", default=os.path.join(HERE, "..", "target", "release", "rubsim"))
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--ross-repeat", type=int, default=None,
                    help="runs of ROSS (default --repeat); ROSS takes minutes per run")
    ap.add_argument("--points", type=int, default=200)
    ap.add_argument("--modes", type=int, default=12)
    a = ap.parse_args()
    rotor = ross_rotor()
    print(f"ross {rs.__version__}, python {sys.version.split()[0]}, rotor: "
          f"{len(rotor.shaft_elements)} elements, {rotor.ndof} DOFs", flush=True)
    out = tempfile.mkdtemp(prefix="rubsim_campbell_")
    t_rub, t_ross, c_rub, c_ross = [], [], [], []
    camp = None
    ross_repeat = a.repeat if a.ross_repeat is None else a.ross_repeat
    for i in range(max(a.repeat, ross_repeat)):
        if i < a.repeat:
            w, c = time_rubsim(a.rubsim, out, a.points, a.modes)
            t_rub.append(w)
            c_rub.append(c)
            print(f"run {i + 1}: rubsim {w:.3f} s wall {c:.3f} s CPU, "
                  f"load average {os.getloadavg()[0]:.2f}", flush=True)
        if i < ross_repeat:
            w, c, camp = time_ross(rotor, a.points, a.modes)
            t_ross.append(w)
            c_ross.append(c)
            print(f"run {i + 1}: ROSS {w:.3f} s wall {c:.3f} s CPU, "
                  f"load average {os.getloadavg()[0]:.2f}", flush=True)
    med = statistics.median
    print(f"median wall: rubsim {med(t_rub):.3f} s, ROSS {med(t_ross):.3f} s, "
          f"ROSS/rubsim {med(t_ross) / med(t_rub):.1f}")
    print(f"median CPU:  rubsim {med(c_rub):.3f} s, ROSS {med(c_ross):.3f} s, "
          f"ROSS/rubsim {med(c_ross) / med(c_rub):.1f}")
    # Same rotor: the lowest ω_d at three speeds (rubsim's tracks sorted at each speed).
    with open(os.path.join(out, "campbell.csv")) as f:
        rows = list(csv.reader(f))
    head, body = rows[0], rows[1:]
    cols = [j for j, h in enumerate(head) if h.endswith("_omega_d")]
    wd_ross = np.asarray(camp.wd)
    for i in (0, a.points // 2, a.points - 1):
        ours = sorted(float(body[i][j]) for j in cols)[:6]
        theirs = sorted(wd_ross[i])[:6]
        print(f"Ω = {float(body[i][0]):7.2f} rad/s  rubsim " + " ".join(f"{w:9.3f}" for w in ours))
        print("                    ROSS   " + " ".join(f"{w:9.3f}" for w in theirs))


if __name__ == "__main__":
    main()
