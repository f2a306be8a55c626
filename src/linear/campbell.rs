//! Campbell diagram: the damped modes of [`super::modes::modal`] followed over the spin
//! speed, and the critical speeds where they cross the 1× line.
//!
//! # Tracking
//!
//! From one speed Ω_a to the next Ω_b every track (a mode at Ω_a, with its slope dω_d/dΩ)
//! is matched to one of the `2·nmodes + 4` lowest modes at Ω_b by the cost
//!
//! `c = (1 − MAC) + |ω_b − ω_pred| / ω_pred`,  `ω_pred = ω_a + (dω_d/dΩ)(Ω_b − Ω_a)`,
//!
//! where the MAC ([`mode_mac`]) compares the full complex shapes — displacements, rotations,
//! axial and torsional DOFs — so a backward and a forward mode, or a bending and a torsional
//! mode, never match each other, and the frequency term keeps a track on its own line when
//! shapes are alike. Pairs are assigned cheapest first (each track and each mode once). A
//! match is *ambiguous* when a track's cost exceeds [`AMBIGUOUS_COST`] or its second-best
//! candidate is within [`AMBIGUOUS_MARGIN`] of it; the step is then halved (up to
//! [`MAX_HALVINGS`] times) and tracked through the intermediate speeds, which are solved but not
//! reported. A track that still finds no candidate below [`LOST_COST`] is `NaN` at that speed
//! and keeps its last mode for the next one.
//!
//! The undamped basis of the modal solve ([`ModalBasis`]) is built once for the whole diagram
//! when the bearings are not tabulated over speed (K independent of Ω), else at every speed.
//!
//! # Critical speeds
//!
//! A track crossing the 1× line `ω_d = Ω` between two speeds of the diagram (linear
//! interpolation) is a critical speed, with the whirl of the mode at the speed after the
//! crossing: only crossings inside the diagram's speed range are found.

use super::modes::{modal, modal_in, mode_label, mode_mac, ModalBasis, Mode};
use super::modes::{ModeKind, Whirl};
use crate::error::ModelError;
use crate::model::Rotor;
use crate::scene::SpeedUnit;
use serde::Serialize;

/// Track cost above which a match is refined.
pub const AMBIGUOUS_COST: f64 = 0.2;
/// Second-best candidate closer than this to the best: refined.
pub const AMBIGUOUS_MARGIN: f64 = 0.1;
/// Most halvings of one step of the diagram (a step is cut into at most 2^this sub-steps).
pub const MAX_HALVINGS: u32 = 8;
/// Track cost above which the track is lost at that speed (after refinement).
pub const LOST_COST: f64 = 0.9;

/// A mode followed over speed.
#[derive(Debug, Clone, Serialize)]
pub struct Track {
    /// Label, e.g. "1 FW", "3 torsional" (whirl at the highest speed).
    pub label: String,
    /// Whirl at the highest speed.
    pub whirl: Whirl,
    /// Kind at the highest speed.
    pub kind: ModeKind,
    /// ω_d (rad/s) per speed of the diagram (`NaN` where lost).
    pub omega_d: Vec<f64>,
    /// Log decrement per speed.
    pub log_dec: Vec<f64>,
    /// Whirl per speed.
    pub whirls: Vec<Whirl>,
}

/// A critical speed: a track crossing the 1× line ω_d = Ω inside the diagram's speed range.
/// Lateral (forward or backward) crossings are the unbalance critical speeds; axial and
/// torsional crossings are listed too (the unbalance does not excite them in the linear model,
/// but a once-per-revolution rub force or friction torque does).
#[derive(Debug, Clone, Serialize)]
pub struct CriticalSpeed {
    /// Track label.
    pub mode: String,
    /// Whirl of the mode at the crossing (at the diagram's speed after it).
    pub whirl: Whirl,
    /// Kind.
    pub kind: ModeKind,
    /// Spin speed (rad/s).
    pub speed: f64,
    /// The same in rpm.
    pub rpm: f64,
}

/// Campbell diagram results.
#[derive(Debug, Clone, Serialize)]
pub struct CampbellResults {
    /// Spin speeds (rad/s).
    pub speeds: Vec<f64>,
    /// Tracked modes.
    pub tracks: Vec<Track>,
    /// Crossings with the 1× line.
    pub critical_speeds: Vec<CriticalSpeed>,
    /// Intermediate speeds solved where matching was ambiguous (not in `speeds`).
    pub refined_speeds: usize,
}

/// One track's state between speeds: its last mode, the slope dω_d/dΩ, and whether it was
/// lost at the last speed.
#[derive(Debug, Clone)]
struct State {
    mode: Mode,
    slope: f64,
    lost: bool,
}

/// The tracker: the rotor, how many candidates per speed, and the count of refinements.
struct Tracker<'a> {
    rotor: &'a Rotor,
    /// The undamped basis of every speed when K does not depend on Ω.
    basis: Option<ModalBasis>,
    candidates: usize,
    tiny: f64,
    refined: usize,
}

impl Tracker<'_> {
    /// Modes at Ω (a tiny spin instead of 0, so that pairs start split the way they go).
    fn solve(&self, omega: f64) -> Result<Vec<Mode>, ModelError> {
        let w = if omega == 0.0 { self.tiny } else { omega };
        Ok(match &self.basis {
            Some(b) => modal_in(self.rotor, w, self.candidates, b)?.modes,
            None => modal(self.rotor, w, self.candidates)?.modes,
        })
    }

    /// The tracks at `b` from their states at `a`, halving the step where matching is
    /// ambiguous.
    fn advance(
        &mut self,
        states: &[State],
        a: f64,
        b: f64,
        halvings: u32,
    ) -> Result<Vec<State>, ModelError> {
        let modes = self.solve(b)?;
        let (assign, ambiguous) = assign(states, &modes, b - a);
        if ambiguous && halvings < MAX_HALVINGS {
            let mid = 0.5 * (a + b);
            self.refined += 1;
            let at_mid = self.advance(states, a, mid, halvings + 1)?;
            return self.advance(&at_mid, mid, b, halvings + 1);
        }
        Ok(states
            .iter()
            .zip(assign)
            .map(|(s, m)| match m {
                Some((j, cost)) if cost <= LOST_COST => {
                    let slope = if b != a {
                        (modes[j].omega_d - s.mode.omega_d) / (b - a)
                    } else {
                        s.slope
                    };
                    State {
                        mode: modes[j].clone(),
                        slope,
                        lost: false,
                    }
                }
                _ => State {
                    lost: true,
                    ..s.clone()
                },
            })
            .collect())
    }
}

/// Matches tracks to candidate modes a step `dw` (rad/s) later: cheapest pairs first. Returns
/// each track's `(mode index, cost)` and whether any match is ambiguous.
#[allow(clippy::type_complexity)]
fn assign(states: &[State], modes: &[Mode], dw: f64) -> (Vec<Option<(usize, f64)>>, bool) {
    let top = modes.iter().fold(0.0_f64, |m, x| m.max(x.omega_d));
    let floor = 1e-6 * top.max(1e-300);
    let cost: Vec<Vec<f64>> = states
        .iter()
        .map(|s| {
            let pred = (s.mode.omega_d + s.slope * dw).max(floor);
            modes
                .iter()
                .map(|m| (1.0 - mode_mac(&s.mode, m)) + (m.omega_d - pred).abs() / pred)
                .collect()
        })
        .collect();
    let mut pairs: Vec<(f64, usize, usize)> = cost
        .iter()
        .enumerate()
        .flat_map(|(t, row)| row.iter().enumerate().map(move |(j, c)| (*c, t, j)))
        .collect();
    pairs.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut out = vec![None; states.len()];
    let mut taken = vec![false; modes.len()];
    for (c, t, j) in pairs {
        if out[t].is_none() && !taken[j] {
            out[t] = Some((j, c));
            taken[j] = true;
        }
    }
    let ambiguous = out.iter().enumerate().any(|(t, m)| match m {
        None => true,
        Some((j, c)) => {
            let second = cost[t]
                .iter()
                .enumerate()
                .filter(|(k, _)| k != j)
                .fold(f64::INFINITY, |b, (_, v)| b.min(*v));
            *c > AMBIGUOUS_COST || second - c < AMBIGUOUS_MARGIN
        }
    });
    (out, ambiguous)
}

/// Campbell diagram over `speeds` (rad/s, ascending) for `nmodes` modes, tracked as the module
/// docs say.
pub fn campbell(
    rotor: &Rotor,
    speeds: &[f64],
    nmodes: usize,
) -> Result<CampbellResults, ModelError> {
    let top = speeds.iter().fold(0.0_f64, |m, s| m.max(s.abs()));
    let basis = match speeds.first() {
        Some(&s) if ModalBasis::reusable(rotor) => Some(ModalBasis::new(rotor, s)?),
        _ => None,
    };
    let mut tracker = Tracker {
        rotor,
        basis,
        candidates: 2 * nmodes + 4,
        tiny: 1e-6 * top.max(1.0),
        refined: 0,
    };
    let Some(&first_speed) = speeds.first() else {
        return Ok(CampbellResults {
            speeds: Vec::new(),
            tracks: Vec::new(),
            critical_speeds: Vec::new(),
            refined_speeds: 0,
        });
    };
    let first = tracker.solve(first_speed)?;
    let nt = nmodes.min(first.len());
    let mut states: Vec<State> = first
        .into_iter()
        .take(nt)
        .map(|mode| State {
            mode,
            slope: 0.0,
            lost: false,
        })
        .collect();
    let mut tracks: Vec<Track> = states
        .iter()
        .map(|s| Track {
            label: String::new(),
            whirl: s.mode.whirl,
            kind: s.mode.kind,
            omega_d: vec![s.mode.omega_d],
            log_dec: vec![s.mode.log_dec],
            whirls: vec![s.mode.whirl],
        })
        .collect();
    for w in speeds.windows(2) {
        states = tracker.advance(&states, w[0], w[1], 0)?;
        for (t, s) in tracks.iter_mut().zip(&states) {
            let nan = if s.lost { f64::NAN } else { 1.0 };
            t.omega_d.push(nan * s.mode.omega_d);
            t.log_dec.push(nan * s.mode.log_dec);
            t.whirls.push(s.mode.whirl);
            t.whirl = s.mode.whirl;
            t.kind = s.mode.kind;
        }
    }
    for (i, t) in tracks.iter_mut().enumerate() {
        t.label = format!("{} {}", i + 1, mode_label(t.kind, t.whirl));
    }
    let critical_speeds = critical_speeds(speeds, &tracks);
    Ok(CampbellResults {
        speeds: speeds.to_vec(),
        tracks,
        critical_speeds,
        refined_speeds: tracker.refined,
    })
}

/// The crossings of the tracks with the 1× line inside the speed range, ascending.
fn critical_speeds(speeds: &[f64], tracks: &[Track]) -> Vec<CriticalSpeed> {
    let mut out = Vec::new();
    for track in tracks {
        for i in 1..speeds.len() {
            let (a, b) = (
                track.omega_d[i - 1] - speeds[i - 1],
                track.omega_d[i] - speeds[i],
            );
            if a.is_finite() && b.is_finite() && a > 0.0 && b <= 0.0 {
                let s = speeds[i - 1] + (speeds[i] - speeds[i - 1]) * a / (a - b);
                out.push(CriticalSpeed {
                    mode: track.label.clone(),
                    whirl: track.whirls[i],
                    kind: track.kind,
                    speed: s,
                    rpm: SpeedUnit::rpm(s),
                });
            }
        }
    }
    out.sort_by(|a, b| a.speed.total_cmp(&b.speed));
    out
}
