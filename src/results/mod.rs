//! Time series for ParaView and pyvista: VTK XML frames (`.vtu` files and a `.pvd` collection,
//! [`vtk`]) and one HDF5 file per run with a transient VTKHDF group ([`hdf5`], cargo feature
//! `hdf5`); and the mode shapes of `rubsim modal` in both formats ([`modes`], `mode_hdf5`),
//! animatable over one period. The layout of both is documented in `docs/OUTPUTS.md`.
//!
//! [`ResultsSink`] is a [`FrameSink`](crate::time::FrameSink): the integrator hands it the full state every few steps
//! and it streams frames to disk while the run goes, so memory does not grow with the run.
//! Files are written below the output directory's staging folder
//! ([`crate::output::OutDir::staging_dir`]) and moved into place when the command succeeds.
//!
//! # The output grid
//!
//! Both formats write the same unstructured grid ([`Layout`]):
//!
//! * points: the points of every stator, stator after stator, then the rotor nodes on the axis
//!   `(0, 0, z)`. A stator's points are its nodes — 2-D stators in the plane `z` of the rotor
//!   node carrying their station, 3-D (tetrahedral) meshed stators at their own axial position
//!   `z = node z + axial_origin` — followed, for a ring target, by the [`RING_POINTS`] points
//!   of its contact circle and the ring's contact point ([`RingSlot`]). Points are at their
//!   **undeformed** positions (m); the point array `displacement` moves them (ParaView's
//!   *Warp By Vector*).
//! * cells: one per stator element ([`element_cell`]), a closed polyline per ring (its
//!   contact circle), the rotor (a vertex for a one-node rotor, else a polyline through its
//!   nodes), then the contact pairs as lines from the rotor node of the station the target
//!   faces to the stator node (a ring: to its contact point). The `.vtu` frames hold only the
//!   pairs in contact at that instant; the VTKHDF grid, written once, holds every candidate pair
//!   with `normal_force = 0` while it is open.
//! * cell data `part` (0 stator element or ring circle, 1 rotor, 2 contact pair), `stator`
//!   (stator index, −1 for the rotor) and `index` (element index in its stator, −1 for a ring
//!   circle, pair index, 0 for the rotor).
//! * rotor points: `displacement` `[u_x, u_y, u_z]` (u_z of rotors with axial DOFs, else 0);
//!   with torsional DOFs ([`Layout::rotor_has_torsion`]) the point array `twist` (θ_z, rad,
//!   counter-clockwise seen from +z, the sense of the spin) and, with velocities,
//!   `twist_rate` (rad/s), NaN on the stator points. The bending rotations θ_x, θ_y are not
//!   grid arrays (a point array spans every stator point); the HDF5 file's `/rotor/u` with
//!   `/rotor/node_dofs` ([`RotorNodeDofs`]) holds them.
//!
//! Conventions are the crate's: SI units, x horizontal, y vertical, rotor axis z; contact force
//! positive on the body it acts on (`contact_force` at a stator node is `Σ (n + μa) p` of its
//! pairs, at a rotor node the opposite sum); `normal_force` is the multiplier `p ≥ 0`
//! (compression).

pub mod frame;
pub mod layout;
pub mod modes;
pub mod series;
pub mod sink;
pub mod vtk;

#[cfg(feature = "hdf5")]
pub mod hdf5;
#[cfg(feature = "hdf5")]
mod hdf5_io;
#[cfg(feature = "hdf5")]
mod hdf5_spin;
#[cfg(feature = "hdf5")]
pub mod mode_hdf5;

pub use frame::FrameState;
pub use layout::{
    element_cell, gmsh_to_vtk_order, part, rotor_dof_map, rotor_node_z, vtk_cell_type, CellType,
    Layout, OutputGrid, PairSlot, RingSlot, RotorNodeDofs, RING_POINTS, ROTOR_DOF_NAMES, THETA_Z,
    U_Z,
};
pub use series::Series;
pub use sink::{check_free_space, ResultsSink};

use crate::scene::{OutputSpec, PerSpeed, SeriesField, SeriesSpec};
use crate::time::StepPlan;

/// Which fields a writer writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Fields {
    /// Point `displacement` (and the rotor DOFs in HDF5).
    pub displacement: bool,
    /// Point `velocity` (and the rotor DOF velocities in HDF5).
    pub velocity: bool,
    /// Point `contact_force`, cell `normal_force`, HDF5 `/contact`.
    pub contact_force: bool,
    /// Cell `axial_force`, `stress`, `strain`.
    pub stress: bool,
}

impl Fields {
    /// From a scene's list.
    pub fn from_list(list: &[SeriesField]) -> Self {
        let has = |f| list.contains(&f);
        Self {
            displacement: has(SeriesField::Displacement),
            velocity: has(SeriesField::Velocity),
            contact_force: has(SeriesField::ContactForce),
            stress: has(SeriesField::Stress),
        }
    }
}

/// The frames of one writer: steps `first, first + every, … ≤ last`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FramePlan {
    /// Steps between frames.
    pub every: usize,
    /// First frame step (a multiple of `every`).
    pub first: usize,
    /// Last step that may hold a frame.
    pub last: usize,
    /// Fields written.
    pub fields: Fields,
}

impl FramePlan {
    /// Resolves a scene's writer against a run's step plan.
    pub fn new(spec: &SeriesSpec, plan: &StepPlan) -> Self {
        let every = spec.every.unwrap_or(plan.record_every).max(1);
        let spr = plan.steps_per_rev as f64;
        let first =
            ((spec.from_revolution * spr - 1e-6).ceil().max(0.0) as usize).div_ceil(every) * every;
        let last = spec.to_revolution.map_or(plan.steps, |r| {
            ((r * spr + 1e-6).floor().max(0.0) as usize).min(plan.steps)
        });
        Self {
            every,
            first,
            last,
            fields: Fields::from_list(&spec.fields),
        }
    }

    /// True when `step` holds a frame.
    pub fn contains(&self, step: usize) -> bool {
        step >= self.first && step <= self.last && step.is_multiple_of(self.every)
    }

    /// Number of frames.
    pub fn count(&self) -> usize {
        if self.first > self.last {
            0
        } else {
            (self.last - self.first) / self.every + 1
        }
    }
}

/// Run information stored with the results (HDF5 attributes, `.pvd` comment).
#[derive(Debug, Clone, PartialEq)]
pub struct RunInfo {
    /// The resolved scene as JSON.
    pub scene_json: String,
    /// ω/ω_n.
    pub speed_ratio: f64,
    /// ω (rad/s).
    pub omega: f64,
    /// The step plan.
    pub plan: StepPlan,
    /// Integrator name.
    pub integrator: &'static str,
}

/// True when the scene asks for any time series.
pub fn wanted(o: &OutputSpec) -> bool {
    o.vtk.is_some() || o.hdf5.is_some()
}

/// Frame plans of the scene's writers at one speed, as `(format, plan)`, e.g. for reports.
pub fn frame_plans(o: &OutputSpec, plan: &StepPlan) -> Vec<(&'static str, FramePlan)> {
    let mut v = Vec::new();
    if let Some(s) = &o.vtk {
        v.push(("vtk", FramePlan::new(s, plan)));
    }
    if let Some(s) = &o.hdf5 {
        v.push(("hdf5", FramePlan::new(s, plan)));
    }
    v
}

/// One line per time-series writer for `rubsim check`: files, frame count and interval at the
/// speed of `plan`.
pub fn describe(o: &OutputSpec, plan: &StepPlan, sweep: bool) -> Vec<String> {
    let folder = if sweep {
        match &o.per_speed {
            PerSpeed::All(false) => {
                return vec!["time series: none (sweep without output.per_speed)".into()]
            }
            PerSpeed::All(true) => "speed_<ν>/ for every speed, ",
            PerSpeed::Speeds(_) => "speed_<ν>/ for the speeds of output.per_speed, ",
        }
    } else {
        ""
    };
    frame_plans(o, plan)
        .into_iter()
        .map(|(fmt, fp)| {
            let files = match fmt {
                "vtk" => format!("{} + {}/frame_NNNNNN.vtu", vtk::PVD, vtk::FRAME_DIR),
                _ => "results.vtkhdf".to_string(),
            };
            format!(
                "{fmt}: {folder}{files}: {} frames, every {} steps (Δt = {:.3e} s), steps {}–{} of {}",
                fp.count(),
                fp.every,
                plan.dt,
                fp.first,
                fp.last,
                plan.steps
            )
        })
        .collect()
}

/// One line per time-series writer for `rubsim check`: what `rubsim periodic` (`orbit/`) and
/// `rubsim continue --orbits-at` (`orbits/branch<i>_<ν>/`) write of a periodic orbit at the
/// speed of `plan` — one period of `k` revolutions (`Series::orbit`): `k N / every + 1` frames
/// when `every` divides the `N` steps of a revolution.
pub fn describe_orbit(o: &OutputSpec, plan: &StepPlan) -> Vec<String> {
    frame_plans(o, plan)
        .into_iter()
        .map(|(fmt, fp)| {
            let n = plan.steps_per_rev.max(1);
            let frames = if n.is_multiple_of(fp.every) {
                format!("k·{} + 1 frames", n / fp.every)
            } else {
                format!("about k·{:.1} frames (every {} does not divide the {n} steps of a revolution: the first frame is not the fixed point)", n as f64 / fp.every as f64, fp.every)
            };
            format!(
                "{fmt} of a periodic orbit (`rubsim periodic`: orbit/; `rubsim continue --orbits-at`: orbits/branch<i>_<ν>/): one period of k revolutions from the fixed point, {frames}, every {} steps (Δt = {:.3e} s)",
                fp.every, plan.dt
            )
        })
        .collect()
}

/// The sub-folder of a speed's time series in a sweep: `speed_<ω/ω_n>/`.
pub fn speed_folder(speed_ratio: f64) -> String {
    format!("speed_{speed_ratio}/")
}

/// Which sweep speeds write time series (`output.per_speed`), as a flag per speed.
///
/// # Errors
/// A listed speed that is not one of the sweep's (the message lists them).
pub fn per_speed_selection(
    o: &OutputSpec,
    speeds: &[f64],
) -> std::result::Result<Vec<bool>, String> {
    match &o.per_speed {
        PerSpeed::All(all) => Ok(vec![*all && wanted(o); speeds.len()]),
        PerSpeed::Speeds(list) => {
            let mut sel = vec![false; speeds.len()];
            for v in list {
                match speeds.iter().position(|s| (s - v).abs() < 1e-6) {
                    Some(i) => sel[i] = true,
                    None => {
                        return Err(format!(
                            "ω/ω_n = {v} is not a speed of the sweep ({})",
                            speeds
                                .iter()
                                .map(|s| s.to_string())
                                .collect::<Vec<_>>()
                                .join(", ")
                        ))
                    }
                }
            }
            Ok(sel)
        }
    }
}
