//! A stator at one speed: the speed-independent plan placed at its clearance (a clearance
//! given as δ/|Z0(ω)| depends on ω; a meshed stator translated along its approach), with its
//! contact dashpot and its wear.

use super::stator::{StatorModel, StatorWear};
use super::{Clearance, Model, Placement, StatorPlan, Target};
use crate::error::ModelError;

/// Why `contact_damping` is refused on a stator with mass (the key is named by
/// `blame::stators`).
const CONTACT_DAMPING_WITH_MASS: &str = "`contact_damping` on a stator with mass is not modelled: its contact with the rotor is rigid (the multipliers hold the relative normal velocity at zero while in contact), so a dashpot in parallel with it does nothing; damp the stator itself (`rayleigh`, or a ring's `damping`) or make it massless";

impl Model {
    /// Stator `i` with its contact dashpot; refused on a stator with mass.
    pub(super) fn with_dashpot(
        &self,
        i: usize,
        mut m: StatorModel,
    ) -> Result<StatorModel, ModelError> {
        let d = self.dashpots.get(i).copied().unwrap_or_default();
        if d.active() && !m.massless() {
            return Err(ModelError::Inconsistent {
                what: format!("stator `{}`", m.name),
                message: CONTACT_DAMPING_WITH_MASS.into(),
            });
        }
        m.dashpot = d;
        Ok(m)
    }

    /// One stator at speed ω, placed at its clearance, for a rotor of reference stiffness
    /// `kr` (N/m) whose forced response per node is `forced` ([`Rotor::forced_ellipses`]).
    pub(super) fn stator_at(
        &self,
        plan: &StatorPlan,
        omega: f64,
        kr: f64,
        forced: &[[f64; 2]],
    ) -> Result<StatorModel, ModelError> {
        let si = plan.station();
        let st = &self.stations[si];
        let clearance = |c: Clearance| match c {
            Clearance::Metres(m) => Ok(m),
            Clearance::TimesZ0(nd) => {
                let z0 = forced[st.node][0];
                match self.rotor.z0_trouble(omega, z0) {
                    None => Ok(nd * z0),
                    Some((cause, at_this_speed_only)) => Err(ModelError::ClearanceScale {
                        what: format!("stator `{}`", plan.name()),
                        omega,
                        cause,
                        at_this_speed_only,
                    }),
                }
            }
        };
        Ok(match plan {
            StatorPlan::Rod(r) => {
                let clearance = clearance(r.clearance)?;
                let ks = r.stiffness(kr);
                let e = ks * r.length / r.area;
                StatorModel::rod(
                    &r.name,
                    si,
                    st.radius,
                    clearance,
                    r.length,
                    ks * r.length,
                    e,
                    r.density * r.area,
                    r.elements,
                    r.angle_deg,
                    r.rayleigh,
                )?
            }
            StatorPlan::Ring(r) => {
                StatorModel::of_ring(r, si, st.radius, clearance(r.clearance)?, kr)
            }
            StatorPlan::Fe(f) => {
                let mut m = StatorModel::from_fe(f)?;
                m.clearance = m
                    .targets
                    .iter()
                    .map(|t| match t {
                        Target::Node { x0, .. } => x0[0].hypot(x0[1]) - st.radius,
                        Target::Ring { inner_radius, .. } => inner_radius - st.radius,
                    })
                    .fold(f64::INFINITY, f64::min);
                if m.clearance < 0.0 {
                    return Err(ModelError::Inconsistent {
                        what: format!("stator `{}`", f.name),
                        message: format!(
                            "a contact node lies inside the rotor section (clearance {:.3e} m ≤ 0)",
                            m.clearance
                        ),
                    });
                }
                m
            }
            StatorPlan::Mesh { model, placement } => {
                let mut m = StatorModel::clone(model);
                let radii: Vec<f64> = self.stations.iter().map(|s| s.radius).collect();
                match *placement {
                    Placement::At {
                        clearance: c,
                        approach_deg,
                    } => place(&mut m, &radii, clearance(c)?, approach_deg)?,
                    Placement::AsMeshed => m.clearance = clearance_of(&m, &radii),
                }
                if m.clearance.is_nan() || m.clearance <= 0.0 {
                    return Err(ModelError::Inconsistent {
                        what: format!("stator `{}`", m.name),
                        message: format!(
                            "a contact node lies inside the rotor section (clearance {:.3e} m ≤ 0): check the geometry's radii against the station radius {} m",
                            m.clearance, st.radius
                        ),
                    });
                }
                m
            }
        })
    }

    /// Stator `i` with its wear (`[stator.wear]`): the coefficient times `run.wear_acceleration`
    /// and each contact target's tributary area — a rod's cross-section, a meshed stator's share
    /// of its contact boundary; none for the others (the scene refuses wear on them).
    pub(super) fn with_wear(&self, i: usize, mut m: StatorModel) -> StatorModel {
        let Some(w) = self.wear.get(i).copied().flatten() else {
            return m;
        };
        let areas = match &self.stators[i] {
            StatorPlan::Rod(r) => vec![r.area; m.targets.len()],
            StatorPlan::Mesh { model, .. } => model
                .mesh
                .as_ref()
                .map_or_else(Vec::new, |d| d.contact_areas.clone()),
            _ => Vec::new(),
        };
        if areas.len() == m.targets.len() {
            m.wear = Some(StatorWear {
                rate: w.coefficient * w.acceleration,
                acceleration: w.acceleration,
                areas,
                layer: w.layer,
            });
        }
        m
    }
}

/// Clearance of a meshed stator as placed: the smallest distance from the surface of the
/// station each contact node faces (`radii[station]`, m) to that node (m).
fn clearance_of(model: &StatorModel, radii: &[f64]) -> f64 {
    model
        .targets
        .iter()
        .enumerate()
        .filter_map(|(t, tg)| match tg {
            Target::Node { x0, .. } => Some(x0[0].hypot(x0[1]) - radii[model.target_station(t)]),
            Target::Ring { .. } => None,
        })
        .fold(f64::INFINITY, f64::min)
}

/// Translates the stator rigidly along `approach_deg` so that, coming from far along that
/// direction, its first contact node meets the circle of radius `r + clearance` of its station
/// (`r = radii[station]`): the translation is `s d` with
/// `s = max_i (−x_i·d + √((x_i·d)² − |x_i|² + (r_i+δ)²))` over the contact nodes whose line of
/// approach meets their circle.
fn place(
    model: &mut StatorModel,
    radii: &[f64],
    clearance: f64,
    approach_deg: f64,
) -> Result<(), ModelError> {
    let t = approach_deg.to_radians();
    let d = [t.cos(), t.sin()];
    let s = model
        .targets
        .iter()
        .enumerate()
        .filter_map(|(i, tg)| match tg {
            Target::Node { x0, .. } => {
                let rc = radii[model.target_station(i)] + clearance;
                let b = x0[0] * d[0] + x0[1] * d[1];
                let disc = b * b - (x0[0] * x0[0] + x0[1] * x0[1]) + rc * rc;
                (disc >= 0.0).then(|| -b + disc.sqrt())
            }
            Target::Ring { .. } => None,
        })
        .fold(f64::NEG_INFINITY, f64::max);
    if !s.is_finite() {
        return Err(ModelError::Inconsistent {
            what: format!("stator `{}`", model.name),
            message: format!(
                "moved along approach_deg = {approach_deg}°, no contact node ever meets the rotor section: check approach_deg"
            ),
        });
    }
    for p in model.nodes.iter_mut() {
        p[0] += s * d[0];
        p[1] += s * d[1];
    }
    for tg in model.targets.iter_mut() {
        if let Target::Node { x0, .. } = tg {
            x0[0] += s * d[0];
            x0[1] += s * d[1];
        }
    }
    model.clearance = clearance_of(model, radii);
    model.angle_deg = Some(approach_deg);
    Ok(())
}
