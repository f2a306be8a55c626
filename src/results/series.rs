//! [`Series`]: a run with the VTK/HDF5 time-series writers its scene asks for attached — the
//! one way a single run (`rubsim run`) and a study's case (`crate::study`) write their series.

use super::{wanted, ResultsSink};
use crate::analysis::autonomous::AutonomousOrbit;
use crate::analysis::periodic::{self, PeriodicOrbit};
use crate::analysis::{Keep, Prepared, SpeedResults};
use crate::error::Result;
use crate::model::Model;
use crate::scene::{OutputSpec, SeriesSpec};
use crate::time::FrameSink;
use std::path::Path;

/// Where a run's VTK/HDF5 time series go: the scene's `[output]` (as text for the files'
/// metadata) and the staging folder of the output directory (or of a case's kept series).
pub struct Series<'a> {
    /// The scene's `[output]`.
    pub output: &'a OutputSpec,
    /// The scene as JSON, stored with the series.
    pub scene_json: &'a str,
    /// The staging folder the files are written into.
    pub staging: &'a Path,
}

impl Series<'_> {
    /// Runs `prep` (a run of `model`) with the time-series writers the scene asks for
    /// attached, their files below `prefix` (empty or ending in `/`); returns the results and
    /// the files written, relative to the staging folder.
    ///
    /// # Errors
    /// As [`ResultsSink::new`] and [`Prepared::run`].
    pub fn run(
        &self,
        model: &Model,
        prep: &Prepared,
        keep: Keep,
        prefix: &str,
    ) -> Result<(SpeedResults, Vec<String>)> {
        self.run_with(model, prep, keep, prefix, None)
    }

    /// [`Series::run`] with one more sink (`extra`, e.g. a progress bar) beside the writers.
    ///
    /// # Errors
    /// As [`Series::run`].
    pub fn run_with(
        &self,
        model: &Model,
        prep: &Prepared,
        keep: Keep,
        prefix: &str,
        extra: Option<&mut dyn FrameSink>,
    ) -> Result<(SpeedResults, Vec<String>)> {
        let mut writer = ResultsSink::for_output(
            model,
            prep,
            self.output,
            self.scene_json,
            self.staging,
            prefix,
        )?;
        let mut sinks: Vec<&mut dyn FrameSink> = Vec::with_capacity(2);
        if let Some(w) = writer.as_mut() {
            sinks.push(w);
        }
        if let Some(e) = extra {
            sinks.push(e);
        }
        let r = prep.run(keep, &mut sinks)?;
        drop(sinks);
        match writer {
            None => Ok((r, Vec::new())),
            Some(w) => Ok((r, w.finish()?)),
        }
    }

    /// Writes the periodic orbit `o` of `prep` (a run of `model`; the orbit found on it, its
    /// speed and step) as the time series the scene asks for, below `prefix` (empty or ending
    /// in `/`): one period of `k` revolutions integrated from the fixed point by the run's own
    /// scheme and step with the same writers a run attaches, after a lead-in of one period
    /// ([`periodic::series_plan`]: frames at steps `k N … 2 k N`, times `k T … 2 k T`). Every
    /// writer's `every` and `fields` are the scene's; its `from_revolution`/`to_revolution`
    /// (the window of a run) are replaced by the written period. Returns the files written,
    /// relative to the staging folder; none when the scene asks for no series.
    ///
    /// # Errors
    /// As [`ResultsSink::new`] and [`periodic::integrate_orbit`].
    pub fn orbit(
        &self,
        model: &Model,
        prep: &Prepared,
        o: &PeriodicOrbit,
        prefix: &str,
    ) -> Result<Vec<String>> {
        let output = orbit_output(self.output, o.period);
        if !wanted(&output) {
            return Ok(Vec::new());
        }
        let plan = periodic::series_plan(&prep.plan, o.period);
        let mut w = self.sink_on(model, prep, (&plan, &output), prefix)?;
        periodic::integrate_orbit(prep, o, &plan, Some(&mut w))?;
        w.finish()
    }

    /// The writers `output` asks for on `prep`'s case over `plan` (an orbit's), below `prefix`
    /// ([`ResultsSink::with_plan`]).
    fn sink_on<'p>(
        &self,
        model: &Model,
        prep: &'p Prepared,
        (plan, output): (&crate::time::StepPlan, &OutputSpec),
        prefix: &str,
    ) -> Result<ResultsSink<'p>> {
        ResultsSink::with_plan(
            model,
            prep,
            plan,
            output,
            self.scene_json,
            self.staging,
            prefix,
        )
    }
    /// Writes the autonomous orbit `o` of `prep` (its whirl of period `T`, not tied to the
    /// shaft's revolutions) as the time series the scene asks for, below `prefix`: one period
    /// integrated from the fixed point at `Δt = T/N` after a lead-in of one
    /// ([`AutonomousOrbit::series_plan`]: frames at steps `N … 2N`, times `T … 2T`; the files'
    /// "revolution" is one period `T`), each writer's `every` lowered to the largest divisor
    /// of `N` not above it (the scene's, or the recording interval) so that the frames close
    /// the period. Returns the files written; none when the scene asks for no series.
    ///
    /// # Errors
    /// As [`ResultsSink::new`] and [`AutonomousOrbit::integrate`].
    pub fn autonomous_orbit(
        &self,
        model: &Model,
        prep: &Prepared,
        o: &AutonomousOrbit,
        prefix: &str,
    ) -> Result<Vec<String>> {
        let plan = o.series_plan(&prep.plan);
        let mut output = orbit_output(self.output, 1);
        if !wanted(&output) {
            return Ok(Vec::new());
        }
        // The whirl's N steps are not the shaft's: each writer's `every` lowered to a divisor
        // of N, so that the first frame is the fixed point and the last closes the period.
        for s in [&mut output.vtk, &mut output.hdf5].into_iter().flatten() {
            let asked = s.every.unwrap_or(plan.record_every);
            s.every = Some(divisor_at_most(plan.steps_per_rev, asked));
        }
        let mut w = self.sink_on(model, prep, (&plan, &output), prefix)?;
        o.integrate(prep, &plan, Some(&mut w))?;
        w.finish()
    }
}

/// The largest divisor of `n` not above `at_most` (1 at least).
fn divisor_at_most(n: usize, at_most: usize) -> usize {
    (1..=at_most.min(n).max(1))
        .rev()
        .find(|d| n.is_multiple_of(*d))
        .unwrap_or(1)
}

/// `output` with each time-series writer's window set to the second period of `k`
/// revolutions (revolutions `k … 2k`: [`Series::orbit`]).
fn orbit_output(output: &OutputSpec, k: usize) -> OutputSpec {
    let k = k.max(1) as f64;
    let window = |s: &Option<SeriesSpec>| {
        s.clone().map(|s| SeriesSpec {
            from_revolution: k,
            to_revolution: Some(2.0 * k),
            ..s
        })
    };
    OutputSpec {
        vtk: window(&output.vtk),
        hdf5: window(&output.hdf5),
        ..output.clone()
    }
}
