//! `rubsim continue`'s entry: the speeds of a branch and the continuation it asks for — in ν
//! alone ([`super::branch`]) or by pseudo-arclength ([`super::arclength`]) —, for the command
//! line and the Python package alike.

use super::branch::Branch;
use super::switch::Diagram;
use super::RunSettings;
use crate::error::Result;
use crate::model::Model;

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
    let pinned = super::branch::pinned_reduction(model, s, from.max(to))?;
    let prep = super::speed::prepare(model, &super::branch::request(&pinned, speeds[0]))?;
    let start = super::periodic::shoot(&prep, period)?;
    let first = super::branch::follow(model, &pinned, start, &speeds, None);
    Ok(super::switch::switch_all(model, &pinned, first, max_period))
}
