//! What a study or a continuation in segments prints while it runs
//! (`rubsim::study::Progress`): warnings, the chosen step, what was found finished, the
//! estimate and a progress bar.

use super::{announce_sweep, describe_choice, progress_bar};
use indicatif::ProgressBar;
use rubsim::analysis::{RunSettings, StepChoice};
use rubsim::model::Model;
use std::path::Path;
use std::sync::OnceLock;

/// The progress on stderr of a study's cases or a continuation's segments (`noun`): the bar
/// is set up front, or by `start` (a study: its estimate printed then).
pub struct Printed {
    bar: OnceLock<ProgressBar>,
    noun: &'static str,
}

impl Printed {
    /// Progress over `noun` (`cases`, `segments`), with the bar `bar` (empty: set by `start`).
    pub fn new(noun: &'static str, bar: OnceLock<ProgressBar>) -> Self {
        Self { bar, noun }
    }
}

impl rubsim::study::Progress for Printed {
    fn warning(&self, message: &str) {
        eprintln!("warning: {message}");
    }
    fn step_chosen(&self, choice: &StepChoice) {
        eprintln!("{}", describe_choice(choice));
    }
    fn resumed(&self, finished: usize, of: usize, store: &Path) {
        if let Some(b) = self.bar.get() {
            b.inc(finished as u64);
        }
        eprintln!(
            "{finished} of {of} {} already finished in {}; running {}",
            self.noun,
            store.display(),
            of - finished
        );
    }
    fn start(&self, model: &Model, settings: &RunSettings, speeds: &[f64], runs: usize) {
        announce_sweep(model, settings, speeds, runs);
        let _ = self.bar.set(progress_bar(runs));
    }
    fn case_done(&self) {
        if let Some(b) = self.bar.get() {
            b.inc(1);
        }
    }
    fn end(&self) {
        if let Some(b) = self.bar.get() {
            b.finish_and_clear();
        }
    }
}
