//! The discretisation error from runs at two or three steps (Richardson extrapolation at the
//! scheme's order), the ways two pairs' estimates are combined at a rub, and the error of a run
//! that never repeats ([`attractor_error`]).

/// The run's error from the finer pair's estimate `fine` = `|Q_h − Q_{h/2}|/(1 − 2^−p)` and the
/// (Δt, 2Δt) pair's `pair`: the weighted geometric mean `fine^¾ pair^¼`.
///
/// With `e(h) = C(h) h^p` and a coefficient that depends on the contact events' phase in the
/// step, `fine = e(h) |1 − C(h/2)/(2^p C(h))| / (1 − 2^−p)` is the run's own error to within
/// `(1 ± 2^−p|C(h/2)/C(h)|)/(1 − 2^−p)` — for p = 2 and C(h/2) within a factor 2 of C(h), 2/3 to
/// 5/3 of it — and cancels only when `C(h/2) ≈ 2^p C(h)`; the coarser pair, which never sees
/// `C(h)` (it mixes C(h) and C(2h)), is given a quarter of the logarithm to lift such a cancelled
/// fine pair.
pub fn combine_fine(fine: f64, pair: f64) -> f64 {
    fine.max(1e-300).powf(0.75) * pair.max(1e-300).powf(0.25)
}

/// The error of the finer run of a pair from their difference `d = |Q_f − Q_c|` (Richardson):
/// `d/|r^p − 1|`, `r = h_c/h_f` the ratio of the steps (below 1 when the companion is the finer),
/// `p` the order. With `Q_h = Q + C h^p`, `Q_f − Q_c = C h_f^p (1 − r^p)`.
pub fn richardson(d: f64, r: f64, p: f64) -> f64 {
    d / (r.powf(p) - 1.0).abs()
}

/// The run's error from the estimates of two step pairs at the scheme's order p: `fine` =
/// E₁ = `|Q_h − Q_2h|/(r₁^p − 1)` and `coarse` = E₂ = `|Q_2h − Q_4h|/((r₂^p − 1) r₁^p)` (the 2Δt
/// run's Richardson error, brought to Δt by the order). Returns their geometric mean √(E₁E₂),
/// or E₁ without a coarse pair.
///
/// At a rub the error is `e(h) = C(h) h^p` with the nominal order but a coefficient that
/// depends on where the contact events fall inside the steps (docs/VALIDATION.md §15): each
/// pair's estimate is the coefficient of two levels mixed, and either can cancel (E₁ ≪ e(h) when
/// `C(h) ≈ 2^p C(2h)`). E₁ and E₂ sample the coefficient at different event phases; the mean of
/// their logarithms halves the spread of log(estimate/error) when the phases are unrelated —
/// the factor-of-three goal is a bound on that logarithm.
pub fn combine_levels(fine: f64, coarse: Option<f64>) -> f64 {
    match coarse {
        Some(c) => (fine * c).sqrt(),
        None => fine,
    }
}

/// The error of a statistic of a run that never repeats (quasi-periodic or chaotic: its
/// extents), from its difference `d = |Q_h − Q_c|` from the companion at the step ratio
/// `r = h_c/h` and the sampling uncertainties `s_run`, `s_comp` of each run's finite window
/// (the halves' difference of the statistic, [`super::steady::AttractorStationarity`]), all
/// relative to the same scale: the time-step bias `max(0, d − s_run − s_comp)/|r^p − 1|` plus
/// `s_run`.
///
/// Two windows of an orbit that does not repeat are different samples of the same attractor:
/// their difference is the bias of the step, `C h^p (r^p − 1)`, plus the two samples'
/// deviations from the attractor's statistic, which do not scale with the step. Richardson on
/// the whole difference reads the sampling as an error of order p and divides it by `r^p − 1`
/// (a third at r = 2) — or, worse, the (2Δt, 4Δt) pair adds a third sample. What the run can
/// claim is its statistic up to the sampling of its window plus what is left of the step's
/// bias once the sampling is taken out.
pub fn attractor_error(d: f64, s_run: f64, s_comp: f64, r: f64, p: f64) -> f64 {
    richardson((d - s_run - s_comp).max(0.0), r, p) + s_run
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Q_h = Q + C h^p: the Richardson estimate of the finer run's error is exact, for a coarser
    /// companion (r = 2, 1.5) and for a finer one (r = ½, the error of the run being the coarser).
    #[test]
    fn richardson_is_exact_on_the_asymptotic_expansion() {
        let (q, c, p) = (1.25, -3.0e-2, 2.0);
        let qh = |h: f64| q + c * h.powf(p);
        for (h, r) in [(0.01, 2.0), (0.03, 1.5), (0.02, 0.5)] {
            let est = richardson((qh(h) - qh(r * h)).abs(), r, p);
            let true_err = (qh(h) - q).abs();
            assert!(
                (est - true_err).abs() <= 1e-9 * true_err,
                "{est} {true_err}"
            );
        }
    }

    /// With a constant coefficient both pairs give the run's error and so does their combination;
    /// without a coarse pair the fine pair's estimate is returned as it is.
    #[test]
    fn combining_two_exact_levels_keeps_the_error() {
        let (c, p) = (4.0e-3, 2.0);
        let e = |n: f64| c * n.powf(-p);
        let (n1, n2, n3) = (192.0, 128.0, 64.0);
        let (r1, r2) = (n1 / n2, n2 / n3);
        let fine = richardson((e(n1) - e(n2)).abs(), r1, p);
        let coarse = richardson((e(n2) - e(n3)).abs(), r2, p) / r1.powf(p);
        let both = combine_levels(fine, Some(coarse));
        assert!((both - e(n1)).abs() <= 1e-12 * e(n1));
        assert_eq!(combine_levels(fine, None), fine);
    }

    /// The case the second pair is for: a coefficient that depends on the step (the contact
    /// events' phase), C(h), C(2h), C(4h) = 1, 0.15625, 0.7890625 (× 1e-3): the fine pair's
    /// difference cancels to an eighth of the run's error, the coarse pair gives it exactly, and
    /// their geometric mean, e/√8, is within a factor 3 of it.
    #[test]
    fn the_coarse_pair_lifts_a_cancelled_fine_pair() {
        let p = 2.0;
        let h: f64 = 1.0 / 256.0;
        let c: [f64; 3] = [1.0e-3, 0.15625e-3, 0.7890625e-3];
        let e = [
            c[0] * h * h,
            c[1] * (2.0 * h).powi(2),
            c[2] * (4.0 * h).powi(2),
        ];
        let fine = richardson((e[0] - e[1]).abs(), 2.0, p);
        let coarse = richardson((e[1] - e[2]).abs(), 2.0, p) / 4.0;
        assert!((fine - e[0] / 8.0).abs() <= 1e-9 * e[0], "{fine} {}", e[0]);
        assert!((coarse - e[0]).abs() <= 1e-9 * e[0], "{coarse} {}", e[0]);
        let both = combine_levels(fine, Some(coarse));
        assert!((both - e[0] / 8f64.sqrt()).abs() <= 1e-9 * e[0]);
        assert!(both >= e[0] / 3.0 && both <= 3.0 * e[0], "{both} {}", e[0]);
    }

    /// The finer pair: with C(h/2) = C(h) the (Δt, Δt/2) estimate is the run's error exactly
    /// (finer companion, r = ½); with C(h/2) = 3C(h) it cancels to a third of it, and
    /// `fine^¾ pair^¼` with the (Δt, 2Δt) pair at C(2h) = 2C(h) (which reads 7/3 of the error)
    /// brings it to 0.54 of it; equal estimates combine to themselves.
    #[test]
    fn the_finer_pair_weighs_three_quarters() {
        let p = 2.0;
        let h: f64 = 1.0 / 300.0;
        let e = |c: f64, h: f64| c * h * h;
        let c = 2.0e-3;
        let exact = richardson((e(c, h) - e(c, h / 2.0)).abs(), 0.5, p);
        assert!((exact - e(c, h)).abs() <= 1e-12 * e(c, h));
        let cancelled = richardson((e(c, h) - e(3.0 * c, h / 2.0)).abs(), 0.5, p);
        assert!((cancelled - e(c, h) / 3.0).abs() <= 1e-12 * e(c, h));
        let pair = richardson((e(c, h) - e(2.0 * c, 2.0 * h)).abs(), 2.0, p);
        let both = combine_fine(cancelled, pair);
        assert!((pair - 7.0 / 3.0 * e(c, h)).abs() <= 1e-12 * e(c, h));
        assert!((both / e(c, h) - 0.5422).abs() < 1e-4, "{both}");
        let expected = cancelled.powf(0.75) * pair.powf(0.25);
        assert!((both - expected).abs() <= 1e-12 * expected);
        assert!((combine_fine(4e-5, 4e-5) - 4e-5).abs() <= 1e-18);
    }

    /// A difference within the two windows' sampling is no step error: the estimate is the
    /// run's sampling; beyond it, the excess is the step's bias, Richardson-scaled.
    #[test]
    fn the_sampling_of_a_window_is_not_a_step_error() {
        assert_eq!(attractor_error(3e-3, 2e-3, 2e-3, 2.0, 2.0), 2e-3);
        let e = attractor_error(1e-2, 2e-3, 2e-3, 2.0, 2.0);
        assert!((e - (6e-3 / 3.0 + 2e-3)).abs() < 1e-15, "{e}");
        // Without sampling it is the Richardson estimate.
        assert_eq!(
            attractor_error(3e-3, 0.0, 0.0, 2.0, 2.0),
            richardson(3e-3, 2.0, 2.0)
        );
    }
}
