//! The Jacobian `∂P/∂y` of pseudo-arclength's map (`super` module docs): the variational
//! monodromy of the scheme's step (`periodic::variational_over`) in the branch's `(u, v)`
//! layout where the step has its linearisation, central differences of whole maps otherwise;
//! and the correctors again with differences where the variational Jacobian's Newton fails (a
//! kink of the map near a grazing, where the one-sided derivative makes Newton cycle).

use super::{periodic, Arc, FD_STEP};
use crate::error::Result;
use nalgebra::{DMatrix, DVector};

impl Arc<'_> {
    /// `∂P/∂y` at `(y, ν)` (unscaled): `S (∂P/∂x) T` of the variational monodromy in the
    /// stepper's layout `x = (uᴺ, uᴺ⁻¹)`, `T = ∂x/∂y` ([`from_uv`]) and `S = ∂y/∂x`
    /// ([`to_uv`]) both at the map's one Δt; by differences of whole maps where the step has
    /// no linearisation or a retry asks for them.
    pub(super) fn dp_dy(&mut self, y: &[f64], v: f64) -> Result<DMatrix<f64>> {
        self.linearised = false;
        if !self.differences_only {
            let p = self.prep(v)?;
            let start = self.start(y, p.plan.dt)?;
            if let Some(jx) = periodic::variational_over(&p, &start)? {
                self.steps += p.plan.steps as u64;
                self.linearised = true;
                return Ok(self.in_uv(&jx, p.plan.dt));
            }
        }
        self.dp_dy_differences(y, v)
    }

    /// `S J T`: the Jacobian `j` of the `(uᴺ, uᴺ⁻¹)` layout in the `(u, v)` layout at `dt`.
    fn in_uv(&self, j: &DMatrix<f64>, dt: f64) -> DMatrix<f64> {
        let n = j.nrows();
        let mut out = DMatrix::zeros(n, n);
        let mut e = vec![0.0; n];
        for c in 0..n {
            e[c] = 1.0;
            let jt = j * DVector::from_vec(from_uv(&e, &self.sizes, dt));
            e[c] = 0.0;
            out.set_column(c, &DVector::from_vec(to_uv(jt.as_slice(), &self.sizes, dt)));
        }
        out
    }

    /// Newton in `y` at a fixed ν from `y`; again with differences of whole maps where it fails
    /// with the variational Jacobian.
    pub(super) fn correct_at(&mut self, y: Vec<f64>, v: f64) -> Result<(Vec<f64>, usize)> {
        match self.correct_at_once(y.clone(), v) {
            Err(_) if self.linearised => self.by_differences(|a| a.correct_at_once(y, v)),
            r => r,
        }
    }

    /// The pseudo-arclength corrector from `wp` along `t`; again with differences of whole
    /// maps where it fails with the variational Jacobian.
    pub(super) fn corrector(&mut self, wp: &[f64], t: &[f64]) -> Result<Option<(Vec<f64>, usize)>> {
        match self.corrector_once(wp, t) {
            Ok(None) | Err(_) if self.linearised => {
                self.by_differences(|a| a.corrector_once(wp, t))
            }
            r => r,
        }
    }

    /// `f` with the Jacobians by differences of whole maps.
    fn by_differences<R>(&mut self, f: impl FnOnce(&mut Self) -> R) -> R {
        self.differences_only = true;
        let r = f(self);
        self.differences_only = false;
        r
    }

    /// `∂P/∂y` at `(y, ν)` by central differences of whole maps (unscaled).
    fn dp_dy_differences(&mut self, y: &[f64], v: f64) -> Result<DMatrix<f64>> {
        let n = y.len();
        let mut m = DMatrix::zeros(n, n);
        for j in 0..n {
            let h = FD_STEP * self.scale[j];
            let (mut a, mut b) = (y.to_vec(), y.to_vec());
            a[j] += h;
            b[j] -= h;
            let (pa, pb) = (self.map(&a, v)?, self.map(&b, v)?);
            for i in 0..n {
                m[(i, j)] = (pa[i] - pb[i]) / (2.0 * h);
            }
        }
        Ok(m)
    }
}

/// `(uᴺ, uᴺ⁻¹)` per body → `(u, v)`, `v = (uᴺ − uᴺ⁻¹)/dt`.
pub(super) fn to_uv(x: &[f64], sizes: &[usize], dt: f64) -> Vec<f64> {
    let mut y = x.to_vec();
    let mut at = 0;
    for &n in sizes {
        for i in 0..n {
            y[at + n + i] = (x[at + i] - x[at + n + i]) / dt;
        }
        at += 2 * n;
    }
    y
}

/// `(u, v)` per body → `(uᴺ, uᴺ⁻¹)` at step `dt`.
pub(super) fn from_uv(y: &[f64], sizes: &[usize], dt: f64) -> Vec<f64> {
    let mut x = y.to_vec();
    let mut at = 0;
    for &n in sizes {
        for i in 0..n {
            x[at + n + i] = y[at + i] - dt * y[at + n + i];
        }
        at += 2 * n;
    }
    x
}
