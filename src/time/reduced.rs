//! A reduced meshed stator in the loop (`[run.reduction] stators = true`,
//! [`crate::model::stator::reduce::ReducedStator`]): a [`DynBody`] in `q = [u_B; η]` whose
//! boundary coordinates are the contact DOFs' displacements. The contact reads and loads the
//! stator by its full DOF numbers, mapped to q here; frames get the whole field `u = T q`.

use super::body::DynBody;
use super::newmark::Alpha;
use crate::linalg::LinalgError;
use crate::model::stator::reduce::{ExpandScratch, ReducedStator};
use std::sync::Arc;

/// A Craig–Bampton stator integrated in its reduced coordinates.
#[derive(Debug)]
pub(crate) struct ReducedDyn {
    /// The reduced body (r DOF); its contact DOFs are the boundary coordinates `0..|B|`.
    pub(crate) body: DynBody,
    red: Arc<ReducedStator>,
    /// Full DOF → q index (`usize::MAX` for interior DOFs).
    q_of: Vec<usize>,
    /// Full-length view whose contact DOFs hold the current prediction (the contact reads
    /// only those).
    view: Vec<f64>,
    /// The whole field of the last frame, `u = T qⁿ`.
    pub(crate) field: Vec<f64>,
    scratch: ExpandScratch,
}

impl ReducedDyn {
    /// The reduced body with its step operator (`implicit`: the generalised-α coefficients,
    /// `None`: central differences) at step `dt` (s).
    pub(crate) fn new(
        red: &Arc<ReducedStator>,
        dt: f64,
        implicit: Option<Alpha>,
    ) -> Result<Self, LinalgError> {
        let nb = red.boundary.len();
        let cd: Vec<usize> = (0..nb).collect();
        let body = DynBody::new(&red.m, &red.c, &red.k, None, dt, &cd, implicit)?;
        let mut q_of = vec![usize::MAX; red.ndof];
        for (j, &d) in red.boundary.iter().enumerate() {
            q_of[d] = j;
        }
        Ok(Self {
            body,
            q_of,
            view: vec![0.0; red.ndof],
            field: vec![0.0; red.ndof],
            scratch: red.expand_scratch(),
            red: red.clone(),
        })
    }

    /// Copies the boundary coordinates of the prediction into the full-length view.
    #[inline]
    pub(crate) fn sync(&mut self) {
        for (j, &d) in self.red.boundary.iter().enumerate() {
            self.view[d] = self.body.u_next[j];
        }
    }

    /// Displacements by full DOF number (current at the contact DOFs).
    #[inline]
    pub(crate) fn disp(&self) -> &[f64] {
        &self.view
    }

    /// Displacement of contact DOFs `[x, y]` (full numbers) at the step's start, `qⁿ`'s
    /// boundary coordinates (m).
    pub(crate) fn start_disp(&self, dofs: [Option<usize>; 2]) -> [f64; 2] {
        dofs.map(|d| d.map_or(0.0, |d| self.body.u[self.q_of[d]]))
    }

    /// `(S⁻¹)_ab` of the reduced operator between contact DOFs `a`, `b` (full numbers).
    #[inline]
    pub(crate) fn flex(&self, a: usize, b: usize) -> f64 {
        self.body.flex(self.q_of[a], self.q_of[b])
    }

    /// A contact force `f` (N) on contact DOF `d` (full number).
    #[inline]
    pub(crate) fn apply(&mut self, d: usize, f: f64) {
        self.body.apply(self.q_of[d], f);
        self.sync();
    }

    /// Rebuilds the whole field of uⁿ for a frame (one solve with the interior factor).
    pub(crate) fn refresh(&mut self) {
        self.red
            .expand(&self.body.u, &mut self.field, &mut self.scratch);
    }
}
