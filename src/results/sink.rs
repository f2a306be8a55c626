//! [`ResultsSink`]: the [`FrameSink`] that streams a run's frames to the VTK and HDF5 writers
//! the scene asks for.

#[cfg(feature = "hdf5")]
use super::hdf5;
use super::{vtk, wanted, FramePlan, FrameState, Layout, RunInfo, THETA_Z};
use crate::analysis::{Prepared, TransientPrepared};
use crate::error::{Error, Result};
use crate::math::gcd;
use crate::model::{Case, Model};
use crate::scene::OutputSpec;
use crate::time::{Frame, FrameSink, StepPlan};
use std::path::Path;

/// Displacements of the step before a frame (for the backward-difference velocities).
#[derive(Debug, Clone)]
struct PrevStep {
    step: usize,
    t: f64,
    displacement: Vec<[f64; 3]>,
    rotor_u: Vec<f64>,
}

/// Streams the frames of one run to the VTK and HDF5 writers a scene asks for.
pub struct ResultsSink<'a> {
    case: &'a Case,
    layout: Layout,
    state: FrameState,
    every: usize,
    /// The step before a frame, for velocities.
    prev: Option<PrevStep>,
    need_velocity: bool,
    init_velocity: [f64; 2],
    vtk: Option<(FramePlan, vtk::VtkSeries)>,
    #[cfg(feature = "hdf5")]
    hdf5: Option<(FramePlan, hdf5::Hdf5Series)>,
}

impl std::fmt::Debug for ResultsSink<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ResultsSink")
            .field("every", &self.every)
            .field("points", &self.layout.num_points())
            .finish_non_exhaustive()
    }
}

/// Errors when the file system holding `dir` has less free space than `bytes` (estimated size
/// of the series) plus a 5 % margin. Unix only (`statvfs`); elsewhere no check.
pub fn check_free_space(dir: &Path, bytes: f64) -> Result<()> {
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStrExt;
        let Ok(c) = std::ffi::CString::new(dir.as_os_str().as_bytes()) else {
            return Ok(());
        };
        // SAFETY: `c` is a valid NUL-terminated path and `st` a zeroed out-parameter.
        let mut st: libc::statvfs = unsafe { std::mem::zeroed() };
        if unsafe { libc::statvfs(c.as_ptr(), &mut st) } != 0 {
            return Ok(());
        }
        let free = st.f_bavail as f64 * st.f_frsize as f64;
        if bytes * 1.05 > free {
            return Err(Error::output(
            dir,
            format!(
                "the requested VTK/HDF5 series needs about {:.0} MB but only {:.0} MB are free; write fewer frames (output.*.every, from_revolution/to_revolution, fields) or choose another --out",
                bytes / 1e6,
                free / 1e6
            ),
        ));
        }
    }
    #[cfg(not(unix))]
    let _ = (dir, bytes);
    Ok(())
}

impl<'a> ResultsSink<'a> {
    /// The writers `output` asks for at the prepared run `prep` of `model`, or `None` when it
    /// asks for no time series ([`wanted`]); see [`ResultsSink::new`].
    ///
    /// # Errors
    /// As [`ResultsSink::new`].
    pub fn for_output(
        model: &Model,
        prep: &'a Prepared,
        output: &OutputSpec,
        scene_json: &str,
        staging: &Path,
        prefix: &str,
    ) -> Result<Option<Self>> {
        if !wanted(output) {
            return Ok(None);
        }
        Self::new(model, prep, output, scene_json, staging, prefix).map(Some)
    }

    /// Prepares the writers of `output` for the prepared run `prep` of `model` (whose case and
    /// step plan it lays out and frames); files go below `staging/prefix` (`prefix` empty or
    /// ending in `/`). Opens every file and writes the static parts at once, so an unwritable
    /// directory fails before the run.
    ///
    /// # Errors
    /// [`Error::Output`] naming the file when a writer cannot be created or the disk is too
    /// full for the series.
    pub fn new(
        model: &Model,
        prep: &'a Prepared,
        output: &OutputSpec,
        scene_json: &str,
        staging: &Path,
        prefix: &str,
    ) -> Result<Self> {
        Self::with_plan(model, prep, &prep.plan, output, scene_json, staging, prefix)
    }

    /// [`ResultsSink::new`] on the step plan `plan` instead of `prep`'s (a run of `prep`'s case
    /// and step over other steps: a periodic orbit's series, `Series::orbit`); the plan is the
    /// one `from_revolution`/`to_revolution` count in and the files' metadata state.
    ///
    /// # Errors
    /// As [`ResultsSink::new`].
    pub fn with_plan(
        model: &Model,
        prep: &'a Prepared,
        plan: &StepPlan,
        output: &OutputSpec,
        scene_json: &str,
        staging: &Path,
        prefix: &str,
    ) -> Result<Self> {
        let info = RunInfo {
            scene_json: scene_json.to_string(),
            speed_ratio: prep.case.speed_ratio,
            omega: prep.omega,
            plan: *plan,
            integrator: prep.request.step.integrator.name(),
        };
        let init_v = prep.request.initial().v;
        Self::build(model, &prep.case, info, init_v, output, staging, prefix)
    }

    /// The writers `output` asks for along the speed transient `prep` of `model`, or `None`
    /// when it asks for no time series: as [`ResultsSink::new`], on the transient's case (at
    /// its reference speed Ω_ref, the `speed_ratio`/`omega_rad_s` of the HDF5 attributes and
    /// the `.pvd` comment) and its step plan. Every frame carries the spin state of its
    /// instant (Ω, Ω/ω_n, φ, Ω̇: [`FrameState`]); `from_revolution`/`to_revolution` count
    /// periods 2π/Ω_max of the profile's top speed (`steps_per_rev` steps of the plan).
    ///
    /// # Errors
    /// As [`ResultsSink::new`].
    pub fn for_transient(
        model: &Model,
        prep: &'a TransientPrepared,
        output: &OutputSpec,
        scene_json: &str,
        staging: &Path,
        prefix: &str,
    ) -> Result<Option<Self>> {
        if !wanted(output) {
            return Ok(None);
        }
        let info = RunInfo {
            scene_json: scene_json.to_string(),
            speed_ratio: prep.case.speed_ratio,
            omega: prep.case.omega,
            plan: prep.plan,
            integrator: prep.settings.step.integrator.name(),
        };
        let init_v = prep.settings.initial.v;
        Self::build(model, &prep.case, info, init_v, output, staging, prefix).map(Some)
    }

    /// The writers of `output` on `case` and the plan of `info`; `init_v` is the station
    /// node's initial velocity (the first frame's velocity).
    fn build(
        model: &Model,
        case: &'a Case,
        info: RunInfo,
        init_v: [f64; 2],
        output: &OutputSpec,
        staging: &Path,
        prefix: &str,
    ) -> Result<Self> {
        let plan: StepPlan = info.plan;
        let layout = Layout::new(model, case);
        let state = FrameState::new(&layout, case);
        // Refuse a run whose series cannot fit on the disk before it spends its time.
        let mut need_bytes = 0.0;
        let pts = layout.num_points() as f64;
        let cells = layout.grid.num_cells() as f64;
        let conn = layout.grid.connectivity.len() as f64;
        // `twist` and `twist_rate`: one value per point each.
        let twist = if layout.rotor_has_torsion() { 2.0 } else { 0.0 };
        if let Some(spec) = &output.vtk {
            let fp = FramePlan::new(spec, &plan);
            // Per .vtu: geometry and fields as base64 text (4/3) of f64/i64.
            let per =
                (pts * (3.0 + 9.0 + twist) + conn + 2.0 * cells + 4.0 * cells) * 8.0 * 4.0 / 3.0;
            need_bytes += fp.count() as f64 * per;
        }
        if let Some(spec) = &output.hdf5 {
            let fp = FramePlan::new(spec, &plan);
            let per = (pts * (9.0 + twist) + 4.0 * cells + case.rotor.ndof as f64 * 2.0) * 8.0;
            need_bytes += fp.count() as f64 * per;
        }
        check_free_space(staging, need_bytes)?;
        let mut every = 0;
        let mut need_velocity = false;
        let vtk = match &output.vtk {
            Some(spec) => {
                let fp = FramePlan::new(spec, &plan);
                every = gcd(every, fp.every);
                need_velocity |= fp.fields.velocity;
                Some((fp, vtk::VtkSeries::create(staging, prefix, &info)?))
            }
            None => None,
        };
        #[cfg(feature = "hdf5")]
        let hdf5 = match &output.hdf5 {
            Some(spec) => {
                let fp = FramePlan::new(spec, &plan);
                every = gcd(every, fp.every);
                need_velocity |= fp.fields.velocity;
                Some((
                    fp,
                    hdf5::Hdf5Series::create(staging, prefix, &layout, case, &fp, &info)?,
                ))
            }
            None => None,
        };
        #[cfg(not(feature = "hdf5"))]
        if output.hdf5.is_some() {
            return Err(Error::output(
                staging.join(prefix),
                "output.hdf5 is set but rubsim was built without the `hdf5` feature (rebuild with default features, libhdf5 installed)",
            ));
        }
        if need_velocity {
            every = 1;
        }
        Ok(Self {
            case,
            layout,
            state,
            every,
            prev: None,
            need_velocity,
            init_velocity: init_v,
            vtk,
            #[cfg(feature = "hdf5")]
            hdf5,
        })
    }

    /// The grid layout.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// True when a writer writes the frame of `step`.
    fn writes(&self, step: usize) -> bool {
        let v = self.vtk.as_ref().is_some_and(|(p, _)| p.contains(step));
        #[cfg(feature = "hdf5")]
        let h = self.hdf5.as_ref().is_some_and(|(p, _)| p.contains(step));
        #[cfg(not(feature = "hdf5"))]
        let h = false;
        v || h
    }

    fn velocities(&mut self) {
        let st = &mut self.state;
        match &self.prev {
            Some(p) if p.step + 1 == st.step && st.t > p.t => {
                let dt = st.t - p.t;
                for (v, (a, b)) in st
                    .velocity
                    .iter_mut()
                    .zip(st.displacement.iter().zip(&p.displacement))
                {
                    *v = [(a[0] - b[0]) / dt, (a[1] - b[1]) / dt, (a[2] - b[2]) / dt];
                }
                for (v, (a, b)) in st.rotor_v.iter_mut().zip(st.rotor_u.iter().zip(&p.rotor_u)) {
                    *v = (a - b) / dt;
                }
            }
            _ => {
                // First frame of the run: the initial velocity (rotor station node; stators at
                // rest).
                st.velocity.fill([0.0; 3]);
                st.rotor_v.fill(0.0);
                if st.step == 0 {
                    let node = self.case.stations.first().map_or(0, |s| s.node);
                    let d = self.case.rotor.node_dofs[node];
                    st.rotor_v[d[0]] = self.init_velocity[0];
                    st.rotor_v[d[1]] = self.init_velocity[1];
                    let p = self.layout.rotor_first_point + node;
                    st.velocity[p] = [self.init_velocity[0], self.init_velocity[1], 0.0];
                }
            }
        }
        // Twist rates: the same backward difference, on the θ_z DOFs.
        for (r, d) in st.rotor_twist_rate.iter_mut().zip(&self.layout.rotor_dofs) {
            *r = d[THETA_Z].map_or(0.0, |i| st.rotor_v[i]);
        }
    }

    fn write(&mut self) -> Result<()> {
        let step = self.state.step;
        if let Some((fp, w)) = &mut self.vtk {
            if fp.contains(step) {
                w.write(&self.layout, &self.state, &fp.fields)?;
            }
        }
        #[cfg(feature = "hdf5")]
        if let Some((fp, w)) = &mut self.hdf5 {
            if fp.contains(step) {
                w.write(&self.layout, &self.state, &fp.fields)?;
            }
        }
        Ok(())
    }

    /// Flushes and closes every writer; returns the files written (relative to the staging
    /// folder, prefix included), to be adopted by the output directory.
    ///
    /// # Errors
    /// [`Error::Output`] naming the file.
    pub fn finish(self) -> Result<Vec<String>> {
        let mut names = Vec::new();
        if let Some((_, w)) = self.vtk {
            names.extend(w.finish()?);
        }
        #[cfg(feature = "hdf5")]
        if let Some((_, w)) = self.hdf5 {
            names.extend(w.finish()?);
        }
        Ok(names)
    }
}

impl FrameSink for ResultsSink<'_> {
    fn every(&self) -> usize {
        self.every
    }

    /// A frame that is written, or the step before one when velocities are written.
    fn wants(&self, step: usize) -> bool {
        self.writes(step) || (self.need_velocity && self.writes(step + 1))
    }

    fn frame(&mut self, frame: &Frame<'_>) -> Result<()> {
        let now = self.writes(frame.step);
        let before_next = self.need_velocity && self.writes(frame.step + 1);
        if !now && !before_next {
            return Ok(());
        }
        self.state.fill(&self.layout, self.case, frame);
        if now {
            if self.need_velocity {
                self.velocities();
            }
            self.write()?;
        }
        if before_next {
            // Reuses the buffers of the previous copy: no allocation after the first frame.
            let p = match self.prev.take() {
                Some(mut p) => {
                    p.displacement.copy_from_slice(&self.state.displacement);
                    p.rotor_u.copy_from_slice(&self.state.rotor_u);
                    p
                }
                None => PrevStep {
                    step: 0,
                    t: 0.0,
                    displacement: self.state.displacement.clone(),
                    rotor_u: self.state.rotor_u.clone(),
                },
            };
            self.prev = Some(PrevStep {
                step: frame.step,
                t: frame.t,
                ..p
            });
        }
        Ok(())
    }
}
