//! Rules of `[run]` and of `[output]`'s time series.

use super::checks::*;
use crate::error::SceneError;
use crate::scene::*;

pub(super) fn validate_run(ls: &LoadedScene) -> Result<(), SceneError> {
    let r = &ls.scene.run;
    validate_speed_choice(ls)?;
    if let Some(p) = &r.speed_profile {
        super::super::profile::validate(ls, p)?;
    }
    super::super::event::validate(ls, &r.event)?;
    if let Some(v) = r.speed_ratio {
        positive(ls, "run.speed_ratio", v)?;
    }
    if let Some(v) = r.speed {
        positive(ls, "run.speed", v)?;
    }
    if let Some(sw) = &r.sweep {
        validate_sweep(ls, sw)?;
    }
    validate_windows(ls)?;
    if let Some(d) = r.duration {
        validate_duration(ls, d)?;
    }
    positive(ls, "run.harmonics", r.harmonics)?;
    if let Some(rho) = r.rho_inf {
        validate_rho_inf(ls, rho)?;
    }
    validate_limits(ls)?;
    if let Some(red) = &r.reduction {
        validate_reduction(ls, red)?;
    }
    validate_initial(ls)
}

/// Exactly one way to give the speed: `run.speed_ratio`, `run.speed`, `[run.sweep]`,
/// `[run.speed_profile]` or a `[run.map]` with a speed axis (a map of two other keys runs at
/// `speed_ratio` or `speed`); a map with neither a sweep nor a profile.
fn validate_speed_choice(ls: &LoadedScene) -> Result<(), SceneError> {
    let r = &ls.scene.run;
    let map_speed = r
        .map
        .as_ref()
        .is_some_and(|m| m.x.is_speed() || m.y.is_speed());
    let n_speed = [
        r.speed_ratio.is_some(),
        r.speed.is_some(),
        r.sweep.is_some(),
        r.speed_profile.is_some(),
        map_speed,
    ]
    .iter()
    .filter(|b| **b)
    .count();
    if n_speed != 1 && r.map.is_some() {
        return Err(ls.invalid(
            "run.map",
            if map_speed {
                "`run.map.x.key` or `run.map.y.key` is `speed_ratio`: leave out `run.speed_ratio`, \
                 `run.speed`, `[run.sweep]` and `[run.speed_profile]`"
            } else {
                "neither `run.map.x.key` nor `run.map.y.key` is `speed_ratio`: a map of two scene \
                 keys runs at `run.speed_ratio` or `run.speed`; give exactly one"
            },
        ));
    }
    if n_speed != 1 {
        return Err(ls.invalid(
            "run",
            "give exactly one of `speed_ratio`, `speed`, `[run.sweep]`, `[run.speed_profile]` \
             or a `[run.map]` with a `speed_ratio` axis (a map of two other keys runs at \
             `speed_ratio` or `speed`)",
        ));
    }
    if r.map.is_some() && (r.sweep.is_some() || r.speed_profile.is_some()) {
        return Err(ls.invalid(
            "run.map",
            "cannot be combined with `[run.sweep]` or `[run.speed_profile]`",
        ));
    }
    Ok(())
}

/// `[run.sweep]`: positive `from`, `to`, `step`, `to ≥ from`, at most [`MAX_SWEEP_SPEEDS`]
/// speeds.
fn validate_sweep(ls: &LoadedScene, sw: &SweepSpec) -> Result<(), SceneError> {
    positive(ls, "run.sweep.from", sw.from)?;
    positive(ls, "run.sweep.to", sw.to)?;
    positive(ls, "run.sweep.step", sw.step)?;
    if sw.to < sw.from {
        return Err(ls.invalid("run.sweep.to", "must not be below `from`"));
    }
    let n = (sw.to - sw.from) / sw.step + 1.0;
    if n.is_nan() || n > MAX_SWEEP_SPEEDS as f64 {
        let key = if sw.to / sw.from > 1e3 {
            "run.sweep.to"
        } else {
            "run.sweep.step"
        };
        return Err(ls.invalid(
            key,
            format!(
                "the sweep {} … {} step {} has {n:.3e} speeds; at most {MAX_SWEEP_SPEEDS} are allowed",
                show(sw.from),
                show(sw.to),
                show(sw.step)
            ),
        ));
    }
    Ok(())
}

/// The run's windows and accuracy: more revolutions than transient ones, a positive `dt`, a
/// tolerance in 1e-12 ..= 0.5, the transient and classification limits.
fn validate_windows(ls: &LoadedScene) -> Result<(), SceneError> {
    let r = &ls.scene.run;
    if r.revolutions <= r.transient_revolutions {
        return Err(ls.invalid(
            "run.revolutions",
            format!(
                "must exceed transient_revolutions ({}), got {}",
                r.transient_revolutions, r.revolutions
            ),
        ));
    }
    if let Some(dt) = r.dt {
        positive(ls, "run.dt", dt)?;
    }
    if !(1e-12..=0.5).contains(&r.tolerance) {
        return Err(ls.invalid(
            "run.tolerance",
            format!(
                "a relative tolerance must lie in 1e-12 ..= 0.5, got {}",
                show(r.tolerance)
            ),
        ));
    }
    if let Some(m) = r.max_transient_revolutions {
        if m < r.transient_revolutions || m > MAX_REVOLUTIONS {
            return Err(ls.invalid(
                "run.max_transient_revolutions",
                format!(
                    "must lie in transient_revolutions ({}) ..= {MAX_REVOLUTIONS}, got {m}",
                    r.transient_revolutions
                ),
            ));
        }
    }
    if r.classify_revolutions > MAX_REVOLUTIONS {
        return Err(ls.invalid(
            "run.classify_revolutions",
            format!(
                "must lie in 0 ..= {MAX_REVOLUTIONS}, got {}",
                r.classify_revolutions
            ),
        ));
    }
    Ok(())
}

/// `run.duration = d` (a fixed window): positive and finite, and none of the keys that lengthen
/// a run or set its length otherwise beside it — `[run.speed_profile]` (its profile sets the
/// length), `run.max_transient_revolutions` and `run.classify_revolutions` (a fixed window is
/// never lengthened). `revolutions` and `transient_revolutions` do not apply and are not
/// refused: every scene writes them, and `--set run.duration=…` must work on any of them.
fn validate_duration(ls: &LoadedScene, d: f64) -> Result<(), SceneError> {
    positive(ls, "run.duration", d)?;
    let r = &ls.scene.run;
    let refuse = |key: &str, why: &str| {
        ls.invalid(
            "run.duration",
            format!("`run.duration` cannot be combined with `{key}`: {why}; leave one out"),
        )
    };
    if r.speed_profile.is_some() {
        return Err(refuse(
            "run.speed_profile",
            "a transient's length is its speed profile's",
        ));
    }
    for key in ["max_transient_revolutions", "classify_revolutions"] {
        if given(ls, "run", key) {
            return Err(refuse(
                &format!("run.{key}"),
                "a fixed window is never lengthened (not for the steady state, not for the 0–1 test)",
            ));
        }
    }
    Ok(())
}

/// Whether the scene gives `[table] key` itself (in its file or by a `--set table.key=…`), not
/// by its default.
fn given(ls: &LoadedScene, table: &str, key: &str) -> bool {
    let in_file = toml::from_str::<toml::Table>(&ls.source)
        .ok()
        .and_then(|t| t.get(table)?.as_table()?.get(key).cloned())
        .is_some();
    let dotted = format!("{table}.{key}");
    in_file
        || ls
            .overrides
            .iter()
            .any(|o| o.split('=').next().is_some_and(|k| k.trim() == dotted))
}

/// `run.rho_inf = rho`: only for `generalized_alpha`, in 0 ..= 1.
fn validate_rho_inf(ls: &LoadedScene, rho: f64) -> Result<(), SceneError> {
    let r = &ls.scene.run;
    if r.integrator() != IntegratorKind::GeneralizedAlpha {
        return Err(ls.invalid(
            "run.rho_inf",
            format!(
                "only `run.integrator = \"generalized_alpha\"` has a spectral radius ρ∞; the integrator is `{}`: leave `rho_inf` out or choose `generalized_alpha`",
                r.integrator().name()
            ),
        ));
    }
    if !(0.0..=1.0).contains(&rho) {
        return Err(ls.invalid(
            "run.rho_inf",
            format!("must lie in 0 ..= 1 (the spectral radius at infinite frequency), got {rho}"),
        ));
    }
    Ok(())
}

/// The documented size limits of `[run]`: samples per revolution, revolutions, `max_steps`.
fn validate_limits(ls: &LoadedScene) -> Result<(), SceneError> {
    let r = &ls.scene.run;
    if !(8..=MAX_SAMPLES_PER_REV).contains(&r.samples_per_rev) {
        return Err(ls.invalid(
            "run.samples_per_rev",
            format!(
                "must lie in 8 ..= {MAX_SAMPLES_PER_REV}, got {}",
                r.samples_per_rev
            ),
        ));
    }
    if r.revolutions > MAX_REVOLUTIONS {
        return Err(ls.invalid(
            "run.revolutions",
            format!(
                "at most {MAX_REVOLUTIONS} revolutions, got {}",
                r.revolutions
            ),
        ));
    }
    if let Some(m) = r.max_steps {
        if m == 0 {
            return Err(ls.invalid("run.max_steps", "must be at least 1"));
        }
    }
    Ok(())
}

/// `[run.reduction]`: an FE rotor at a constant speed and/or meshed stators with mass
/// (`stators = true`); a positive cut-off or a factor ≥ 1.
fn validate_reduction(ls: &LoadedScene, red: &ReductionSpec) -> Result<(), SceneError> {
    let fe = matches!(ls.scene.rotor, RotorSpec::Fe(_));
    if red.rotor == Some(true) && !fe {
        return Err(ls.invalid(
            "run.reduction.rotor",
            "only an FE rotor (`rotor.kind = \"fe\"`) is reduced; a Jeffcott rotor has two DOFs",
        ));
    }
    let stators = red.stators == Some(true);
    if stators {
        let with_mass = ls.scene.stators.iter().any(|s| match s {
            StatorSpec::Mesh(m) => {
                m.density > 0.0 || m.regions.iter().any(|r| r.density.is_some_and(|d| d > 0.0))
            }
            _ => false,
        });
        if !with_mass {
            return Err(ls.invalid(
                "run.reduction.stators",
                "no meshed stator (`kind = \"mesh\"`) has mass (`density` > 0): there is no stator to reduce",
            ));
        }
    }
    let rotor = red.rotor.unwrap_or(fe);
    if !rotor && !stators {
        return Err(ls.invalid(
            "run.reduction",
            if fe {
                "`rotor = false` and no `stators = true`: nothing is reduced"
            } else {
                "only an FE rotor (`rotor.kind = \"fe\"`) is reduced; a Jeffcott rotor has two DOFs (reduce meshed stators with mass by `stators = true`)"
            },
        ));
    }
    let driven = (ls.scene.run.speed_profile.as_ref())
        .is_some_and(|p| p.kind == crate::scene::ProfileKind::Driven);
    if rotor && (driven || !ls.scene.run.event.is_empty()) {
        return Err(ls.invalid(
            "run.reduction",
            "a reduced rotor runs at constant speed or along a prescribed `[run.speed_profile]` \
             only: leave out a driven profile (`kind = \"driven\"`) and `[[run.event]]`, or the \
             reduction",
        ));
    }
    if let Some(c) = red.cutoff {
        positive(ls, "run.reduction.cutoff", c)?;
        if red.cutoff_factor.is_some() {
            return Err(ls.invalid(
                "run.reduction.cutoff_factor",
                "give `cutoff` (rad/s) or `cutoff_factor`, not both",
            ));
        }
    }
    if let Some(k) = red.cutoff_factor {
        if !(k.is_finite() && (1.0..=1e3).contains(&k)) {
            return Err(ls.invalid(
                "run.reduction.cutoff_factor",
                format!(
                    "must lie in 1 ..= 1000 (the cut-off over the highest frequency the run resolves), got {}",
                    show(k)
                ),
            ));
        }
    }
    Ok(())
}

/// `run.initial_displacement` and `run.initial_velocity`: finite, and the displacement within
/// the radius of the first station (a rotor displaced by more than its own radius is outside
/// the small-displacement model; the orbit would start far outside any clearance).
fn validate_initial(ls: &LoadedScene) -> Result<(), SceneError> {
    let r = &ls.scene.run;
    for (name, v) in [
        ("initial_displacement", r.initial_displacement),
        ("initial_velocity", r.initial_velocity),
    ] {
        if !v.iter().all(|x| x.is_finite()) {
            return Err(ls.invalid(&format!("run.{name}"), format!("must be finite, got {v:?}")));
        }
    }
    let [x, y] = r.initial_displacement;
    if let Some(st) = ls.scene.stations.first() {
        if x.hypot(y) > st.radius {
            return Err(ls.invalid(
                "run.initial_displacement",
                format!(
                    "|u0| = {:.3e} m exceeds the radius of station `{}` ({} m): outside the small-displacement model and any clearance",
                    x.hypot(y),
                    st.name,
                    st.radius
                ),
            ));
        }
    }
    Ok(())
}

/// `[run.sweep.vary]`: values finite and distinct, and the scene with `key = value` valid for
/// every value (so a key that does not exist, or a value its rule refuses, is found by `check`,
/// not in the middle of a sweep).
pub(super) fn validate_vary(ls: &LoadedScene, v: &VarySpec) -> Result<(), SceneError> {
    let vk = "run.sweep.vary.values";
    if v.values.is_empty() {
        return Err(ls.invalid(vk, "no values"));
    }
    for (i, x) in v.values.iter().enumerate() {
        if !x.is_finite() {
            return Err(ls.invalid(vk, format!("value {i} is {x}: must be finite")));
        }
        if v.values[..i].contains(x) {
            return Err(ls.invalid(vk, format!("value {x} appears twice")));
        }
    }
    for x in &v.values {
        valid_with(ls, &v.key, *x, None).map_err(|(key, msg)| {
            let key = if key == KEY { "run.sweep.vary.key" } else { vk };
            ls.invalid(
                key,
                format!("with `{} = {x}` the scene is invalid: {msg}", v.key),
            )
        })?;
    }
    Ok(())
}

/// Marks an error of [`valid_with`] that is about the key itself (it does not exist).
const KEY: &str = "key";

/// Checks that the scene with `key = x` (and the study tables removed; a map's speed axis
/// replaced by `run.speed_ratio = speed`) is valid; the error is `(KEY or "values", message)`.
fn valid_with(
    ls: &LoadedScene,
    key: &str,
    x: f64,
    speed: Option<f64>,
) -> Result<(), (&'static str, String)> {
    let mut value: toml::Value =
        toml::from_str(&ls.source).map_err(|e| (KEY, e.message().to_string()))?;
    let mut sets = ls.overrides.clone();
    sets.push(format!("{key}={}", toml_number(x)));
    let nested = sets.iter().try_for_each(|a| apply_override(&mut value, a));
    let nested = nested.and_then(|()| {
        if let Some(run) = value.get_mut("run").and_then(|r| r.as_table_mut()) {
            if let Some(sw) = run.get_mut("sweep").and_then(|s| s.as_table_mut()) {
                sw.remove("vary");
            }
            if run.remove("map").is_some() {
                if let Some(v) = speed {
                    run.insert("speed_ratio".into(), toml::Value::Float(v));
                }
            }
        }
        let scene = Scene::deserialize(value).map_err(|e| SceneError::Override {
            assignment: format!("{key}={}", toml_number(x)),
            message: e.message().to_string(),
        })?;
        validate(&LoadedScene {
            scene,
            file: ls.file.clone(),
            source: ls.source.clone(),
            overrides: sets,
        })
    });
    nested.map_err(|e| match &e {
        SceneError::Invalid {
            key: k, message, ..
        } if k == key => ("values", message.clone()),
        SceneError::Invalid {
            key: k, message, ..
        } => ("values", format!("{k}: {message}")),
        other => (KEY, other.to_string()),
    })
}

/// One axis of `[run.map]`: a key, and a list of values or a whole range, finite, distinct,
/// positive speeds.
fn validate_axis(ls: &LoadedScene, name: &str, ax: &MapAxis) -> Result<(), SceneError> {
    let k = |f: &str| format!("run.map.{name}.{f}");
    if ax.key.trim().is_empty() {
        return Err(ls.invalid(&k("key"), "is empty: give `speed_ratio` or a scene key"));
    }
    let range = [ax.from, ax.to, ax.step];
    let (all, any) = (
        range.iter().all(Option::is_some),
        range.iter().any(Option::is_some),
    );
    if (ax.values.is_some() && any) || (ax.values.is_none() && !all) {
        return Err(ls.invalid(
            &k("values"),
            format!(
                "give either `{}` or all of `{}`, `{}` and `{}`",
                k("values"),
                k("from"),
                k("to"),
                k("step")
            ),
        ));
    }
    if let (Some(a), Some(b), Some(h)) = (ax.from, ax.to, ax.step) {
        for (f, x) in [("from", a), ("to", b)] {
            if !x.is_finite() {
                return Err(ls.invalid(&k(f), format!("must be finite, got {x}")));
            }
        }
        if ax.is_speed() {
            positive(ls, &k("from"), a)?;
        }
        positive(ls, &k("step"), h)?;
        if b < a {
            return Err(ls.invalid(
                &k("to"),
                format!("must not be below `{}` ({a}), got {b}", k("from")),
            ));
        }
        let n = (b - a) / h + 1.0;
        if n.is_nan() || n > MAX_SWEEP_SPEEDS as f64 {
            return Err(ls.invalid(
                &k("step"),
                format!(
                    "the range `{}` … `{}` has {n:.3e} values; at most {MAX_SWEEP_SPEEDS} are allowed",
                    k("from"),
                    k("to")
                ),
            ));
        }
    }
    let values = ax.resolved();
    if values.is_empty() {
        return Err(ls.invalid(&k("values"), "no values"));
    }
    for (i, x) in values.iter().enumerate() {
        if !x.is_finite() {
            return Err(ls.invalid(&k("values"), format!("value {i} is {x}: must be finite")));
        }
        if values[..i].contains(x) {
            return Err(ls.invalid(&k("values"), format!("value {x} appears twice")));
        }
        if ax.is_speed() {
            positive(ls, &k("values"), *x)?;
        }
    }
    Ok(())
}

/// Most cases of a map.
pub const MAX_MAP_CASES: usize = 1_000_000;

/// `[run.map]`: each axis a key with values (a list, or `from`/`to`/`step`), the keys
/// distinct, speeds positive, and the scene valid with every value of a scene key.
pub(super) fn validate_map(ls: &LoadedScene, m: &MapSpec) -> Result<(), SceneError> {
    if m.x.key == m.y.key {
        return Err(ls.invalid(
            "run.map.y.key",
            format!("is `{}` like x: give two different keys", m.y.key),
        ));
    }
    let mut total = 1usize;
    for (name, ax) in [("x", &m.x), ("y", &m.y)] {
        validate_axis(ls, name, ax)?;
        total = total.saturating_mul(ax.resolved().len());
    }
    // The scene at the first speed of the map (if one axis is the speed) with each value of
    // a scene key; a failing value of a range is blamed on `from`, `to` or `step`.
    let first_speed = [&m.x, &m.y]
        .iter()
        .find(|a| a.is_speed())
        .and_then(|a| a.resolved().first().copied());
    for (name, ax) in [("x", &m.x), ("y", &m.y)] {
        if ax.is_speed() {
            continue;
        }
        let values = ax.resolved();
        for (i, x) in values.iter().enumerate() {
            valid_with(ls, &ax.key, *x, first_speed).map_err(|(key, msg)| {
                let field = match (key, &ax.values, i) {
                    (KEY, ..) => "key",
                    (_, Some(_), _) => "values",
                    (_, None, 0) => "from",
                    (_, None, i) if i + 1 == values.len() => "to",
                    _ => "step",
                };
                ls.invalid(
                    &format!("run.map.{name}.{field}"),
                    format!("with `{} = {x}` the scene is invalid: {msg}", ax.key),
                )
            })?;
        }
    }
    if total > MAX_MAP_CASES {
        return Err(ls.invalid(
            "run.map",
            format!("has {total} cases; at most {MAX_MAP_CASES} are allowed"),
        ));
    }
    Ok(())
}

/// Checks `output.vtk`, `output.hdf5` and `output.per_speed`.
pub(super) fn validate_series(ls: &LoadedScene) -> Result<(), SceneError> {
    let o = &ls.scene.output;
    let revs = ls.scene.run.revolutions as f64;
    for (name, spec) in [("vtk", &o.vtk), ("hdf5", &o.hdf5)] {
        let Some(sp) = spec else { continue };
        let k = |f: &str| format!("output.{name}.{f}");
        if sp.every == Some(0) {
            return Err(ls.invalid(&k("every"), "must be at least 1 (steps between frames)"));
        }
        if sp.fields.is_empty() {
            return Err(ls.invalid(&k("fields"), "no fields: leave the key out to write all"));
        }
        non_negative(ls, &k("from_revolution"), sp.from_revolution)?;
        let to = sp.to_revolution.unwrap_or(revs);
        if !(to.is_finite() && to >= sp.from_revolution && sp.from_revolution <= revs) {
            return Err(ls.invalid(
                &k("to_revolution"),
                format!(
                    "the window [{}, {to}] revolutions must be ordered and overlap the run (0 to {revs})",
                    sp.from_revolution
                ),
            ));
        }
    }
    if o.per_speed != PerSpeed::All(false) && o.vtk.is_none() && o.hdf5.is_none() {
        return Err(ls.invalid(
            "output.per_speed",
            "asks for per-speed time series, but neither `output.vtk` nor `output.hdf5` is given",
        ));
    }
    for (g, grid) in o.orbit_grids.iter().enumerate() {
        for x in grid {
            positive(ls, &format!("output.orbit_grids.{g}"), *x)?;
        }
    }
    for x in &o.force_histories {
        positive(ls, "output.force_histories", *x)?;
    }
    if !o.snapshot_speeds.is_empty() && ls.scene.run.speed_profile.is_none() {
        return Err(ls.invalid(
            "output.snapshot_speeds",
            "applies to a speed transient only (a scene with `[run.speed_profile]`); use `output.orbit_grids` for the orbits of a sweep",
        ));
    }
    for (i, x) in o.snapshot_speeds.iter().enumerate() {
        positive(ls, &format!("output.snapshot_speeds.{i}"), *x)?;
    }
    if let Some(f) = o.cascade_max_freq {
        positive(ls, "output.cascade_max_freq", f)?;
    }
    if let PerSpeed::Speeds(v) = &o.per_speed {
        for x in v {
            positive(ls, "output.per_speed", *x)?;
        }
    }
    Ok(())
}
