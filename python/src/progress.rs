//! The progress callback of a call, `callback(done, total)`, run with the GIL taken back for the
//! call only: steps of a run's main integration ([`StepProgress`], about 200 calls a run), or
//! cases of a study ([`CaseProgress`], once a case). An exception the callback raises — and a
//! KeyboardInterrupt (Ctrl-C) between two calls — stops a run at its next frame and is raised
//! from the call; a study stops handing cases to the callback after it and raises it at its end.

use pyo3::prelude::*;
use rubsim::analysis::{Prepared, RunSettings, TransientPrepared};
use rubsim::error::Error;
use rubsim::model::Model;
use rubsim::study::single::RunHooks;
use rubsim::time::{Frame, FrameSink};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Calls of a run's progress over its main integration.
const CALLS_PER_RUN: usize = 200;

/// A run's progress: `callback(step, total)` every `total / 200` steps; also a [`RunHooks`] that
/// learns the plan's steps when the run is prepared and keeps its warnings.
pub struct StepProgress {
    callback: Option<Py<PyAny>>,
    total: usize,
    every: usize,
    /// The exception the callback raised (or Ctrl-C), raised again by the caller.
    pub raised: Option<PyErr>,
    /// Warnings of the run.
    pub warnings: Vec<String>,
}

impl StepProgress {
    /// A progress calling `callback` (none: only the signals are checked).
    pub fn new(callback: Option<Py<PyAny>>) -> Self {
        Self {
            callback,
            total: 0,
            every: 0,
            raised: None,
            warnings: Vec::new(),
        }
    }

    /// Follows a run of `steps` planned steps.
    pub fn plan(&mut self, steps: usize) {
        self.total = steps;
        self.every = (steps / CALLS_PER_RUN).max(1);
    }

    /// The run's error, or the exception that stopped it when the callback did.
    pub fn error(&mut self, e: Error) -> PyErr {
        self.raised
            .take()
            .unwrap_or_else(|| crate::errors::to_py(e))
    }
}

impl FrameSink for StepProgress {
    fn every(&self) -> usize {
        self.every
    }
    fn frame(&mut self, frame: &Frame<'_>) -> rubsim::error::Result<()> {
        let total = self.total.max(frame.step);
        let out = Python::attach(|py| {
            py.check_signals()?;
            match &self.callback {
                Some(cb) => cb.call1(py, (frame.step, total)).map(drop),
                None => Ok(()),
            }
        });
        out.map_err(|e| {
            let message = e.to_string();
            self.raised = Some(e);
            Error::study("the progress callback", message)
        })
    }
}

impl RunHooks for StepProgress {
    fn prepared(&mut self, prep: &Prepared) {
        self.plan(prep.plan.steps);
    }
    fn transient_prepared(&mut self, prep: &TransientPrepared) {
        self.plan(prep.plan.steps);
    }
    fn progress(&mut self) -> Option<&mut dyn FrameSink> {
        Some(self)
    }
    fn warning(&mut self, message: &str) {
        self.warnings.push(message.to_string());
    }
}

/// A study's progress: `callback(done, total)` after each case (from the worker that finished
/// it), and the study's warnings kept.
pub struct CaseProgress {
    callback: Option<Py<PyAny>>,
    total: AtomicUsize,
    done: AtomicUsize,
    /// The first exception the callback raised.
    pub raised: Mutex<Option<PyErr>>,
    /// Warnings of the study.
    pub warnings: Mutex<Vec<String>>,
}

impl CaseProgress {
    /// A progress calling `callback`.
    pub fn new(callback: Option<Py<PyAny>>) -> Self {
        Self {
            callback,
            total: AtomicUsize::new(0),
            done: AtomicUsize::new(0),
            raised: Mutex::new(None),
            warnings: Mutex::new(Vec::new()),
        }
    }

    /// The exception the callback raised, if any.
    pub fn take_raised(&self) -> Option<PyErr> {
        self.raised.lock().ok().and_then(|mut r| r.take())
    }

    /// The warnings, emptied.
    pub fn take_warnings(&self) -> Vec<String> {
        self.warnings
            .lock()
            .map(|mut w| std::mem::take(&mut *w))
            .unwrap_or_default()
    }

    fn warn(&self, message: String) {
        if let Ok(mut w) = self.warnings.lock() {
            w.push(message);
        }
    }
}

impl rubsim::study::Progress for CaseProgress {
    fn warning(&self, message: &str) {
        self.warn(message.to_string());
    }
    fn start(&self, _model: &Model, _settings: &RunSettings, _speeds: &[f64], runs: usize) {
        self.total.store(runs, Ordering::Relaxed);
    }
    fn case_done(&self) {
        let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        let Some(cb) = &self.callback else {
            return;
        };
        let mut raised = match self.raised.lock() {
            Ok(r) => r,
            Err(_) => return,
        };
        if raised.is_some() {
            return;
        }
        let total = self.total.load(Ordering::Relaxed).max(done);
        if let Err(e) = Python::attach(|py| cb.call1(py, (done, total)).map(drop)) {
            *raised = Some(e);
        }
    }
}
