//! Pictures drawn together: each is staged in the output folder in order, then they are drawn
//! in parallel (rayon), since a picture (rasterising its lines, encoding the PNG) uses one
//! thread and a command's pictures do not depend on one another.

use super::OutDir;
use crate::error::Result;
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// One picture: it writes its file at the staged path it is given.
type Draw<'a> = Box<dyn FnOnce(&Path) -> Result<()> + Send + 'a>;

/// Pictures staged in an [`OutDir`] and drawn by [`Drawings::draw`].
#[derive(Default)]
pub struct Drawings<'a> {
    jobs: Vec<(PathBuf, Draw<'a>)>,
}

impl std::fmt::Debug for Drawings<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list()
            .entries(self.jobs.iter().map(|(p, _)| p))
            .finish()
    }
}

impl<'a> Drawings<'a> {
    /// No pictures yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Stages `name` in `out` ([`OutDir::stage`]) and keeps `draw`, which writes the picture
    /// at the staged path, for [`Drawings::draw`].
    ///
    /// # Errors
    /// As [`OutDir::stage`] (a name that is not confined, a folder that cannot be made).
    pub fn add(
        &mut self,
        out: &mut OutDir,
        name: &str,
        draw: impl FnOnce(&Path) -> Result<()> + Send + 'a,
    ) -> Result<()> {
        let p = out.stage(name)?;
        self.jobs.push((p, Box::new(draw)));
        Ok(())
    }

    /// Draws every picture, in parallel; every one is drawn even when one fails, and the
    /// first failure (in the order they were added) is returned.
    ///
    /// # Errors
    /// The first picture's error.
    pub fn draw(self) -> Result<()> {
        let res: Vec<Result<()>> = self
            .jobs
            .into_par_iter()
            .map(|(p, draw)| draw(&p))
            .collect();
        res.into_iter().collect()
    }
}
