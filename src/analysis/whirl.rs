//! Whirl direction from the full spectrum of the orbit `z = x + iy`
//! ([`crate::signal::FullSpectrum`]): the forward and backward 1× lines, the dominant line with
//! its sign, and the strongest lines a full-spectrum cascade draws — for a run at one speed
//! ([`whirl_lines`]) and, window by window, for a speed transient
//! ([`super::waterfall::full_waterfall`]).
//!
//! **Sign convention.** Frequencies are signed: positive is *forward* whirl (the orbit turns
//! in the sense of the spin Ω, counter-clockwise seen from +z), negative is *backward* whirl
//! (against the spin — dry whip, rolling). Orders are `f/Ω`; an amplitude is the radius of the
//! circular component at that frequency.

use crate::math::V2;
use crate::signal::{FullSpectrum, Line};
use serde::{Deserialize, Serialize};

/// Lines kept per run (or per transient window): the strongest, strongest first.
pub const WHIRL_LINES: usize = 8;
/// Lines weaker than this fraction of the strongest are not kept.
pub const LINE_FLOOR: f64 = 1e-3;
/// The mirror-to-dominant amplitude ratio above which a whirl is [`WhirlDirection::Planar`]:
/// `(a − b)/(a + b) < 0.05`.
pub const PLANAR_RATIO: f64 = 0.95 / 1.05;

/// The sense of the dominant whirl.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WhirlDirection {
    /// With the spin: the dominant line is at a positive frequency.
    Forward,
    /// Against the spin: the dominant line is at a negative frequency.
    Backward,
    /// Neither: the dominant line's mirror at the opposite frequency is at least
    /// [`PLANAR_RATIO`] of it — at that frequency the orbit is a straight line (its ellipse's
    /// minor axis under 5 % of its major), e.g. a rod stator's bouncing.
    Planar,
    /// No line (the orbit is a point).
    NoWhirl,
}

impl WhirlDirection {
    /// The direction of a line at the signed order `order` of amplitude `amp` whose mirror at
    /// `−order` has amplitude `mirror`.
    pub fn of(order: f64, amp: f64, mirror: f64) -> Self {
        if amp.is_nan() || amp <= 0.0 || order == 0.0 {
            Self::NoWhirl
        } else if mirror >= PLANAR_RATIO * amp {
            Self::Planar
        } else if order > 0.0 {
            Self::Forward
        } else {
            Self::Backward
        }
    }

    /// `forward`, `backward` or `no_whirl` (as in the CSV tables and summary.json).
    pub fn name(self) -> &'static str {
        match self {
            Self::Forward => "forward",
            Self::Backward => "backward",
            Self::Planar => "planar",
            Self::NoWhirl => "no_whirl",
        }
    }
}

/// The whirl of a steady window: its full spectrum's 1× lines and strongest lines.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WhirlLines {
    /// Forward 1× amplitude (the `e^{+iΩt}` circle's radius) / |Z0|, exact (on its bin).
    pub forward_1x_nd: f64,
    /// Backward 1× amplitude (the `e^{−iΩt}` circle's radius) / |Z0|, exact.
    pub backward_1x_nd: f64,
    /// Signed order `f/Ω` of the strongest line (+ forward, − backward); 0 without one.
    pub dominant_order: f64,
    /// Its amplitude / |Z0|.
    pub dominant_nd: f64,
    /// The sense of the strongest line.
    pub direction: WhirlDirection,
    /// The strongest [`WHIRL_LINES`] lines above [`LINE_FLOOR`] of the strongest, strongest
    /// first: `(signed order f/Ω, amplitude / |Z0|)`, located between bins where they fall
    /// there ([`FullSpectrum::peaks`]).
    pub lines: Vec<(f64, f64)>,
}

/// The whirl of `window` (points / |Z0|, `revolutions` whole revolutions, so that bin `k` is
/// the order `k / revolutions` and 1× is the bin ±`revolutions`), and its full spectrum.
pub fn whirl_lines(window: &[V2], revolutions: usize) -> (WhirlLines, FullSpectrum) {
    let s = FullSpectrum::new(window);
    let r = revolutions.max(1) as f64;
    let lines: Vec<(f64, f64)> = s
        .peaks(WHIRL_LINES, LINE_FLOOR)
        .iter()
        .map(|l: &Line| (l.bin / r, l.amp))
        .collect();
    let (order, amp) = lines.first().copied().unwrap_or((0.0, 0.0));
    let mirror = lines
        .iter()
        .find(|(o, _)| ((o + order) * r).abs() < 0.5)
        .map_or(0.0, |l| l.1);
    let one = revolutions as isize;
    let w = WhirlLines {
        forward_1x_nd: if revolutions > 0 { s.amp(one) } else { 0.0 },
        backward_1x_nd: if revolutions > 0 { s.amp(-one) } else { 0.0 },
        dominant_order: order,
        dominant_nd: amp,
        direction: WhirlDirection::of(order, amp, mirror),
        lines,
    };
    (w, s)
}

/// The full spectrum of a window of `revolutions` revolutions as `(signed order f/Ω, amplitude)`
/// per bin in ascending order, within `|f/Ω| ≤ max_order`.
pub fn signed_orders(s: &FullSpectrum, revolutions: usize, max_order: f64) -> Vec<(f64, f64)> {
    let r = revolutions.max(1) as f64;
    s.signed()
        .map(|(k, a)| (k as f64 / r, a))
        .filter(|(o, _)| o.abs() <= max_order + 1e-9)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn an_elliptic_orbit_reads_its_split_and_its_sense() {
        // 6 revolutions, 64 samples each: x = 0.9 cos θ, y = −0.5 sin θ — traced backward,
        // so 0.2 forward and 0.7 backward; plus a forward ½× of 0.1.
        let z: Vec<V2> = (0..384)
            .map(|i| {
                let t = 2.0 * PI * i as f64 / 64.0;
                [
                    0.9 * t.cos() + 0.1 * (t / 2.0).cos(),
                    -0.5 * t.sin() + 0.1 * (t / 2.0).sin(),
                ]
            })
            .collect();
        let (w, _) = whirl_lines(&z, 6);
        assert!((w.forward_1x_nd - 0.2).abs() < 1e-12, "{w:?}");
        assert!((w.backward_1x_nd - 0.7).abs() < 1e-12, "{w:?}");
        assert_eq!(w.direction, WhirlDirection::Backward);
        assert_eq!((w.dominant_order, w.lines.len()), (-1.0, 3));
        assert!((w.lines[2].0 - 0.5).abs() < 1e-12 && (w.lines[2].1 - 0.1).abs() < 1e-12);
        let (still, _) = whirl_lines(&[[1.0, 2.0]; 64], 1);
        assert_eq!(still.direction, WhirlDirection::NoWhirl);
        // A straight line (b = 0): forward and backward equal.
        let line: Vec<V2> = (0..64)
            .map(|i| [0.0, (PI * i as f64 / 32.0).cos()])
            .collect();
        let (planar, _) = whirl_lines(&line, 1);
        assert_eq!(planar.direction, WhirlDirection::Planar);
        assert!((planar.forward_1x_nd - 0.5).abs() < 1e-12);
    }
}
