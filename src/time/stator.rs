//! A stator's state in the loop ([`StatorDyn`]): a massless stator's [`Compliance`] (Eq. 49), a
//! body with mass ([`DynBody`], integrated like the rotor), or a body with mass in its
//! Craig–Bampton basis ([`ReducedDyn`]). The contact sees each through the same flexibility
//! `flex` and correction `apply`.

use super::body::DynBody;
use super::compliance::Compliance;
use super::reduced::ReducedDyn;
use crate::contact::target_disp;
use crate::math::V2;

/// A stator in the loop.
#[derive(Debug)]
pub(crate) enum StatorDyn {
    /// Massless (Eq. 49): the compliance of its contact DOFs.
    Massless(Box<Compliance>),
    /// With mass: integrated explicitly like the rotor.
    Massive(Box<DynBody>),
    /// With mass, in its Craig–Bampton basis (`[run.reduction] stators = true`).
    Reduced(Box<ReducedDyn>),
}

impl StatorDyn {
    /// Current (predicted) displacement of a target's DOFs `[x, y]` (m; 0 for a DOF it does
    /// not have). A massless stator's must be prepared ([`StatorDyn::prepare`]) unless it is
    /// undeformed.
    #[inline]
    pub(crate) fn target_disp(&self, dofs: [Option<usize>; 2]) -> V2 {
        match self {
            StatorDyn::Massless(c) => [
                dofs[0].map_or(0.0, |d| c.disp_at(d)),
                dofs[1].map_or(0.0, |d| c.disp_at(d)),
            ],
            StatorDyn::Massive(b) => target_disp(dofs, &b.u_next),
            StatorDyn::Reduced(r) => target_disp(dofs, r.disp()),
        }
    }
    /// Displacement of a target's DOFs `[x, y]` at the step's start, tₙ (m): a massless
    /// stator's under the last solve's forces (its DOFs prepared), a body's `uⁿ`.
    pub(crate) fn target_disp_start(&self, dofs: [Option<usize>; 2]) -> V2 {
        match self {
            StatorDyn::Massless(c) => [
                dofs[0].map_or(0.0, |d| c.disp_before(d)),
                dofs[1].map_or(0.0, |d| c.disp_before(d)),
            ],
            StatorDyn::Massive(b) => target_disp(dofs, &b.u),
            StatorDyn::Reduced(r) => r.start_disp(dofs),
        }
    }
    #[inline]
    pub(crate) fn flex(&self, a: usize, b: usize) -> f64 {
        match self {
            StatorDyn::Massless(c) => c.flex(a, b),
            StatorDyn::Massive(d) => d.flex(a, b),
            StatorDyn::Reduced(r) => r.flex(a, b),
        }
    }
    /// This stator's index of a target's DOFs for [`StatorDyn::block_at`]: a massless
    /// stator's positions in its packed compliance (the DOFs prepared), else the DOFs
    /// (`usize::MAX` for a DOF the target does not have).
    #[inline]
    pub(crate) fn key(&self, dofs: [Option<usize>; 2]) -> [usize; 2] {
        match self {
            StatorDyn::Massless(c) => c.locs(dofs),
            _ => dofs.map(|d| d.unwrap_or(usize::MAX)),
        }
    }
    /// The 2 × 2 flexibility block between two targets by their [`StatorDyn::key`]s (m/N; 0
    /// for a DOF a target does not have).
    #[inline]
    pub(crate) fn block_at(&self, ki: [usize; 2], kj: [usize; 2]) -> [[f64; 2]; 2] {
        if let StatorDyn::Massless(c) = self {
            return c.block_read(ki, kj);
        }
        let mut f = [[0.0; 2]; 2];
        for a in 0..2 {
            for b in 0..2 {
                if ki[a] != usize::MAX && kj[b] != usize::MAX {
                    f[a][b] = self.flex(ki[a], kj[b]);
                }
            }
        }
        f
    }
    /// Whether [`StatorDyn::block_at`] of two keys is exactly the transpose of the block with
    /// the keys swapped: a massless stator's, read from one packed symmetric compliance.
    #[inline]
    pub(crate) fn symmetric(&self) -> bool {
        matches!(self, StatorDyn::Massless(_))
    }
    #[inline]
    pub(crate) fn apply(&mut self, d: usize, f: f64) {
        match self {
            StatorDyn::Massless(c) => c.apply(d, f),
            StatorDyn::Massive(b) => b.apply(d, f),
            StatorDyn::Reduced(r) => r.apply(d, f),
        }
    }
    /// Makes `flex` available for a target's DOFs (massless: computes missing columns).
    #[inline]
    pub(crate) fn prepare(&mut self, dofs: [Option<usize>; 2]) {
        if let StatorDyn::Massless(c) = self {
            for d in dofs.into_iter().flatten() {
                c.ensure(d);
            }
        }
    }
    /// First DOF whose current value is not finite (massless: of a contact force, the only
    /// values the loop keeps).
    #[inline]
    pub(crate) fn first_non_finite(&self) -> Option<usize> {
        match self {
            StatorDyn::Massless(c) => c.first_non_finite(),
            StatorDyn::Massive(b) => b.u_next.iter().position(|v| !v.is_finite()),
            StatorDyn::Reduced(r) => r.body.u_next.iter().position(|v| !v.is_finite()),
        }
    }
}
