"""Readers for rubsim's time series (docs/OUTPUTS.md): the HDF5 file `results.vtkhdf` and the
VTK collection `results.pvd`. Used by post/animate.py, post/orbit_cascade.py and the tests.

Only reads files; needs numpy and h5py (pyvista for the grids).
"""
import json
import math
import os

import numpy as np

#: `part` cell data values.
PART_STATOR, PART_ROTOR, PART_CONTACT = 0, 1, 2

#: Columns of `/rotor/node_dofs`: the DOFs of a rotor node (m, rad). θ_x, θ_y right-handed about
#: x, y (θ_y = ∂u_x/∂z, θ_x = −∂u_y/∂z); θ_z, the twist, counter-clockwise seen from +z (the
#: sense of the spin). −1 where the rotor has no such DOF.
ROTOR_DOFS = ("u_x", "u_y", "theta_x", "theta_y", "u_z", "theta_z")


class Series:
    """The plain datasets of one `results.vtkhdf` (SI units).

    Attributes: `t` (s), `step`, `u` (rotor DOFs, frames × ndof, m and rad), `v` (m/s and
    rad/s, or None), `p` (pair normal forces, frames × pairs, N, or None), `pairs` (station,
    stator, node), `station_force` (frames × stations × 2, N, on the rotor, or None), `scene`
    (dict), `attrs` (root attributes), `node_dofs` (rotor nodes × 6: the column of `u` of each
    node's [u_x, u_y, θ_x, θ_y, u_z, θ_z], −1 where absent, see `ROTOR_DOFS`; files written
    before the map had 6 columns are padded with −1).
    """

    def __init__(self, path):
        import h5py

        self.path = path
        with h5py.File(path, "r") as f:
            self.attrs = {k: _plain(v) for k, v in f.attrs.items()}
            self.scene = json.loads(self.attrs["scene"])
            self.units = json.loads(self.attrs["units"])
            self.t = f["time"][:]
            self.step = f["step"][:]
            nd = np.asarray(f["rotor/node_dofs"][:], dtype=np.int64)
            if nd.shape[1] < len(ROTOR_DOFS):
                nd = np.c_[nd, np.full((len(nd), len(ROTOR_DOFS) - nd.shape[1]), -1)]
            self.node_dofs = nd
            self.u = f["rotor/u"][:] if "u" in f["rotor"] else None
            self.v = f["rotor/v"][:] if "v" in f["rotor"] else None
            c = f["contact"]
            self.pairs = c["pairs"][:]
            self.p = c["p"][:] if "p" in c else None
            self.pair_force = c["force"][:] if "force" in c else None
            self.station_force = c["station_force"][:] if "station_force" in c else None
            self.num_points = int(f["VTKHDF/NumberOfPoints"][0])

    @property
    def omega(self):
        """Speed ω (rad/s)."""
        return float(self.attrs["omega_rad_s"])

    @property
    def speed_ratio(self):
        """ω/ω_n."""
        return float(self.attrs["speed_ratio"])

    @property
    def omega_n(self):
        """ω_n (rad/s) that speed ratios refer to."""
        return self.omega / self.speed_ratio

    @property
    def num_nodes(self):
        """Number of rotor nodes."""
        return len(self.node_dofs)

    def station_node(self, station=0):
        """Rotor node carrying a station (node 0 without stations)."""
        st = self.scene.get("station", [])
        return int(st[station].get("node", 0)) if st else 0

    def dof(self, node, name):
        """Column of `u` of DOF `name` (one of `ROTOR_DOFS`) of a rotor node, None if absent."""
        if not 0 <= node < self.num_nodes:
            raise IndexError(f"{self.path}: rotor node {node} out of range (0…{self.num_nodes - 1})")
        d = int(self.node_dofs[node, ROTOR_DOFS.index(name)])
        return None if d < 0 else d

    def node_disp(self, node):
        """Displacement [x, y] of a rotor node per frame (m)."""
        return self.u[:, [self.dof(node, "u_x"), self.dof(node, "u_y")]]

    def twist(self, node):
        """Twist θ_z of a rotor node per frame (rad, counter-clockwise seen from +z), or None
        when the rotor has no torsional DOFs."""
        d = self.dof(node, "theta_z")
        return None if d is None else self.u[:, d]

    def observed_node(self):
        """The rotor node the run's analysis observed (`output.node`, default the first station's
        node): the node of summary.json's orbits, spectra and amplitudes."""
        node = self.scene.get("output", {}).get("node")
        return self.station_node(0) if node is None else int(node)

    def station_disp(self, station=0):
        """Displacement [x, y] of a station's rotor node per frame (m)."""
        return self.node_disp(self.station_node(station))

    def frames_per_rev(self):
        """Frames per revolution when frames are evenly spaced and whole per revolution."""
        spr = int(self.attrs["steps_per_rev"])
        every = int(self.attrs["every"])
        if spr % every:
            raise ValueError(f"{self.path}: {every} steps between frames do not divide a revolution ({spr} steps)")
        return spr // every

    def steady(self):
        """Frame range [first, last) of the analysis window as planned: after
        `run.transient_revolutions`, up to `run.revolutions` (a window shorter than 6 revolutions
        lengthened to 6) — the summary's when the run kept that transient (its
        `transient_revolutions`; a run that went on to reach its steady state analysed later)."""
        spr = int(self.attrs["steps_per_rev"])
        run = self.scene["run"]
        t0, revs = run["transient_revolutions"], run["revolutions"]
        if revs > t0:
            revs = t0 + max(revs - t0, 6)
        s0, s1 = t0 * spr, revs * spr
        idx = np.nonzero((self.step >= s0) & (self.step < s1))[0]
        return int(idx[0]), int(idx[-1]) + 1


def _plain(v):
    if isinstance(v, bytes):
        return v.decode()
    if isinstance(v, np.generic):
        return v.item()
    return v


def hann_spectrum(x):
    """One-sided amplitude spectrum with a Hann window, mean removed (as rubsim's
    `signal::hann_spectrum`): a sine of amplitude A on bin k reads A at bin k."""
    x = np.asarray(x, dtype=float)
    n = len(x)
    w = 0.5 * (1.0 - np.cos(2.0 * math.pi * np.arange(n) / n))
    return 2.0 * np.abs(np.fft.rfft((x - x.mean()) * w)) / (n / 2.0)


def line_exact(x, per_rev, order):
    """Amplitude of the line of `order` cycles per revolution in `x` (`per_rev` samples per
    revolution): the rectangular-window DFT at the line's exact frequency, mean removed (as
    rubsim's `signal::line_exact`; exact for a periodic record spanning whole periods)."""
    x = np.asarray(x, dtype=float)
    n = len(x)
    if n == 0:
        return 0.0
    k = round(order * 6)
    m = (k * (np.arange(n) % (6 * per_rev))) % (6 * per_rev)
    e = np.exp(-2j * math.pi * m / (6 * per_rev))
    return float(2.0 * abs(np.sum((x - x.mean()) * e)) / n)


def lines_revolutions(nrev, period=1):
    """Revolutions the lines are read over (as rubsim's `analysis::steady::lines_revolutions`):
    the largest multiple of lcm(6, period) within `nrev`, else of 6, else `nrev`."""
    l = 6 * max(period, 1) // math.gcd(6, max(period, 1))
    if nrev >= l:
        return nrev // l * l
    return nrev // 6 * 6 if nrev >= 6 else nrev


def spectrum(series, component=None, station=0, node=None):
    """(f/ω_n, amplitude in m) of a displacement component (`output.component`, "x" or "y") of
    a rotor node (default: the node of station `station`) over the steady window."""
    comp = component or series.scene.get("output", {}).get("component", "y")
    a, b = series.steady()
    node = series.station_node(station) if node is None else node
    x = series.node_disp(node)[a:b, 0 if comp == "x" else 1]
    spec = hann_spectrum(x)
    nrev = (b - a) / series.frames_per_rev()
    f = np.arange(len(spec)) / nrev * series.speed_ratio
    return f, spec, nrev


def pvd_frames(path):
    """[(time, absolute path of the .vtu)] of a .pvd collection."""
    import xml.etree.ElementTree as ET

    root = ET.parse(path).getroot()
    base = os.path.dirname(os.path.abspath(path))
    return [(float(d.get("timestep")), os.path.join(base, d.get("file"))) for d in root.iter("DataSet")]


def find_scene(results_path):
    """The resolved scene of a run: from the HDF5 file's `scene` attribute, or the summary.json
    beside a .pvd (a sweep's per-speed folder: the summary.json one level up)."""
    d = os.path.dirname(os.path.abspath(results_path))
    h = os.path.join(d, "results.vtkhdf")
    if results_path.endswith(".vtkhdf") or os.path.exists(h):
        import h5py

        with h5py.File(results_path if results_path.endswith(".vtkhdf") else h, "r") as f:
            return json.loads(_plain(f.attrs["scene"]))
    for s in (os.path.join(d, "summary.json"), os.path.join(os.path.dirname(d), "summary.json")):
        if os.path.exists(s):
            with open(s) as f:
                return json.load(f)["scene"]
    return None
