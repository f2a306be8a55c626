//! Regimes of a sweep: contiguous speed ranges of one Poincaré period, and the
//! quasi-resonance peaks within them (the paper's Sec. 4).

use super::SpeedResults;

/// A contiguous speed range with one Poincaré period.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct RegimeRange {
    /// Period (0 = not periodic).
    pub period: usize,
    /// First speed ω/ω_n.
    pub from: f64,
    /// Last speed ω/ω_n.
    pub to: f64,
}

/// Groups consecutive speeds with the same period.
pub fn regime_ranges(speeds: &[SpeedResults]) -> Vec<RegimeRange> {
    let mut out: Vec<RegimeRange> = Vec::new();
    for r in speeds {
        match out.last_mut() {
            Some(last) if last.period == r.period => last.to = r.speed_ratio,
            _ => out.push(RegimeRange {
                period: r.period,
                from: r.speed_ratio,
                to: r.speed_ratio,
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

/// The regime classes of a map cell, in the order of their colours.
pub const REGIME_CLASSES: [&str; 6] = [
    "no contact",
    "1×",
    "1/2×",
    "1/3×",
    "1/4× … 1/8×",
    "quasi-periodic or chaotic",
];

/// The class of a run for a regime map (an index into [`REGIME_CLASSES`]): no contact in the
/// steady window, else by Poincaré period — 1, 2, 3, 4 to [`super::MAX_PERIOD`], or not
/// periodic.
pub fn regime_class(r: &SpeedResults) -> usize {
    if r.contact_fraction == 0.0 {
        return 0;
    }
    match r.period {
        0 => 5,
        1..=3 => r.period,
        _ => 4,
    }
}
