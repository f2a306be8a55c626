//! Rules of `[run]` and of `[output]`'s time series.

use super::*;

pub(super) fn validate_run(ls: &LoadedScene) -> Result<(), SceneError> {
    let r = &ls.scene.run;
    let n_speed = [
        r.speed_ratio.is_some(),
        r.speed.is_some(),
        r.sweep.is_some(),
    ]
    .iter()
    .filter(|b| **b)
    .count();
    if n_speed != 1 {
        return Err(ls.invalid(
            "run",
            "give exactly one of `speed_ratio`, `speed` or `[run.sweep]`",
        ));
    }
    if let Some(v) = r.speed_ratio {
        positive(ls, "run.speed_ratio", v)?;
    }
    if let Some(v) = r.speed {
        positive(ls, "run.speed", v)?;
    }
    if let Some(sw) = &r.sweep {
        positive(ls, "run.sweep.from", sw.from)?;
        positive(ls, "run.sweep.to", sw.to)?;
        positive(ls, "run.sweep.step", sw.step)?;
        if sw.to < sw.from {
            return Err(ls.invalid("run.sweep.to", "must not be below `from`"));
        }
        if let Some(v) = &sw.vary {
            if v.values.is_empty() {
                return Err(ls.invalid("run.sweep.vary.values", "no values"));
            }
        }
    }
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
    positive(ls, "run.harmonics", r.harmonics)?;
    if r.samples_per_rev < 8 {
        return Err(ls.invalid("run.samples_per_rev", "must be at least 8"));
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
    if let PerSpeed::Speeds(v) = &o.per_speed {
        for x in v {
            positive(ls, "output.per_speed", *x)?;
        }
    }
    Ok(())
}
