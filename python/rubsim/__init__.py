"""rubsim from Python: rotor-to-stator rubbing vibration with finite elements.

A :class:`Scene` is what the ``rubsim`` command line reads: a TOML scene file (or its text, or
a dict of its tables) with overrides (``--set key=value``), validated with file, key and line.
Its calls run the rubsim library in this process, with the GIL released while it computes:

- :meth:`Scene.run` — one speed: orbit, Poincaré points, spectra, contact force, summary;
- :meth:`Scene.transient` — the speed transient of ``[run.speed_profile]`` (run-up, coast-down,
  driven rotor);
- :meth:`Scene.sweep` and :meth:`Scene.map` — the studies of ``[run.sweep]`` and ``[run.map]``,
  their tables as dicts of numpy arrays;
- :meth:`Scene.modal` — the damped modes of the rotor alone;
- :meth:`Scene.thermal` — the thermal spiral (Newkirk effect) of ``[thermal]``;
- :meth:`Scene.periodic` and :meth:`Scene.continuation` — periodic orbits by shooting, their
  Floquet multipliers, and their branches over speed with the bifurcations located;
- :func:`from_ross` / :func:`import_ross` — a ROSS rotor (2.x or 3.x) as a rubsim scene.

Given ``out=``, a call writes exactly what the command line writes into that directory
(``summary.json``, CSV, PNG, the VTK/HDF5 series, a study's case store so that a later call
resumes it); :meth:`Run.series` opens the series with pyvista. Without ``out`` nothing is kept
on disk. ``progress=`` takes ``callback(done, total)`` (steps of a run, cases of a study).

Units are SI; speeds are ν = ω/ω_n unless a ``unit`` says otherwise; the ``_nd`` values are
non-dimensional as in rubsim's outputs (displacement over |Z0(ω)|, force over |U|ω²,
frequency over ω_n). Errors are :class:`RubsimError` subclasses; a :class:`SceneError` carries
``file``, ``key`` and ``line``.
"""

from __future__ import annotations

import json
import os
import pathlib
import warnings
from collections.abc import Mapping, Sequence
from typing import Any, Callable, Optional, Union

import numpy as np

from . import _rubsim
from ._rubsim import (
    MeshError,
    ModelError,
    OutputError,
    RubsimError,
    SceneError,
    SolveError,
    StudyError,
)

__version__ = _rubsim.__version__
__all__ = [
    "Scene",
    "Run",
    "Transient",
    "Sweep",
    "Map",
    "Modal",
    "Periodic",
    "Autonomous",
    "AutonomousBranch",
    "Branch",
    "Diagram",
    "Thermal",
    "ThermalMap",
    "from_ross",
    "import_ross",
    "RubsimError",
    "SceneError",
    "ModelError",
    "MeshError",
    "SolveError",
    "StudyError",
    "OutputError",
]

PathLike = Union[str, os.PathLike]
Progress = Optional[Callable[[int, int], Any]]

# Speed units of `Scene.run(unit=...)` and `Scene.modal(unit=...)`, as the command line's --unit.
_UNITS = ("ratio", "rad/s", "rpm")


def _override_list(overrides: Union[None, Mapping, Sequence[str]], keys: Mapping) -> list:
    """`key=value` strings of a mapping (values as TOML), a list of such strings, and keyword
    arguments whose `__` stands for the dot (`run__revolutions=40`)."""
    out = []
    if overrides is None:
        pass
    elif isinstance(overrides, Mapping):
        out += [_rubsim.NativeScene.override_text(str(k), v) for k, v in overrides.items()]
    elif isinstance(overrides, str):
        out.append(overrides)
    else:
        for o in overrides:
            if not isinstance(o, str):
                raise TypeError(f"an override is a 'key=value' string, got {type(o).__name__}")
            out.append(o)
    out += [_rubsim.NativeScene.override_text(k.replace("__", "."), v) for k, v in keys.items()]
    return out


def _path(p: Optional[PathLike]) -> Optional[str]:
    return None if p is None else os.fspath(p)


def _warn(messages: Sequence[str], stacklevel: int = 3) -> None:
    """The warnings of a call as RuntimeWarnings at the user's line (``stacklevel``)."""
    for m in messages:
        warnings.warn(m, RuntimeWarning, stacklevel=stacklevel)


class Scene:
    """A validated rubsim scene and, once built, its model.

    ``Scene("scenes/paper/partial_rub.toml")`` reads a file; ``Scene({...})`` takes a dict of
    the scene's tables (``base`` is the folder its relative paths are taken from, default the
    current one); ``set`` overrides keys (a dict ``{"stator.0.mu": 0.2}`` or ``"key=value"``
    strings, as ``--set``).
    """

    def __init__(
        self,
        source: Union[PathLike, Mapping],
        set: Union[None, Mapping, Sequence[str]] = None,
        *,
        base: Optional[PathLike] = None,
    ):
        overrides = _override_list(set, {})
        if isinstance(source, Scene):
            self._native = source._native.with_overrides(overrides)
        elif isinstance(source, Mapping):
            where = pathlib.Path(base or ".").resolve() / "<dict>"
            self._native = _rubsim.NativeScene.from_dict(dict(source), str(where), overrides)
        elif isinstance(source, (str, os.PathLike)):
            self._native = _rubsim.NativeScene.load(os.fspath(source), overrides)
        else:
            raise TypeError(
                f"a scene is a path to a TOML file or a dict of its tables, got {type(source).__name__}"
            )

    @classmethod
    def _wrap(cls, native) -> "Scene":
        s = cls.__new__(cls)
        s._native = native
        return s

    @classmethod
    def from_toml(
        cls, text: str, *, base: Optional[PathLike] = None, set=None
    ) -> "Scene":
        """A scene from TOML text (``base``: the folder of its relative paths)."""
        where = pathlib.Path(base or ".").resolve() / "<text>"
        return cls._wrap(_rubsim.NativeScene.parse(text, str(where), _override_list(set, {})))

    def set(self, overrides=None, /, **keys) -> "Scene":
        """This scene with more overrides: ``scene.set({"stator.0.mu": 0.2})`` or
        ``scene.set(run__revolutions=40)`` (``__`` for the dot)."""
        return Scene._wrap(self._native.with_overrides(_override_list(overrides, keys)))

    @property
    def title(self) -> str:
        return self._native.title

    @property
    def file(self) -> pathlib.Path:
        return pathlib.Path(self._native.file)

    @property
    def overrides(self) -> list:
        return list(self._native.overrides)

    @property
    def source(self) -> str:
        """The scene's TOML text as given (before the overrides)."""
        return self._native.source

    @property
    def natural_frequency(self) -> float:
        """ω_n (rad/s): the rotor's first lateral natural frequency at rest, the unit of ν."""
        return self._native.natural_frequency()

    def to_dict(self) -> dict:
        """The validated scene with every default filled in."""
        return json.loads(self._native.to_json())

    def check(self) -> "Scene":
        """Builds the model (meshing the stators' geometries); raises what stops it."""
        self._native.check()
        return self

    def describe(self) -> str:
        """One line on the rotor model."""
        return self._native.describe()

    def _ratio(self, speed: Optional[float], unit: str) -> Optional[float]:
        if speed is None:
            return None
        if unit not in _UNITS:
            raise ValueError(f"unit must be one of {_UNITS}, got {unit!r}")
        v = float(speed)
        if unit == "rad/s":
            return v / self.natural_frequency
        if unit == "rpm":
            return v * 2.0 * np.pi / 60.0 / self.natural_frequency
        return v

    def run(
        self,
        speed: Optional[float] = None,
        *,
        unit: str = "ratio",
        out: Optional[PathLike] = None,
        force: bool = False,
        progress: Progress = None,
    ) -> "Run":
        """The steady run at ``speed`` (default: the scene's ``run.speed_ratio`` or
        ``run.speed``), with the step ``rubsim run`` chooses from ``run.tolerance``."""
        d = self._native.run(self._ratio(speed, unit), _path(out), force, progress)
        _warn(d["warnings"])
        return Run(d)

    def transient(
        self, *, out: Optional[PathLike] = None, force: bool = False, progress: Progress = None
    ) -> "Transient":
        """The speed transient of ``[run.speed_profile]`` (and its ``[[run.event]]``s)."""
        d = self._native.transient(_path(out), force, progress)
        _warn(d["warnings"])
        return Transient(d)

    def thermal(
        self,
        speed: Optional[float] = None,
        *,
        unit: str = "ratio",
        out: Optional[PathLike] = None,
        force: bool = False,
    ) -> "Thermal":
        """The thermal spiral (Newkirk effect) of ``[thermal]`` at ``speed`` (default: the
        scene's), as ``rubsim run`` runs a scene with ``[thermal]``."""
        return Thermal(self._native.thermal(self._ratio(speed, unit), _path(out), force))

    def sweep(
        self,
        *,
        out: Optional[PathLike] = None,
        force: bool = False,
        fresh: bool = False,
        jobs: Optional[int] = None,
        progress: Progress = None,
    ) -> "Sweep":
        """The speed sweep of ``[run.sweep]`` (once per variant of ``[run.sweep.vary]``), its
        speeds in parallel on ``jobs`` threads (default: all cores). With ``out`` the finished
        cases are kept and a later call resumes them (``fresh``: discard another scene's)."""
        return Sweep(self._study("sweep", out, force, fresh, jobs, progress))

    def map(self, **options) -> Union["Map", "ThermalMap"]:
        """The 2-D map of ``[run.map]`` (speed × a scene key, or two scene keys); the options of
        :meth:`sweep`. A scene with ``[thermal]`` gives the thermal spiral's stability map
        (:class:`ThermalMap`, as ``rubsim map``; its cells run whole: ``fresh`` does not apply)."""
        d = self._study("map", **options)
        return ThermalMap(d) if d.get("thermal_map") else Map(d)

    def _study(self, kind, out=None, force=False, fresh=False, jobs=None, progress=None) -> dict:
        d = self._native.study(kind, _path(out), force, fresh, jobs, progress)
        _warn(d.get("warnings", []), stacklevel=4)
        return d

    def modal(self, speed: float = 0.0, *, unit: str = "rad/s", modes: int = 12) -> "Modal":
        """The ``modes`` lowest damped modes of the rotor alone at ``speed`` (default rad/s, as
        ``rubsim modal``)."""
        if unit not in _UNITS:
            raise ValueError(f"unit must be one of {_UNITS}, got {unit!r}")
        omega = float(speed)
        if unit == "ratio":
            omega *= self.natural_frequency
        elif unit == "rpm":
            omega *= 2.0 * np.pi / 60.0
        return Modal(json.loads(self._native.modal(omega, int(modes))))

    def periodic(
        self,
        speed: Optional[float] = None,
        *,
        unit: str = "ratio",
        period: Optional[int] = None,
        refine: bool = False,
        autonomous: bool = False,
    ) -> Union["Periodic", "Autonomous"]:
        """The periodic orbit of ``period`` revolutions (default: the settled run's) at
        ``speed`` (default: the scene's) by shooting, as ``rubsim periodic``: its Floquet
        multipliers and stability. With ``refine`` (``rubsim periodic --refine``) the orbit is
        shot again at half the step: ``refined`` holds the multipliers there, their error
        estimates and, for an orbit without contact, their extrapolation to Δt → 0. With
        ``autonomous`` (``rubsim periodic --autonomous``): an :class:`Autonomous` — a whirl at
        its own frequency (dry whip) in a scene without unbalance, its period unknown."""
        if autonomous:
            if period is not None or refine:
                raise ValueError("autonomous= finds the period itself: leave out period= and refine=")
            d = self._native.periodic_autonomous(self._ratio(speed, unit))
            return Autonomous(json.loads(d))
        d = self._native.periodic(self._ratio(speed, unit), period, bool(refine))
        return Periodic(json.loads(d))

    def continuation(
        self,
        from_: Optional[float] = None,
        to: Optional[float] = None,
        step: Optional[float] = None,
        *,
        unit: str = "ratio",
        period: Optional[int] = None,
        arclength: bool = False,
        max_points: int = 200,
        switch: bool = False,
        max_period: int = 8,
        key: Optional[str] = None,
        speed: Optional[float] = None,
        autonomous: bool = False,
    ) -> Union["Branch", "Diagram", "AutonomousBranch"]:
        """The periodic orbit continued over speed from ``from_`` to ``to`` by ``step``
        (default: the scene's ``[run.sweep]``), as ``rubsim continue``: in ν alone, or by
        pseudo-arclength around folds (``arclength``, at most ``max_points`` points). With
        ``switch``: a :class:`Diagram` — the branch and those switched onto at its period
        doublings and theirs, up to period ``max_period`` (``rubsim continue --switch``).
        With ``key`` (a dotted scene key, ``"station.0.friction"``): continued over that key
        from ``from_`` to ``to`` by ``step`` in the key's own units at the fixed ``speed`` (in
        ``unit``; default the scene's), as ``rubsim continue --key``. With ``autonomous``: an
        :class:`AutonomousBranch` — the whirl at its own frequency continued in speed or in
        ``key`` (``rubsim continue --autonomous``)."""
        if autonomous:
            if period is not None or arclength or switch:
                raise ValueError(
                    "autonomous= continues in the parameter alone with the period unknown: leave out period=, arclength= and switch="
                )
            if key is None and speed is not None:
                raise ValueError("speed= is the fixed speed of a branch in a key: give key= too")
            if key is not None:
                r = [None if v is None else float(v) for v in (from_, to, step)]
                nu = self._ratio(speed, unit)
                d = self._native.continuation_autonomous(str(key), nu, *r)
            else:
                r = [self._ratio(v, unit) for v in (from_, to, step)]
                d = self._native.continuation_autonomous(None, None, *r)
            return AutonomousBranch(json.loads(d))
        n = int(max_points) if arclength else None
        m = int(max_period) if switch else None
        if key is not None:
            r = [None if v is None else float(v) for v in (from_, to, step)]
            nu = self._ratio(speed, unit)
            d = json.loads(self._native.continuation_key(str(key), nu, *r, period, n, m))
            return Diagram(d) if switch else Branch(d["branches"][0])
        if speed is not None:
            raise ValueError("speed= is the fixed speed of a branch in a key: give key= too")
        r = [self._ratio(v, unit) for v in (from_, to, step)]
        d = json.loads(self._native.continuation(*r, period, n, m))
        return Diagram(d) if switch else Branch(d)

    def __repr__(self) -> str:
        extra = f", set={self.overrides!r}" if self.overrides else ""
        return f"rubsim.Scene({str(self.file)!r}{extra})"


def _series_reader(folder: Optional[pathlib.Path], format: str):
    """The pyvista reader of the VTK (``results.pvd``) or HDF5 (``results.vtkhdf``) series in
    ``folder``."""
    if folder is None:
        raise RubsimError("no series on disk: run with out=<directory> to keep them")
    names = {"vtk": "results.pvd", "hdf5": "results.vtkhdf"}
    if format not in names:
        raise ValueError(f"format must be 'vtk' or 'hdf5', got {format!r}")
    path = folder / names[format]
    if not path.is_file():
        raise RubsimError(
            f"{path}: not written (the scene's [output.{format}] table asks for the series)"
        )
    import pyvista

    return pyvista.get_reader(str(path))


class Run:
    """One speed's results. ``summary``: summary.json's body (``result``: every number rubsim
    reports, ``regime``, ``dynamics``…). Arrays, non-dimensional as named: ``orbit`` (n × 2,
    x/|Z0|, y/|Z0| over the analysed window), ``poincare`` (once a revolution), ``spectrum``
    (f/ω_n, amplitude/|Z0|), ``full_spectrum`` (signed f/ω_n of x + iy: backward whirl < 0),
    ``force_history`` (revolutions, vertical force on the stator / |U|ω²)."""

    def __init__(self, d: dict):
        self.summary = json.loads(d["summary"])
        self.result = self.summary["result"]
        self.orbit = d["orbit"]
        self.poincare = d["poincare"]
        self.spectrum = d["spectrum"]
        self.full_spectrum = d["full_spectrum"]
        self.force_history = d["force_history"]
        self.warnings = list(d["warnings"])
        self.dir = None if d["dir"] is None else pathlib.Path(d["dir"])

    speed_ratio = property(lambda self: self.result["speed_ratio"])
    period = property(lambda self: self.result["period"])
    regime = property(lambda self: self.summary["regime"])
    z0 = property(lambda self: self.result["z0"], doc="|Z0(ω)| (m): the unit of the _nd values")

    @property
    def orbit_m(self) -> np.ndarray:
        """The orbit in metres."""
        return self.orbit * self.z0

    @property
    def error(self) -> Optional[float]:
        """The estimated relative error of the orbit's extents (None when not estimated)."""
        e = self.result.get("error")
        return None if e is None else e["extents_rel"]

    def series(self, format: str = "vtk"):
        """The run's time series as a pyvista reader (``format``: ``"vtk"`` or ``"hdf5"``);
        needs ``out=`` and the scene's ``[output.vtk]`` / ``[output.hdf5]``."""
        return _series_reader(self.dir, format)

    def __repr__(self) -> str:
        return f"<rubsim.Run ν={self.speed_ratio:.4g}: {self.regime}>"


class Transient:
    """A speed transient's results: ``summary`` (summary.json's body; ``transient`` holds the
    numbers), ``t``, ``speed`` (Ω, rad/s), ``angle`` (φ, rad), ``acceleration`` (Ω̇) per
    recorded sample, ``response`` (n × 2: x, y of the analysed node, m), ``contact_force``
    (|F| on station 0, N), ``friction_power`` (W), ``friction_energy`` (J, so far), ``torque``
    (a driven rotor's drive and friction torques, N·m; empty otherwise), and ``windows``: the
    full-spectrum waterfall's windows (``window_revolutions`` each) as a dict of columns —
    ``t`` (s), ``omega`` (rad/s), ``frequency`` (the strongest line, rad/s, backward < 0),
    ``contact_fraction``, ``stick_fraction`` (NaN without stick) and ``dry_rub`` (a list of
    ``"whirl"``, ``"whip"`` or ``None``), as ``full_waterfall.csv`` has them; ``wear``
    (``None`` without ``[stator.wear]`` or ``[stator.abradable]``): ``history`` (n × 3: t,
    volume removed m³, largest depth m) and the worn contact nodes' columns ``stator``,
    ``node``, ``x``, ``y``, ``z``, ``angle_deg``, ``area``, ``depth`` (m) and, with an
    abradable coating, ``abraded`` (m, its plastic shortening, part of ``depth``), as
    ``wear.csv`` and ``worn_depth.csv`` have them."""

    def __init__(self, d: dict):
        self.summary = json.loads(d["summary"])
        spin = d["spin"]
        self.t, self.speed, self.angle, self.acceleration = (spin[:, k] for k in range(4))
        self.response = d["response"]
        c = d["contact"]
        self.contact_force, self.friction_power, self.friction_energy = (c[:, k] for k in range(3))
        self.torque = d["torque"]
        self.windows = d["waterfall"]
        self.wear = d["wear"]
        self.warnings = list(d["warnings"])
        self.dir = None if d["dir"] is None else pathlib.Path(d["dir"])

    @property
    def omega_n(self) -> float:
        return self.summary["omega_n"]

    def series(self, format: str = "vtk"):
        """The transient's time series as a pyvista reader (needs ``out=``)."""
        return _series_reader(self.dir, format)

    def __repr__(self) -> str:
        return f"<rubsim.Transient {len(self.t)} samples, {self.summary['duration']:.4g} s>"


class Thermal:
    """A thermal spiral: per coupling step ``t`` (s) and, as complex numbers in the rotor's
    frame, ``delta_t`` (K), ``bow`` (m), ``one_x`` (the 1× vector, m), ``heat`` (the friction
    power's first harmonic, W); ``power`` (mean friction power, W), ``contact_fraction``,
    ``non_synchronous`` (the orbit's change over a revolution relative to its radius);
    ``growth_rate`` (1/s) and ``rotation_rate`` (rad/s) of the spiral, ``runaway_at_s``,
    ``unsynchronous_at_s`` (where the vibration stopped being synchronous and the run stopped);
    ``error`` (the error estimate of ``run.error_estimate``, a dict: ``delta_t`` relative to
    the largest |ΔT|, ``growth_rate``, ``rotation_rate`` and its ``coupling`` and ``step``
    parts; None without it); ``summary`` (everything)."""

    def __init__(self, d: dict):
        self.summary = json.loads(d["summary"])
        self.t = d["t"]
        for name in ("delta_t", "bow", "one_x", "heat"):
            a = d[name]
            setattr(self, name, a[:, 0] + 1j * a[:, 1])
        self.power = d["power"]
        self.contact_fraction = d["contact_fraction"]
        self.non_synchronous = d["non_synchronous"]
        self.growth_rate = self.summary["growth_rate"]
        self.rotation_rate = self.summary["rotation_rate"]
        self.runaway_at_s = self.summary["runaway_at_s"]
        self.unsynchronous_at_s = self.summary["unsynchronous_at_s"]
        self.error = self.summary.get("error")
        self.dir = None if d["dir"] is None else pathlib.Path(d["dir"])

    def __repr__(self) -> str:
        end = "runs away" if self.runaway_at_s is not None else f"{self.t[-1]:.4g} s"
        return f"<rubsim.Thermal growth {self.growth_rate:+.3g} 1/s, {end}>"


# The columns of a study's table: (name, how it is read from one case's results), as in
# sweep.csv where it has the column.
_COLUMNS = {
    "speed_ratio": lambda r: r["speed_ratio"],
    "period": lambda r: r["period"],
    "x_min_nd": lambda r: r["extents_nd"][0],
    "x_max_nd": lambda r: r["extents_nd"][1],
    "y_min_nd": lambda r: r["extents_nd"][2],
    "y_max_nd": lambda r: r["extents_nd"][3],
    "amp_1x_nd": lambda r: r["amp_1x_nd"],
    "amp_half_nd": lambda r: r["amp_half_nd"],
    "amp_third_nd": lambda r: r["amp_third_nd"],
    "contact_force_max_nd": lambda r: r["contact_force_max_nd"],
    "contact_fraction": lambda r: r["contact_fraction"],
    "penetration_max_m": lambda r: r["penetration_max_m"],
    "z0_m": lambda r: r["z0"],
    "steps": lambda r: r["stats"]["steps"],
    "wall_s": lambda r: r["stats"]["wall_s"],
    "dt_s": lambda r: r["plan"]["dt"],
    "err_extents_rel": lambda r: np.nan if r.get("error") is None else r["error"]["extents_rel"],
    "steady": lambda r: r["steady"],
    "fwd_1x_nd": lambda r: r["whirl"]["forward_1x_nd"],
    "bwd_1x_nd": lambda r: r["whirl"]["backward_1x_nd"],
    "coexisting": lambda r: bool(r.get("coexistence") and r["coexistence"]["coexisting"]),
    # A flagged speed's stable periodic responses (its two responses shot as orbits); NaN at
    # a speed not flagged.
    "coexisting_stable": lambda r: (
        r["coexistence"]["orbits"]["coexisting_stable"]
        if r.get("coexistence") and r["coexistence"].get("orbits")
        else np.nan
    ),
}


def _table(runs: Sequence[dict], labels: Sequence[str]) -> dict:
    """The table of a study's cases: the columns above, ``regime`` (periodic, quasi-periodic,
    chaotic, … as sweep.csv's column) and ``label`` (the regime as the figures name it: 1×,
    1/2×, …)."""
    t = {name: np.array([f(r) for r in runs]) for name, f in _COLUMNS.items()}
    t["regime"] = np.array([r["dynamics"]["regime"] for r in runs], dtype=object)
    t["label"] = np.array(labels, dtype=object)
    return t


class Sweep:
    """A sweep's results: ``summary`` (summary.json's body: ``sweeps``, one per variant, with
    their regimes and quasi-resonance peaks), ``runs`` (every case's results, case order:
    variant-major), ``tables`` (one dict of numpy arrays per variant; ``table`` is the first),
    ``orbits`` (``{(variant, ν): n × 2 array}`` where the scene's figures keep them)."""

    def __init__(self, d: dict):
        self.summary = json.loads(d["summary"])
        self.runs = json.loads(d["runs"])
        regimes = list(d["regimes"])
        self.variants = [s["variant"] for s in self.summary["sweeps"]]
        n = len(self.runs) // max(len(self.variants), 1)
        self.tables = [
            _table(self.runs[i * n : (i + 1) * n], regimes[i * n : (i + 1) * n])
            for i in range(len(self.variants))
        ]
        self.orbits = {(v, s): o for v, s, o in d["orbits"]}
        self.warnings = list(d["warnings"])
        self.dir = None if d["dir"] is None else pathlib.Path(d["dir"])

    @property
    def table(self) -> dict:
        return self.tables[0]

    @property
    def regimes(self) -> list:
        """The first variant's speed ranges of one regime."""
        return self.summary["sweeps"][0]["regimes"]

    def series(self, speed_ratio: float, format: str = "vtk"):
        """The time series kept at one speed (``output.per_speed``) as a pyvista reader."""
        if self.dir is None:
            return _series_reader(None, format)
        return _series_reader(self.dir / f"speed_{speed_ratio}", format)

    def __repr__(self) -> str:
        return f"<rubsim.Sweep {len(self.variants)} variant(s) × {len(self.table['speed_ratio'])} speeds>"


class Map:
    """A map's results: ``summary`` (``map``: its axes, regime counts), ``runs`` (every cell's
    results), ``table`` (dict of numpy arrays over the cells, with the axes' values as ``x`` and
    ``y``); :meth:`grid` lays a column out as a 2-D array (rows along y)."""

    def __init__(self, d: dict):
        self.summary = json.loads(d["summary"])
        self.runs = json.loads(d["runs"])
        m = self.summary["map"]
        self.x_key, self.x = m["x"]["key"], np.array(m["x"]["values"])
        self.y_key, self.y = m["y"]["key"], np.array(m["y"]["values"])
        self.cells = np.array(d["cells"], dtype=int).reshape(-1, 2)
        self.table = _table(self.runs, list(d["regimes"]))
        self.table["x"] = self.x[self.cells[:, 0]]
        self.table["y"] = self.y[self.cells[:, 1]]
        self.warnings = list(d["warnings"])
        self.dir = None if d["dir"] is None else pathlib.Path(d["dir"])

    def grid(self, column: str) -> np.ndarray:
        """``table[column]`` as a ``len(y) × len(x)`` array."""
        values = self.table[column]
        g = np.empty((len(self.y), len(self.x)), dtype=values.dtype)
        g[self.cells[:, 1], self.cells[:, 0]] = values
        return g

    def __repr__(self) -> str:
        return f"<rubsim.Map {self.x_key} × {self.y_key}: {len(self.x)} × {len(self.y)}>"


class ThermalMap:
    """The thermal spiral's stability map (``rubsim map`` of a scene with ``[thermal]``):
    ``x_key``, ``x``, ``y_key``, ``y``; ``table`` (dict of numpy arrays over the cells, x-major:
    ``x``, ``y``, ``speed_ratio``, ``growth_rate`` (1/s; NaN where not synchronous),
    ``rotation_rate`` (rad/s), ``delta_t_end`` (K), and ``stability`` — ``stable``,
    ``growing``, ``runaway`` or ``not_synchronous``); ``classes`` (count per class);
    :meth:`grid` lays a column out as a 2-D array (rows along y)."""

    def __init__(self, d: dict):
        self.summary = json.loads(d["summary"])
        m = self.summary
        self.x_key, self.y_key = m["keys"]
        self.x, self.y = np.array(m["values"][0]), np.array(m["values"][1])
        cells = m["cells"]
        num = lambda v: np.nan if v is None else float(v)
        self.table = {
            "x": np.array([c["at"][0] for c in cells]),
            "y": np.array([c["at"][1] for c in cells]),
            "stability": np.array([c["stability"] for c in cells]),
        }
        for name in ("speed_ratio", "growth_rate", "rotation_rate", "delta_t_end"):
            self.table[name] = np.array([num(c[name]) for c in cells])
        self.classes = dict(zip(("stable", "growing", "runaway", "not_synchronous"), m["classes"]))
        self.dir = None if d["dir"] is None else pathlib.Path(d["dir"])

    def grid(self, column: str) -> np.ndarray:
        """``table[column]`` as a ``len(y) × len(x)`` array."""
        return self.table[column].reshape(len(self.x), len(self.y)).T

    def __repr__(self) -> str:
        return f"<rubsim.ThermalMap {self.x_key} × {self.y_key}: {self.classes}>"


class Modal:
    """The damped modes of the rotor alone at one speed: ``omega_d`` (rad/s), ``freq_hz``,
    ``damping_ratio`` (ζ), ``log_dec``, ``whirl`` and ``kind`` per mode; ``modes``: each mode's
    whole record (shapes included)."""

    def __init__(self, d: dict):
        self.summary = d
        self.speed = d["speed"]
        self.modes = d["modes"]
        for name in ("omega_d", "freq_hz", "damping_ratio", "log_dec"):
            setattr(self, name, np.array([m[name] for m in self.modes]))
        self.whirl = [m["whirl"] for m in self.modes]
        self.kind = [m["kind"] for m in self.modes]

    def __repr__(self) -> str:
        return f"<rubsim.Modal {len(self.modes)} modes at Ω = {self.speed:.4g} rad/s>"


def _complex(pairs) -> np.ndarray:
    a = np.array(pairs, dtype=float).reshape(-1, 2)
    return a[:, 0] + 1j * a[:, 1]


class Periodic:
    """A periodic orbit found by shooting: ``multipliers`` (complex numpy array, largest modulus
    first), ``stable``, ``instability`` (``period_doubling``, ``fold``, ``neimark_sacker`` or
    None), ``converged``, ``period`` (revolutions), ``orbit`` (the orbit's results, as a run's
    ``result``), ``monodromy`` (how the multipliers' monodromy was taken: ``"variational"`` —
    the scheme's own step linearised along one run of the map — or ``"finite_difference"`` —
    differences of whole maps, where the step has no linearisation), ``linearisation`` (a
    dict of the variational linearisation's counters — ``contact_steps``, ``one_sided``,
    ``straddled``, ``shrunk`` — or None), ``summary`` (everything); with ``refine=True`` ``refined`` (a dict:
    ``half_step``, ``error_estimate``, ``extrapolated`` — complex numpy arrays or None —,
    ``order``, ``stable``, ``verdict_changes``, ``dt``), else None."""

    def __init__(self, d: dict):
        self.summary = d
        self.refined = None
        r = d.get("refined")
        if r is not None:
            self.refined = dict(r)
            self.refined["half_step"] = _complex(r["half_step"])
            self.refined["error_estimate"] = np.array(r["error_estimate"])
            if r["extrapolated"] is not None:
                self.refined["extrapolated"] = _complex(r["extrapolated"])
        self.speed_ratio = d["speed_ratio"]
        self.period = d["period"]
        self.converged = d["converged"]
        self.stable = d["stable"]
        self.instability = d["instability"]
        self.multipliers = _complex(d["multipliers"])
        self.orbit = d["orbit"]
        self.monodromy = d["monodromy"]
        self.linearisation = d["linearisation"]

    def __repr__(self) -> str:
        state = "stable" if self.stable else f"unstable ({self.instability})"
        if not self.converged:
            state = "not converged"
        return f"<rubsim.Periodic ν={self.speed_ratio:.4g}, period {self.period}: {state}>"


class Autonomous:
    """An autonomous periodic orbit (``periodic(autonomous=True)``): a whirl at its own
    frequency, its period unknown. ``period_s`` (s), ``whirl_ratio`` (ω_w/ω_n, signed: negative
    backward), ``order`` (ω_w/Ω), ``radius_m`` (the first station's smallest and largest radius
    over the period), ``contact_fraction``, ``multipliers`` (complex numpy array, largest
    modulus first, the trivial one among them), ``trivial_multiplier`` (complex: the shift
    along the orbit, 1 to the differences' accuracy), ``largest_modulus`` (of the others),
    ``stable``, ``instability``, ``converged``, ``parameter``, ``speed_ratio``, ``summary``
    (everything)."""

    def __init__(self, d: dict):
        self.summary = d
        for k in ("parameter", "speed_ratio", "converged", "period_s", "whirl_ratio", "order",
                  "contact_fraction", "largest_modulus", "stable", "instability"):
            setattr(self, k, d[k])
        self.radius_m = np.array(d["radius_m"], dtype=float)
        self.multipliers = _complex(d["multipliers"])
        self.trivial_multiplier = complex(*d["trivial_multiplier"])

    def __repr__(self) -> str:
        state = "stable" if self.stable else f"unstable ({self.instability})"
        if not self.converged:
            state = "not converged"
        return f"<rubsim.Autonomous ν={self.speed_ratio:.4g}, whirl {self.whirl_ratio:+.5g} ω_n: {state}>"


class AutonomousBranch:
    """Autonomous orbits continued (``continuation(autonomous=True)``): ``parameter``
    (``"speed_ratio"`` or the scene key), ``points`` (each an :class:`Autonomous`), ``table``
    (numpy columns over the points: ``parameter``, ``speed_ratio``, ``stable``,
    ``largest_modulus``, ``period_s``, ``whirl_ratio``, ``order``, ``radius_m`` — the mean of
    the smallest and largest —, ``contact_fraction``), ``ended`` (why it stopped early, or
    None), ``summary``."""

    def __init__(self, d: dict):
        self.summary = d
        self.parameter = d["parameter"]
        self.points = [Autonomous(p) for p in d["points"]]
        self.table = {
            k: np.array([getattr(p, k) for p in self.points])
            for k in ("parameter", "speed_ratio", "largest_modulus", "period_s", "whirl_ratio",
                      "order", "contact_fraction")
        }
        self.table["stable"] = np.array([p.stable for p in self.points], dtype=bool)
        self.table["radius_m"] = np.array([p.radius_m.mean() for p in self.points])
        self.ended = d["ended"]

    def __repr__(self) -> str:
        return f"<rubsim.AutonomousBranch in {self.parameter}: {len(self.points)} points>"


class Branch:
    """A continued branch of periodic orbits: ``parameter`` (``"speed_ratio"``, or the scene
    key of ``continuation(key=...)``), ``table`` (numpy columns over its points: ``parameter``
    (ν, or the key's values), ``speed_ratio``, ``stable``, ``largest_modulus``, ``rho1`` (complex), ``amp_1x_nd``,
    ``contact_fraction``, ``x_min_nd`` … ``y_max_nd``), ``poincare`` (per point its k section
    points, a k × 2 array / |Z0|), ``bifurcations`` (each a dict: ``kind``,
    ``speed_ratio``, ``between``, ``rho``), ``ended`` (why it stopped early, or None)."""

    def __init__(self, d: dict):
        self.summary = d
        self.period = d["period"]
        pts = d["points"]
        # The continued parameter: "speed_ratio", or the scene key (then "parameter" holds
        # its values and "speed_ratio" the fixed speed).
        self.parameter = d.get("parameter", "speed_ratio")
        self.table = {
            "parameter": np.array([p.get("parameter", p["speed_ratio"]) for p in pts]),
            "speed_ratio": np.array([p["speed_ratio"] for p in pts]),
            "stable": np.array([p["stable"] for p in pts], dtype=bool),
            "largest_modulus": np.array([p["largest_modulus"] for p in pts]),
            "rho1": _complex([p["rho1"] for p in pts]),
            "amp_1x_nd": np.array([p["amp_1x_nd"] for p in pts]),
            "contact_fraction": np.array([p["contact_fraction"] for p in pts]),
        }
        for k, name in enumerate(("x_min_nd", "x_max_nd", "y_min_nd", "y_max_nd")):
            self.table[name] = np.array([p["extents_nd"][k] for p in pts])
        # Each point's k Poincaré section points [x, y] / |Z0| (a k × 2 array).
        self.poincare = [np.array(p["poincare_nd"], dtype=float).reshape(-1, 2) for p in pts]
        self.bifurcations = d["bifurcations"]
        self.ended = d["ended"]

    def __repr__(self) -> str:
        return f"<rubsim.Branch period {self.period}: {len(self.table['speed_ratio'])} points, {len(self.bifurcations)} bifurcation(s)>"


class Diagram:
    """Branches of periodic orbits switched at period doublings (``rubsim continue
    --switch``): ``branches`` (each a :class:`Branch`, the first the one asked for),
    ``switched`` (per switched branch a dict: ``branch``, ``parent``, ``bifurcation``,
    ``at_speed_ratio``, ``found_at_speed_ratio``, ``supercritical``, ``offset``, ``distance``),
    ``not_switched`` (the doublings not followed, and why)."""

    def __init__(self, d: dict):
        self.summary = d
        self.branches = [Branch(b) for b in d["branches"]]
        self.switched = d["switched"]
        self.not_switched = d["not_switched"]

    def __repr__(self) -> str:
        periods = [b.period for b in self.branches]
        return f"<rubsim.Diagram {len(self.branches)} branches, periods {periods}>"


def import_ross(path: PathLike, *, run: Union[None, Mapping, Sequence[str]] = None) -> Scene:
    """A rotor saved by ROSS (``Rotor.save``, ROSS 2.x or 3.x TOML) as a rubsim scene, as
    ``rubsim import-ross`` converts it; ``run`` overrides its keys (e.g. a ``[run]`` table's)."""
    path = pathlib.Path(path)
    text = _rubsim.import_ross(path.read_text(), str(path.resolve()))
    return Scene.from_toml(text, base=path.resolve().parent, set=run)


def from_ross(rotor, *, run: Union[None, Mapping, Sequence[str]] = None) -> Scene:
    """A ROSS rotor object (ROSS 2.3 or 3.x ``ross.Rotor``) as a rubsim scene: the rotor is
    saved by its own ``save`` and imported as ``rubsim import-ross`` does (every damping
    convention kept; what cannot be represented is refused by name)."""
    import tempfile

    if not hasattr(rotor, "save"):
        raise TypeError(f"from_ross takes a ross.Rotor, got {type(rotor).__name__}")
    with tempfile.TemporaryDirectory(prefix="rubsim-ross-") as d:
        path = pathlib.Path(d) / "rotor.toml"
        rotor.save(str(path))
        text = _rubsim.import_ross(path.read_text(), str(path))
    return Scene.from_toml(text, set=run)
