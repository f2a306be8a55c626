//! Archard wear in the loop (`[stator.wear]`, `scene::wear`): after each contact solve, every
//! pair carrying force on a target that wears recedes by
//!
//! `Δh = k A p |ζ| / a`   (m),
//!
//! `k A` the wear coefficient times the wear magnification, `p` the pair's normal force (N),
//! `ζ` its slip over the step (m, the section's surface over the stator's material point,
//! docs/STICK.md §1: 0 while it sticks) and `a` the target's tributary area (m²). The worn depth
//! is added to the target's gap from the next step on (`select::Pairs::worn`), so the clearance
//! opens where the rotor rubs. The worn volume `Σ Δh a = k A Σ p |ζ|` is Archard's law summed
//! step by step.

use super::stepper::Stepper;
use super::workspace::Held;

impl Stepper<'_> {
    /// The wear of the step just solved (`held`: the collocated scheme's static solve of the
    /// rotor held at tₙ, whose slip is over tₙ₋₁ → tₙ; else the step n → n + 1 at time `t`),
    /// added to the pairs' worn depths and the run's worn volume.
    pub(crate) fn wear_step(&mut self, held: Held, n: usize, t: f64) {
        if !self.pairs.any_wear {
            return;
        }
        let (dphi, kappa) = self.spin_step(held, n, t);
        let dphi = dphi - kappa * self.ws.friction_torque;
        for i in 0..self.ws.sel.len() {
            let (ci, p) = (self.ws.sel[i], self.ws.pvec[i]);
            let (rate, area) = self.pairs.wear[ci];
            if p <= 0.0 || rate == 0.0 || area <= 0.0 {
                continue;
            }
            let zeta = self.slip(held, (ci, n), self.ws.us[i], dphi).abs();
            let volume = rate * p * zeta;
            self.pairs.worn[ci] += volume / area;
            self.worn_volume += volume;
        }
    }

    /// The run's removed volume — worn by Archard's law and cut off abradable coatings — (m³)
    /// and the largest depth a target receded (m) so far.
    pub(crate) fn wear_state(&self) -> [f64; 2] {
        let deepest = self.pairs.worn.iter().fold(0.0_f64, |m, h| m.max(*h));
        [self.worn_volume + self.abradable[0], deepest]
    }
}
