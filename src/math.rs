//! Small dense kernels shared by the contact solver and the models.
//!
//! Everything is `f64` (SI units). 2-vectors are plain `[f64; 2]` in the station plane: x
//! horizontal, y vertical, the rotor axis z pointing toward the viewer (rotor spins
//! counter-clockwise seen from +z when Ω > 0).

/// A vector in the station plane `[x, y]` (m, N, … depending on context).
pub type V2 = [f64; 2];

/// Dot product of two plane vectors.
#[inline]
pub fn dot(a: V2, b: V2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// `(sin x, cos x)`, both from one call of the C library's `sincos` where the compiler
/// fuses them (the same values as `sin` and `cos` apart: the two share their argument
/// reduction, which is then done once). Kept out of line so that both results are used in one
/// block, which is what the fusion needs.
#[inline(never)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    x.sin_cos()
}

/// Euclidean norm of a plane vector, `√(x² + y²)`: a plain square root, not `hypot` (whose
/// guard against overflow of x² took 5.7 % of a paper sweep's CPU); the plane's
/// vectors are lengths in metres and forces in newtons, far inside the range where x² neither
/// overflows nor underflows to a wrong result.
#[inline]
pub fn norm(a: V2) -> f64 {
    (a[0] * a[0] + a[1] * a[1]).sqrt()
}

/// `Ω ẑ × n` for a unit normal `n` in the plane: `sign(Ω)·(−n_y, n_x)`.
///
/// This is the paper's tangent `a = Ω × n` (Eq. 10) normalised: the direction in which the rotor
/// surface moves at the contact point. For Ω = 0 it returns the counter-clockwise tangent.
#[inline]
pub fn spin_tangent(omega: f64, n: V2) -> V2 {
    let s = if omega < 0.0 { -1.0 } else { 1.0 };
    [-s * n[1], s * n[0]]
}

/// Dense LU factorisation with partial pivoting of the `n×n` row-major matrix stored in
/// `a[..n*n]`, in place; `piv[..n]` receives the row permutation.
///
/// Returns `false` when a pivot is smaller than `tiny` times the largest entry (singular).
/// Allocation free: the caller owns every buffer.
#[allow(clippy::needless_range_loop)] // dense index kernel
pub fn lu_in_place(a: &mut [f64], n: usize, piv: &mut [usize], tiny: f64) -> bool {
    let scale = a[..n * n].iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if scale == 0.0 {
        return n == 0;
    }
    for k in 0..n {
        let mut p = k;
        let mut best = a[k * n + k].abs();
        for i in k + 1..n {
            let v = a[i * n + k].abs();
            if v > best {
                best = v;
                p = i;
            }
        }
        piv[k] = p;
        if best <= tiny * scale {
            return false;
        }
        if p != k {
            for j in 0..n {
                a.swap(k * n + j, p * n + j);
            }
        }
        let d = a[k * n + k];
        // Row slices: the update of each row below the pivot vectorises.
        let (top, below) = a[..n * n].split_at_mut((k + 1) * n);
        let pivot_row = &top[k * n + k + 1..(k + 1) * n];
        for row in below.chunks_exact_mut(n) {
            let f = row[k] / d;
            row[k] = f;
            if f != 0.0 {
                for (x, y) in row[k + 1..].iter_mut().zip(pivot_row) {
                    *x -= f * y;
                }
            }
        }
    }
    true
}

/// Solves `A x = b` in place (`b` becomes `x`) with the factors from [`lu_in_place`].
#[allow(clippy::needless_range_loop)] // dense index kernel
pub fn lu_solve(a: &[f64], n: usize, piv: &[usize], b: &mut [f64]) {
    for k in 0..n {
        b.swap(k, piv[k]);
    }
    for i in 0..n {
        let mut s = b[i];
        for j in 0..i {
            s -= a[i * n + j] * b[j];
        }
        b[i] = s;
    }
    for i in (0..n).rev() {
        let mut s = b[i];
        for j in i + 1..n {
            s -= a[i * n + j] * b[j];
        }
        b[i] = s / a[i * n + i];
    }
}

/// Least-squares slope of `log y` against `log x` (the observed convergence order when `x` is a
/// step size and `y` an error). Points with non-positive or non-finite values are ignored;
/// returns NaN when fewer than two remain.
pub fn loglog_slope(x: &[f64], y: &[f64]) -> f64 {
    let pts: Vec<(f64, f64)> = x
        .iter()
        .zip(y)
        .filter(|(a, b)| **a > 0.0 && **b > 0.0 && a.is_finite() && b.is_finite())
        .map(|(a, b)| (a.ln(), b.ln()))
        .collect();
    if pts.len() < 2 {
        return f64::NAN;
    }
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    sxy / sxx
}

/// 128-bit FNV-1a: a stable content hash for cache keys and scene identities (not
/// cryptographic). Every [`Fnv128::write`] ends with a separator byte, so that the fields
/// `("ab", "c")` and `("a", "bc")` hash differently.
#[derive(Debug, Clone, Copy)]
pub struct Fnv128(u128);

impl Default for Fnv128 {
    fn default() -> Self {
        Self::new()
    }
}

impl Fnv128 {
    /// The FNV-1a offset basis.
    pub fn new() -> Self {
        Fnv128(0x6c62272e07bb014262b821756295c58d)
    }
    /// Hashes one field.
    pub fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 ^= *b as u128;
            self.0 = self.0.wrapping_mul(0x0000000001000000000000000000013B);
        }
        self.0 ^= 0xff;
        self.0 = self.0.wrapping_mul(0x0000000001000000000000000000013B);
    }
    /// The hash as 32 hexadecimal digits.
    pub fn hex(&self) -> String {
        format!("{:032x}", self.0)
    }
}

/// `y(x)` linearly interpolated in the samples `(xs, ys)` (`xs` ascending), held at the end
/// values outside them; 0 for no samples.
pub fn interp_linear(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    let n = xs.len().min(ys.len());
    if n == 0 {
        return 0.0;
    }
    let k = xs[..n].partition_point(|v| *v < x);
    if k == 0 {
        return ys[0];
    }
    if k == n {
        return ys[n - 1];
    }
    let (x0, x1) = (xs[k - 1], xs[k]);
    let f = if x1 > x0 { (x - x0) / (x1 - x0) } else { 0.0 };
    ys[k - 1] + f * (ys[k] - ys[k - 1])
}

/// Greatest common divisor; `gcd(0, b) = b`, so a fold from 0 over intervals gives their
/// common interval (0 when every interval is 0).
pub fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// Least common multiple; `lcm(a, 0) = 0`.
pub fn lcm(a: usize, b: usize) -> usize {
    if b == 0 {
        0
    } else {
        a / gcd(a, b) * b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lcm_of_the_window_multiple_and_a_period() {
        assert_eq!(lcm(6, 1), 6);
        assert_eq!(lcm(6, 4), 12);
        assert_eq!(lcm(6, 9), 18);
        assert_eq!(lcm(6, 0), 0);
        assert_eq!(lcm(0, 0), 0);
    }

    #[test]
    fn lu_solves_pivoting_system() {
        let mut a = vec![0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 2.0, 0.0, 3.0];
        let orig = a.clone();
        let mut piv = [0; 3];
        assert!(lu_in_place(&mut a, 3, &mut piv, 1e-14));
        let x_true = [1.0, -2.0, 0.5];
        let mut b: Vec<f64> = (0..3)
            .map(|i| (0..3).map(|j| orig[i * 3 + j] * x_true[j]).sum())
            .collect();
        lu_solve(&a, 3, &piv, &mut b);
        for i in 0..3 {
            assert!((b[i] - x_true[i]).abs() < 1e-14);
        }
    }

    #[test]
    fn slope_of_power_law() {
        let x = [1.0, 0.5, 0.25, 0.125];
        let y: Vec<f64> = x.iter().map(|v: &f64| 3.0 * v.powf(2.0)).collect();
        assert!((loglog_slope(&x, &y) - 2.0).abs() < 1e-12);
    }

    #[test]
    fn tangent_follows_spin() {
        // Contact on top (+y): a CCW rotor surface moves toward −x there.
        assert_eq!(spin_tangent(10.0, [0.0, 1.0]), [-1.0, 0.0]);
        assert_eq!(spin_tangent(-10.0, [0.0, 1.0]), [1.0, 0.0]);
    }
}
