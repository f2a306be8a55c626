//! `rubsim continue`'s entry: the speeds of a branch and the continuation it asks for — in ν
//! alone ([`super::branch`]) or by pseudo-arclength ([`super::arclength`]) —, for the command
//! line and the Python package alike; the same in a scene key at a fixed speed
//! ([`continue_key`], [`super::parameter`]).

use super::branch::Branch;
use super::parameter::Continued;
use super::switch::Diagram;
use super::RunSettings;
use crate::error::{Error, Result};
use crate::model::Model;
use crate::scene::LoadedScene;

/// The speeds of a branch from `from` to `to` (ω/ω_n) by `step`, in the order continued:
/// downwards when `to < from`.
///
/// # Errors
/// [`crate::error::Error::Study`] for a speed or step that is not a positive number.
pub fn speeds(from: f64, to: f64, step: f64) -> Result<Vec<f64>> {
    for (name, v) in [("from", from), ("to", to), ("step", step)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(crate::error::Error::study(
                "",
                format!("the branch's `{name}` must be a positive speed, got {v}"),
            ));
        }
    }
    let mut v = super::sweep_speeds(from.min(to), from.max(to), step);
    if to < from {
        v.reverse();
    }
    Ok(v)
}

/// `rubsim continue`'s branch: the period-`period` orbit continued from `from` to `to` by
/// `step` (ω/ω_n) with the settings `s` — in ν alone ([`super::branch::continue_in_speed`]) or, with
/// `arclength = Some(n)`, by pseudo-arclength around folds in at most `n` points
/// ([`super::arclength::continue_arclength`]).
///
/// # Errors
/// As [`speeds`]; [`crate::error::Error::Study`] for fewer than 2 points; the continuations'
/// errors.
pub fn continue_branch(
    model: &Model,
    s: &RunSettings,
    (from, to, step): (f64, f64, f64),
    period: Option<usize>,
    arclength: Option<usize>,
) -> Result<Branch> {
    let speeds = speeds(from, to, step)?;
    match arclength {
        Some(n) if n < 2 => Err(crate::error::Error::study(
            "",
            format!("a pseudo-arclength branch needs at least 2 points, got {n}"),
        )),
        Some(n) => super::arclength::continue_arclength(model, s, (from, to, step), period, n),
        None => super::branch::continue_in_speed(model, s, &speeds, period),
    }
}

/// `rubsim continue --switch`: the period-`period` branch from `from` to `to` by `step` (in ν
/// alone), then the branches switched from its period doublings and theirs, up to period
/// `max_period` ([`super::switch::switch_all`]).
///
/// # Errors
/// As [`speeds`]; the first speed's shooting errors.
pub fn continue_switching(
    model: &Model,
    s: &RunSettings,
    (from, to, step): (f64, f64, f64),
    period: Option<usize>,
    max_period: usize,
) -> Result<Diagram> {
    let speeds = speeds(from, to, step)?;
    let c = Continued::of_speed(model, s, from.max(to))?;
    switching(&c, &speeds, period, max_period)
}

/// `rubsim continue --arclength --switch`: the pseudo-arclength branch from `from` towards `to`
/// (first step `step`, at most `max_points` points), then the branches switched at its period
/// doublings up to period `max_period` ([`super::arclength::arclength_switching`]).
///
/// # Errors
/// As [`speeds`]; [`Error::Study`] for fewer than 2 points; the first speed's shooting errors.
pub fn arclength_switching(
    model: &Model,
    s: &RunSettings,
    (from, to, step): (f64, f64, f64),
    period: Option<usize>,
    (max_points, max_period): (usize, usize),
) -> Result<Diagram> {
    speeds(from, to, step)?;
    if max_points < 2 {
        return Err(Error::study(
            "",
            format!("a pseudo-arclength branch needs at least 2 points, got {max_points}"),
        ));
    }
    let c = Continued::of_speed(model, s, from.max(to))?;
    super::arclength::arclength_switching(c, (from, to, step), period, (max_points, max_period))
}

/// The branch of period `period` over `values` of the parameter `c`, then the branches
/// switched from its period doublings up to period `max_period` ([`continue_switching`] for
/// any parameter).
///
/// # Errors
/// The first value's shooting errors.
pub fn switching(
    c: &Continued<'_>,
    values: &[f64],
    period: Option<usize>,
    max_period: usize,
) -> Result<Diagram> {
    let Some(&first) = values.first() else {
        return Err(crate::error::Error::study(
            "",
            "a branch needs a first value",
        ));
    };
    let start = c.shoot(first, period)?;
    let branch = super::branch::follow(c, start, values, None);
    Ok(super::switch::switch_all(c, branch, max_period))
}

/// The values of a branch in a key from `from` to `to` by `step` (the key's units), in the
/// order continued: downwards when `to < from`; `from + i·step`, its floating-point noise
/// rounded away (`without_noise`: 0.3, not 0.30000000000000004).
///
/// # Errors
/// [`Error::Study`] for a value that is not finite, a step that is not positive, or more than
/// a million values.
pub fn values(from: f64, to: f64, step: f64) -> Result<Vec<f64>> {
    for (name, v) in [("from", from), ("to", to), ("step", step)] {
        if !v.is_finite() {
            return Err(Error::study(
                "",
                format!("the branch's `{name}` must be a finite number, got {v}"),
            ));
        }
    }
    if step <= 0.0 {
        return Err(Error::study(
            "",
            format!("the branch's `step` must be positive, got {step}"),
        ));
    }
    let n = ((to - from).abs() / step + 1e-9).floor();
    if n > 1e6 {
        return Err(Error::study(
            "",
            format!("{n} steps from {from} to {to} by {step}: at most a million"),
        ));
    }
    let dir = if to < from { -1.0 } else { 1.0 };
    Ok((0..=n as usize)
        .map(|i| without_noise(from + dir * step * i as f64, step))
        .collect())
}

/// `v` rounded to six digits below the step's first (`0.30000000000000004` of `0.1 + 4·0.05`
/// printed as `0.3`) when that moves it by no more than 1e-9 of its size or of the step — the
/// floating point's noise, not a value the user gave (`0.123456789` from `--from` stays).
fn without_noise(v: f64, step: f64) -> f64 {
    let q = 10f64.powi(6 - step.log10().floor() as i32);
    let r = (v * q).round() / q;
    if r.is_finite() && (r - v).abs() <= 1e-9 * v.abs().max(step) {
        r
    } else {
        v
    }
}

/// What `rubsim continue --key` continues: the key, the fixed speed, the values and the kind of
/// continuation.
#[derive(Debug, Clone)]
pub struct KeyBranch<'k> {
    /// The dotted scene key (`station.0.friction`).
    pub key: &'k str,
    /// The fixed ν = ω/ω_n.
    pub speed_ratio: f64,
    /// `(from, to, step)` in the key's units.
    pub range: (f64, f64, f64),
    /// Period of the orbit (`None`: the first value's settled period).
    pub period: Option<usize>,
    /// Pseudo-arclength with at most this many points.
    pub arclength: Option<usize>,
    /// Branch switching up to this largest period.
    pub switch: Option<usize>,
}

/// `rubsim continue --key`: the period-`period` orbit of `scene` at the fixed speed continued
/// over the key's values with the settings `s` — in the key alone, by pseudo-arclength, or with
/// switching at period doublings ([`super::parameter`] for how each value's model is built and
/// what is refused before anything runs). A branch without switching is the diagram's only one.
///
/// # Errors
/// As [`values`]; [`Error::Study`] for both `arclength` and `switch`, fewer than 2 points; the
/// key's refusals ([`Continued::of_key`]); the first value's shooting errors.
pub fn continue_key(scene: &LoadedScene, s: &RunSettings, b: &KeyBranch<'_>) -> Result<Diagram> {
    let (from, to, step) = b.range;
    let values = values(from, to, step)?;
    if !(b.speed_ratio.is_finite() && b.speed_ratio > 0.0) {
        return Err(Error::study(
            "",
            format!("the branch's speed must be positive, got {}", b.speed_ratio),
        ));
    }
    let at = (b.key, b.speed_ratio);
    match (b.arclength, b.switch) {
        (Some(n), _) if n < 2 => Err(Error::study(
            "",
            format!("a pseudo-arclength branch needs at least 2 points, got {n}"),
        )),
        (Some(n), None) => {
            let c = Continued::of_key(scene, s, at, &[from, to])?;
            let branch = super::arclength::arclength_in(c, (from, to, step), b.period, n)?;
            Ok(Diagram::of(branch))
        }
        (Some(n), Some(m)) => {
            let c = Continued::of_key(scene, s, at, &[from, to])?;
            super::arclength::arclength_switching(c, (from, to, step), b.period, (n, m))
        }
        (None, Some(m)) => switching(
            &Continued::of_key(scene, s, at, &values)?,
            &values,
            b.period,
            m,
        ),
        (None, None) => {
            let c = Continued::of_key(scene, s, at, &values)?;
            Ok(Diagram::of(super::branch::continue_in(
                &c, &values, b.period,
            )?))
        }
    }
}

/// `rubsim continue --autonomous`: the autonomous orbit (a whirl at its own frequency) of the
/// scene continued over `range` — in speed (ν `from … to` by `step`), or with `key = Some((key,
/// ν))` over the key's values at the fixed speed ν ([`super::autonomous_branch`]).
///
/// # Errors
/// As [`speeds`] or [`values`]; the key's refusals ([`Continued::of_key`]); the first value's
/// ([`super::autonomous_branch::follow_autonomous`]).
pub fn continue_autonomous(
    (scene, model): (&LoadedScene, &Model),
    s: &RunSettings,
    key: Option<(&str, f64)>,
    (from, to, step): (f64, f64, f64),
) -> Result<super::autonomous_branch::AutonomousBranch> {
    match key {
        None => {
            let v = speeds(from, to, step)?;
            let c = Continued::of_speed(model, s, from.max(to))?;
            super::autonomous_branch::follow_autonomous(&c, &v)
        }
        Some(at) => {
            let v = values(from, to, step)?;
            let c = Continued::of_key(scene, s, at, &v)?;
            super::autonomous_branch::follow_autonomous(&c, &v)
        }
    }
}

/// The orbits of the autonomous branch `b` in speed (continued by [`continue_autonomous`]
/// over `(from, to, _)` with the settings `s`) at the speeds `values` (ν), each shot from the
/// branch's nearest point (`autonomous_branch::orbits_at`), and a sentence for each value
/// outside the branch or whose shot failed.
///
/// # Errors
/// As [`Continued::of_speed`].
pub fn autonomous_orbits_at(
    model: &Model,
    s: &RunSettings,
    (from, to, _): (f64, f64, f64),
    b: &super::autonomous_branch::AutonomousBranch,
    values: &[f64],
) -> Result<(Vec<super::autonomous_branch::AutonomousAt>, Vec<String>)> {
    let c = Continued::of_speed(model, s, from.max(to))?;
    Ok(super::autonomous_branch::orbits_at(&c, b, values))
}

#[cfg(test)]
mod tests {
    use super::values;

    #[test]
    fn key_values_carry_no_floating_point_noise_but_keep_what_was_given() {
        assert_eq!(values(0.1, 0.3, 0.05).unwrap(), [0.1, 0.15, 0.2, 0.25, 0.3]);
        assert_eq!(values(0.3, 0.1, 0.05).unwrap()[4], 0.1);
        let v = values(0.123456789, 0.2, 0.05).unwrap();
        assert_eq!(v[0], 0.123456789);
        assert_eq!(values(1e-4, 1.3e-4, 1e-5).unwrap()[3], 1.3e-4);
        assert_eq!(values(25.0, 5.0, 0.5).unwrap()[39], 5.5);
    }
}
