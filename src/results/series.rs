//! [`Series`]: a run with the VTK/HDF5 time-series writers its scene asks for attached — the
//! one way a single run (`rubsim run`) and a study's case (`crate::study`) write their series.

use super::ResultsSink;
use crate::analysis::{Keep, Prepared, SpeedResults};
use crate::error::Result;
use crate::model::Model;
use crate::scene::OutputSpec;
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
}
