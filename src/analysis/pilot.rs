//! What every pilot run shares (the step choice's pilots, [`super::autostep`], and the
//! cut-off's, [`super::cutoff`]): its window. A pilot is a [`super::RunRequest::pilot`].

/// Transient revolutions of a pilot run before its analysed window (started as the run is).
pub const PILOT_TRANSIENT: usize = 10;
/// Analysed revolutions of a pilot run (the shortest window, [`crate::time::plan::WINDOW_MULTIPLE`]).
pub const PILOT_WINDOW: usize = 6;
