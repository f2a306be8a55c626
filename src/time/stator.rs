//! A stator's state in the loop ([`StatorDyn`]): a massless stator's [`Compliance`] (Eq. 49), a
//! body with mass ([`DynBody`], integrated like the rotor), or a body with mass in its
//! Craig–Bampton basis ([`ReducedDyn`]). The contact sees each through the same flexibility
//! `flex` and correction `apply`.

use super::body::DynBody;
use super::compliance::Compliance;
use super::reduced::ReducedDyn;

/// A stator in the loop.
#[derive(Debug)]
pub(crate) enum StatorDyn {
    /// Massless (Eq. 49): the compliance of its contact DOFs.
    Massless(Compliance),
    /// With mass: integrated explicitly like the rotor.
    Massive(Box<DynBody>),
    /// With mass, in its Craig–Bampton basis (`[run.reduction] stators = true`).
    Reduced(Box<ReducedDyn>),
}

impl StatorDyn {
    /// Current (predicted) displacement vector.
    #[inline]
    pub(crate) fn disp(&self) -> &[f64] {
        match self {
            StatorDyn::Massless(c) => &c.u,
            StatorDyn::Massive(b) => &b.u_next,
            StatorDyn::Reduced(r) => r.disp(),
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
    /// First DOF whose current value is not finite (massless: the contact DOFs, the only ones
    /// the loop updates).
    #[inline]
    pub(crate) fn first_non_finite(&self) -> Option<usize> {
        match self {
            StatorDyn::Massless(c) => c.cd.iter().copied().find(|&d| !c.u[d].is_finite()),
            StatorDyn::Massive(b) => b.u_next.iter().position(|v| !v.is_finite()),
            StatorDyn::Reduced(r) => r.body.u_next.iter().position(|v| !v.is_finite()),
        }
    }
}
