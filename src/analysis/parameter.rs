//! The parameter a branch of periodic orbits is continued in (issue 29): the speed ν, or any
//! numeric scene key at a fixed speed. Natural continuation ([`super::branch`]), the location
//! of a change of stability by bisection, pseudo-arclength ([`super::arclength`]) and switching
//! at period doublings ([`super::switch`]) see the parameter only through [`Continued`]: the
//! run prepared at a value of it.
//!
//! **In speed** the model is the scene's; at ν each run is prepared at ω = ν ω_n with its own
//! step plan (natural continuation), or at one fixed `N` steps a revolution for the whole
//! branch (pseudo-arclength, so that the map is smooth in ν).
//!
//! **In a key** (`station.0.friction`, `stator.0.stiffness_ratio`, …: the dotted keys of
//! `--set`) each value's model is built from the scene's text with the key overridden after the
//! scene's own overrides ([`LoadedScene::with_overrides`], as a study builds a variant's), its
//! run prepared at the fixed ν = ω/ω_n of that model — the same ω unless the key changes ω_n —
//! with one `N` steps a revolution for the whole branch, the finer of the plans at the range's
//! two ends: one Δt = 2π/(Ω N), so that the map is smooth in the key. A key that is not a number
//! in the scene, a value the scene's validation refuses, a run setting (`run.*`, `output.*`) and
//! a key whose values give states of different sizes (a stator's `mass` from 0 to > 0) are
//! refused before anything runs, naming the key.

use super::periodic::{self, PeriodicOrbit};
use super::speed::{prepare, Prepared};
use super::RunSettings;
use crate::error::{Error, Result};
use crate::model::Model;
use crate::scene::{toml_number, LoadedScene};
use crate::time::StepPlan;

/// What a branch is continued in, and how its runs are prepared at a value.
pub struct Continued<'a> {
    /// The runs' settings (a reduced model's cut-off pinned for the whole branch).
    s: RunSettings,
    what: What<'a>,
    /// `N` steps a revolution for every value; `None`: each value's own plan.
    n_rev: Option<usize>,
}

/// The parameter itself.
enum What<'a> {
    /// ν = ω/ω_n of the scene's model.
    Speed(&'a Model),
    /// A scene key's value at the fixed ν `speed_ratio`.
    Key {
        scene: &'a LoadedScene,
        key: String,
        speed_ratio: f64,
    },
}

impl<'a> Continued<'a> {
    /// The speed ν of `model` with the settings `s`, each ν's own step plan, a reduced model's
    /// cut-off pinned at the highest speed `top` ([`pinned_reduction`]).
    ///
    /// # Errors
    /// The case at `top`.
    pub fn of_speed(model: &'a Model, s: &RunSettings, top: f64) -> Result<Self> {
        Ok(Self {
            s: pinned_reduction(model, s, top)?,
            what: What::Speed(model),
            n_rev: None,
        })
    }

    /// The scene key `key` of `scene` at the fixed ν `speed_ratio`, with the settings `s`, over
    /// `values` (module docs: the checks — every value's scene, the states at the first two
    /// values —, the one step plan of the range's ends, the cut-off pinned at the end that asks
    /// for more modes).
    ///
    /// # Errors
    /// [`Error::Study`] naming the key: not a number in the scene, a run setting, a value the
    /// scene refuses (its own error), states of different sizes at the first two values; the
    /// runs' preparation errors.
    pub fn of_key(
        scene: &'a LoadedScene,
        s: &RunSettings,
        (key, speed_ratio): (&str, f64),
        values: &[f64],
    ) -> Result<Self> {
        check_key(scene, key)?;
        for &v in values {
            model_at(scene, key, v)?;
        }
        let (lo, hi) = values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
                (l.min(*v), h.max(*v))
            });
        if values.is_empty() {
            return Err(Error::study(key, "a branch in a key needs values"));
        }
        let (ma, mb) = (model_at(scene, key, lo)?, model_at(scene, key, hi)?);
        let (pa, pb) = (
            pinned_reduction(&ma, s, speed_ratio)?,
            pinned_reduction(&mb, s, speed_ratio)?,
        );
        let cut = |p: &RunSettings| p.reduction.and_then(|r| r.cutoff).unwrap_or(0.0);
        let s = if cut(&pb) > cut(&pa) { pb } else { pa };
        let mut c = Self {
            s,
            what: What::Key {
                scene,
                key: key.to_string(),
                speed_ratio,
            },
            n_rev: None,
        };
        let first = values[0];
        let second = values.get(1).copied().unwrap_or(first);
        let sizes = [first, second].map(|v| c.prepare(v).and_then(|p| periodic::state_size(&p)));
        let [na, nb] = sizes;
        let (na, nb) = (na?, nb?);
        if na != nb {
            let n = |x: Option<usize>| x.map_or("no".to_string(), |n| n.to_string());
            return Err(Error::study(
                "",
                format!(
                    "`{key}` changes the periodic orbit's state between its values: {} components at {key} = {}, {} at {} (a branch continues one state; a stator's `mass` from 0 to > 0 adds its body)",
                    n(na),
                    toml_number(first),
                    n(nb),
                    toml_number(second)
                ),
            ));
        }
        let (ra, rb) = (c.prepare(lo)?, c.prepare(hi)?);
        c.n_rev = Some(ra.plan.steps_per_rev.max(rb.plan.steps_per_rev));
        Ok(c)
    }

    /// This parameter with one `N` steps a revolution for every value, the finer of the plans
    /// at `lo` and `hi` (a key's branch has one already).
    ///
    /// # Errors
    /// The runs' preparation errors at `lo` and `hi`.
    pub fn with_fixed_steps(mut self, (lo, hi): (f64, f64)) -> Result<Self> {
        if self.n_rev.is_none() {
            let (pa, pb) = (self.prepare(lo)?, self.prepare(hi)?);
            self.n_rev = Some(pa.plan.steps_per_rev.max(pb.plan.steps_per_rev));
        }
        Ok(self)
    }

    /// The fixed `N` steps a revolution, when the branch has one.
    pub fn steps_per_rev(&self) -> Option<usize> {
        self.n_rev
    }

    /// The run of the branch at the parameter's value `v`: the scene's settings, no follow-ups,
    /// at the branch's fixed `N` steps a revolution when it has one (the run's revolutions as
    /// its own plan has them).
    ///
    /// # Errors
    /// The value's scene or model errors (naming the key and value), the run's plan errors.
    pub fn prepare(&self, v: f64) -> Result<Prepared> {
        let mut p = match &self.what {
            What::Speed(model) => prepare(model, &request(&self.s, v))?,
            What::Key {
                scene,
                key,
                speed_ratio,
            } => prepare(&model_at(scene, key, v)?, &request(&self.s, *speed_ratio))
                .map_err(|e| e.context(format!("{key} = {}", toml_number(v))))?,
        };
        if let Some(n) = self.n_rev {
            let per = p.plan.steps_per_rev.max(1);
            let spr = p.request.step.samples_per_rev.max(1);
            p.plan = StepPlan {
                dt: 2.0 * std::f64::consts::PI / (p.omega * n as f64),
                steps_per_rev: n,
                steps: p.plan.steps / per * n,
                steady_from: p.plan.steady_from / per * n,
                record_every: (n / spr).max(1),
                ..p.plan
            };
        }
        Ok(p)
    }

    /// [`Continued::prepare`] with the coexistence check's other start
    /// ([`Prepared::linear_start`], which `prepare` leaves out): the run at `v` whose second
    /// response [`super::coexist::check_with_companion`] finds (`super::coexist_branches`).
    ///
    /// # Errors
    /// As [`Continued::prepare`].
    pub(crate) fn prepare_with_companion(&self, v: f64) -> Result<Prepared> {
        let mut p = self.prepare(v)?;
        p.linear_start = match &self.what {
            What::Speed(model) => super::coexist::linear_start(model, &p.case),
            What::Key { scene, key, .. } => {
                super::coexist::linear_start(&model_at(scene, key, v)?, &p.case)
            }
        };
        Ok(p)
    }

    /// The period-`period` orbit at `v` shot from its settled run ([`periodic::shoot`]).
    ///
    /// # Errors
    /// As [`Continued::prepare`] and [`periodic::shoot`].
    pub fn shoot(&self, v: f64, period: Option<usize>) -> Result<PeriodicOrbit> {
        let mut o = periodic::shoot(&self.prepare(v)?, period)?;
        o.parameter = v;
        Ok(o)
    }

    /// The orbit at `v` by Newton from `from` (found at a neighbouring value,
    /// [`periodic::shoot_from`]), and the run it was found on.
    ///
    /// # Errors
    /// As [`Continued::prepare`] and [`periodic::shoot_from`].
    pub(crate) fn shoot_from(
        &self,
        v: f64,
        from: &PeriodicOrbit,
    ) -> Result<(Prepared, PeriodicOrbit)> {
        let prep = self.prepare(v)?;
        let mut o = periodic::shoot_from(&prep, from)?;
        o.parameter = v;
        Ok((prep, o))
    }

    /// The parameter's name in the outputs: `speed_ratio`, or the key.
    pub fn name(&self) -> &str {
        match &self.what {
            What::Speed(_) => "speed_ratio",
            What::Key { key, .. } => key,
        }
    }

    /// The parameter's name in messages and on axes: `ω/ωn`, or the key.
    pub fn label(&self) -> &str {
        match &self.what {
            What::Speed(_) => "ω/ωn",
            What::Key { key, .. } => key,
        }
    }

    /// The key, for a branch in a key.
    pub fn key(&self) -> Option<&str> {
        match &self.what {
            What::Speed(_) => None,
            What::Key { key, .. } => Some(key),
        }
    }

    /// ν of the orbit at the parameter's value `v`: `v` itself in speed, the fixed ν in a key.
    pub fn speed_ratio(&self, v: f64) -> f64 {
        match &self.what {
            What::Speed(_) => v,
            What::Key { speed_ratio, .. } => *speed_ratio,
        }
    }
}

/// The settings `s` with a reduced model's cut-off pinned for the whole branch: a default
/// cut-off `cutoff_factor × max(harmonics × ω, ω_c)` follows the speed, and with it the
/// reduced basis — a state at one speed would mean another thing at the next. Pinned at the
/// branch's highest speed `top_ratio` (ν), every point keeps the modes its own speed would ask
/// for and one basis. Unchanged without a reduction or with a fixed `cutoff`.
///
/// # Errors
/// The case at the top speed.
pub fn pinned_reduction(model: &Model, s: &RunSettings, top_ratio: f64) -> Result<RunSettings> {
    let Some(r) = s.reduction_of(model).copied() else {
        return Ok(*s);
    };
    if r.cutoff.is_some() {
        return Ok(*s);
    }
    let top = top_ratio * model.rotor.natural_frequency();
    let cf = model.case_with(top, None)?.contact_frequency();
    let cut = r.cutoff_factor * (r.harmonics * top).max(cf);
    Ok(RunSettings {
        reduction: Some(crate::resolve::ReductionInput {
            cutoff: Some(cut),
            ..r
        }),
        ..*s
    })
}

/// The run request of the continuation at ν: the scene's settings, no follow-ups
/// ([`Continued::prepare`]'s).
pub(super) fn request(s: &RunSettings, v: f64) -> super::RunRequest {
    let mut r = s.request(v);
    r.follow_ups = super::FollowUps::default();
    r
}

/// The model of `scene` with `key = v` ([`LoadedScene::with_overrides`]).
///
/// # Errors
/// [`Error::Study`] naming the key and the value, with the scene's or the model's own error.
fn model_at(scene: &LoadedScene, key: &str, v: f64) -> Result<Model> {
    let at = |e: String| Error::study("", format!("{key} = {}: {e}", toml_number(v)));
    let l = scene
        .with_overrides(&[format!("{key}={}", toml_number(v))])
        .map_err(|e| at(e.to_string()))?;
    Model::from_scene(&l).map_err(|e| at(e.to_string()))
}

/// Refuses a key that is a run or output setting, or that the scene's text holds as anything
/// but a number.
fn check_key(scene: &LoadedScene, key: &str) -> Result<()> {
    let first = key.split('.').next().unwrap_or("");
    if matches!(first, "run" | "output" | "title") {
        return Err(Error::study(
            "",
            format!(
                "`{key}` is a setting of the run, not a parameter of the model: a branch in the speed is `rubsim continue` without --key; set the others with --set"
            ),
        ));
    }
    match scene.value_at(key) {
        None | Some(toml::Value::Float(_) | toml::Value::Integer(_)) => Ok(()),
        Some(v) => Err(Error::study(
            "",
            format!(
                "`{key}` is not a number in the scene (it is {} `{v}`): a branch is continued in a numeric key",
                v.type_str()
            ),
        )),
    }
}
