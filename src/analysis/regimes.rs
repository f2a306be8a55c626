//! Regimes of a sweep: contiguous speed ranges of one Poincaré period, and the
//! quasi-resonance peaks within them (the paper's Sec. 4).

use super::{Regime, SpeedResults};

/// A contiguous speed range with one Poincaré period.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct RegimeRange {
    /// Period (0 = not periodic).
    pub period: usize,
    /// First speed ω/ω_n.
    pub from: f64,
    /// Last speed ω/ω_n.
    pub to: f64,
    /// The class of the range's runs ([`super::dynamics`]; `periodic` when `period` > 0).
    pub regime: Regime,
    /// A period above [`super::MAX_PERIOD`] found on the Poincaré points.
    pub long_period: Option<usize>,
    /// Dry whirl or dry whip (runs with stick, [`super::dry`]); the range's label then.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dry_rub: Option<super::dry::DryRub>,
}

impl RegimeRange {
    /// The range's regime in words: as [`regime_label`].
    pub fn label(&self) -> String {
        if let Some(d) = self.dry_rub {
            return d.label().into();
        }
        match (self.period, self.regime, self.long_period) {
            (0, Regime::Periodic, Some(q)) => regime_name(q),
            (0, Regime::QuasiPeriodic, _) => "quasi-periodic".into(),
            (0, Regime::Chaotic, _) => "chaotic".into(),
            (0, Regime::Diverging, _) => "diverging".into(),
            (0, _, _) => "not periodic (undetermined)".into(),
            (p, _, _) => regime_name(p),
        }
    }
}

/// Groups consecutive speeds with the same period and, not periodic, the same class
/// ([`super::dynamics`]); with stick, consecutive dry whirls (or whips) form one range whatever
/// their periods.
pub fn regime_ranges(speeds: &[SpeedResults]) -> Vec<RegimeRange> {
    let mut out: Vec<RegimeRange> = Vec::new();
    for r in speeds {
        let (regime, long_period) = (r.dynamics.regime, r.dynamics.long_period);
        let same = |last: &RegimeRange| match (last.dry_rub, r.dry_rub) {
            (Some(a), Some(b)) => a == b,
            (None, None) => {
                last.period == r.period && last.regime == regime && last.long_period == long_period
            }
            _ => false,
        };
        match out.last_mut() {
            Some(last) if same(last) => last.to = r.speed_ratio,
            _ => out.push(RegimeRange {
                period: r.period,
                from: r.speed_ratio,
                to: r.speed_ratio,
                regime,
                long_period,
                dry_rub: r.dry_rub,
            }),
        }
    }
    out
}

/// Speeds where the vertical orbit extent has a local maximum within a run of one period
/// (the paper's "quasi-resonance" peaks), as `(period, ω/ω_n)`.
pub fn quasi_resonances(speeds: &[SpeedResults]) -> Vec<(usize, f64)> {
    let size = |r: &SpeedResults| r.extents_nd[3] - r.extents_nd[2];
    let mut out = Vec::new();
    for rr in regime_ranges(speeds) {
        if rr.period == 0 {
            continue;
        }
        let group: Vec<&SpeedResults> = speeds
            .iter()
            .filter(|r| r.speed_ratio >= rr.from && r.speed_ratio <= rr.to)
            .collect();
        if group.len() < 3 {
            continue;
        }
        let (i, _) = group
            .iter()
            .enumerate()
            .fold((0, f64::NEG_INFINITY), |b, (i, r)| {
                if size(r) > b.1 {
                    (i, size(r))
                } else {
                    b
                }
            });
        if i > 0 && i + 1 < group.len() {
            out.push((rr.period, group[i].speed_ratio));
        }
    }
    out
}

/// "1×", "1/2×", … or "not periodic".
pub fn regime_name(period: usize) -> String {
    match period {
        0 => "not periodic".into(),
        1 => "1×".into(),
        p => format!("1/{p}×"),
    }
}

/// The regime of a run in words: "dry whirl" or "dry whip" for a run with stick in a backward
/// whirl of full contact ([`super::dry`]); else its period ([`regime_name`]); for a run that is not periodic
/// its class ([`super::dynamics`]) — "1/9×" and longer periods found on the Poincaré points,
/// "quasi-periodic", "chaotic", "diverging" (not periodic, and running away when continued), or
/// "not periodic (undetermined)".
pub fn regime_label(r: &SpeedResults) -> String {
    if let Some(d) = r.dry_rub {
        return d.label().into();
    }
    if r.period > 0 {
        return regime_name(r.period);
    }
    match (r.dynamics.regime, r.dynamics.long_period) {
        (Regime::Periodic, Some(q)) => regime_name(q),
        (Regime::QuasiPeriodic, _) => "quasi-periodic".into(),
        (Regime::Chaotic, _) => "chaotic".into(),
        (Regime::Diverging, _) => "diverging".into(),
        _ => "not periodic (undetermined)".into(),
    }
}

/// The regime classes of a map cell, in the order of their colours (the first five as before
/// the split of the responses that are not periodic).
pub const REGIME_CLASSES: [&str; 11] = [
    "no contact",
    "1×",
    "1/2×",
    "1/3×",
    "1/4× … 1/8×",
    "quasi-periodic",
    "chaotic",
    "not periodic (undetermined)",
    "1/9× and longer",
    "dry whirl",
    "dry whip",
];

/// The class of a run for a regime map (an index into [`REGIME_CLASSES`]): no contact in the
/// steady window, else by Poincaré period — 1, 2, 3, 4 to [`super::MAX_PERIOD`] — and, not
/// periodic, by [`super::dynamics`]: quasi-periodic, chaotic, undetermined, or a longer period
/// found on the Poincaré points; a run with stick in dry whirl or dry whip by that first.
pub fn regime_class(r: &SpeedResults) -> usize {
    if r.contact_fraction == 0.0 {
        return 0;
    }
    match r.dry_rub {
        Some(super::dry::DryRub::Whirl) => return 9,
        Some(super::dry::DryRub::Whip) => return 10,
        None => {}
    }
    match r.period {
        0 => match r.dynamics.regime {
            Regime::QuasiPeriodic => 5,
            Regime::Chaotic => 6,
            Regime::Periodic if r.dynamics.long_period.is_some() => 8,
            _ => 7,
        },
        1..=3 => r.period,
        _ => 4,
    }
}
