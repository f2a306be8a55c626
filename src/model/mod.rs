//! Building the physical model from a validated scene.
//!
//! [`Model`] is speed independent (rotor, stations, stator descriptions). [`Model::case`]
//! resolves everything that depends on the speed ω — the clearance δ = δ_nd |Z0(ω)| when the
//! scene gives it non-dimensionally, the stator geometry placed at that clearance — into a
//! [`Case`] that the integrator runs.

pub mod rotor;
pub mod stator;

use crate::error::{Error, ModelError};
use crate::scene::{LoadedScene, RotorSpec, StatorSpec};
pub use rotor::{Jeffcott, RotorBody, UnbalanceLoad};
pub use stator::{StatorModel, Target};

/// A contact station: a radially rigid circular rotor section.
#[derive(Debug, Clone, PartialEq)]
pub struct Station {
    /// Name.
    pub name: String,
    /// Rotor node carrying the section centre.
    pub node: usize,
    /// Section radius r (m).
    pub radius: f64,
    /// Coulomb friction coefficient μ.
    pub friction: f64,
}

/// Rotor model kinds.
#[derive(Debug, Clone, PartialEq)]
pub enum Rotor {
    /// Jeffcott rotor.
    Jeffcott(Jeffcott),
}

impl Rotor {
    /// First natural frequency ω_n (rad/s) used to normalise speeds.
    pub fn natural_frequency(&self) -> f64 {
        match self {
            Rotor::Jeffcott(j) => j.natural_frequency(),
        }
    }
    /// |Z0(ω)| at a rotor node (m).
    pub fn z0(&self, _node: usize, omega: f64) -> f64 {
        match self {
            Rotor::Jeffcott(j) => j.z0(omega),
        }
    }
    /// The linear body at speed ω.
    pub fn body(&self, _omega: f64) -> RotorBody {
        match self {
            Rotor::Jeffcott(j) => j.body(),
        }
    }
    /// Stiffness k_r that `stiffness_ratio` ε refers to (N/m).
    pub fn reference_stiffness(&self) -> f64 {
        match self {
            Rotor::Jeffcott(j) => j.stiffness,
        }
    }
    /// Mass that the contact stiffness acts on, for the contact frequency √((k_r+k_s)/m) (kg).
    pub fn reference_mass(&self) -> f64 {
        match self {
            Rotor::Jeffcott(j) => j.mass,
        }
    }
    /// Largest natural frequency of the free rotor (rad/s).
    pub fn omega_max(&self) -> f64 {
        self.natural_frequency()
    }
    /// One-line description.
    pub fn describe(&self) -> String {
        match self {
            Rotor::Jeffcott(j) => format!(
                "Jeffcott rotor, 2 DOF: m = {:.6} kg, k = {:.6e} N/m, c = {:.6e} N·s/m (ξ = {:.4}), ω_n = {:.4} rad/s ({:.4} Hz)",
                j.mass,
                j.stiffness,
                j.damping,
                j.damping_ratio(),
                j.natural_frequency(),
                j.natural_frequency() / (2.0 * std::f64::consts::PI)
            ),
        }
    }
}

/// Speed-independent model.
#[derive(Debug, Clone)]
pub struct Model {
    /// The rotor.
    pub rotor: Rotor,
    /// Contact stations.
    pub stations: Vec<Station>,
    /// Stator specifications (resolved per speed).
    pub stator_specs: Vec<StatorSpec>,
}

/// Everything the integrator needs at one speed.
#[derive(Debug, Clone)]
pub struct Case {
    /// Speed ω (rad/s), positive = counter-clockwise seen from +z.
    pub omega: f64,
    /// ω/ω_n.
    pub speed_ratio: f64,
    /// The rotor's linear body at this speed.
    pub rotor: RotorBody,
    /// Rotor mass used for contact frequency estimates (kg).
    pub rotor_mass: f64,
    /// Rotor stiffness k_r (N/m).
    pub rotor_stiffness: f64,
    /// Largest free-rotor natural frequency (rad/s).
    pub rotor_omega_max: f64,
    /// Stations.
    pub stations: Vec<Station>,
    /// Stators placed at this speed's clearance.
    pub stators: Vec<StatorModel>,
    /// |Z0(ω)| at station 0 (or node 0 without stations) (m).
    pub z0: f64,
    /// Unbalance force magnitude |Σ m_u e e^{iφ}| ω² (N).
    pub unbalance_force: f64,
}

impl Model {
    /// Builds the model of a validated scene.
    pub fn build(ls: &LoadedScene) -> Result<Self, Error> {
        let s = &ls.scene;
        let rotor = match &s.rotor {
            RotorSpec::Jeffcott(j) => Rotor::Jeffcott(Jeffcott::from_spec(j)),
        };
        let stations = s
            .stations
            .iter()
            .map(|st| Station {
                name: st.name.clone(),
                node: st.node,
                radius: st.radius,
                friction: st.friction,
            })
            .collect();
        let m = Model {
            rotor,
            stations,
            stator_specs: s.stators.clone(),
        };
        // Build once at ω_n to surface model errors (singular stators) before any run.
        m.case(m.rotor.natural_frequency())?;
        Ok(m)
    }

    /// Index of a station by name.
    pub fn station_index(&self, name: &str) -> Option<usize> {
        self.stations.iter().position(|s| s.name == name)
    }

    /// Resolves the model at speed ω (rad/s).
    pub fn case(&self, omega: f64) -> Result<Case, ModelError> {
        let wn = self.rotor.natural_frequency();
        let node0 = self.stations.first().map_or(0, |s| s.node);
        let z0 = self.rotor.z0(node0, omega);
        let body = self.rotor.body(omega);
        let u = body.unbalance_resultant();
        let kr = self.rotor.reference_stiffness();
        let mut stators = Vec::new();
        for spec in &self.stator_specs {
            let si = self
                .station_index(spec.station())
                .expect("validated station name");
            let st = &self.stations[si];
            let zs = self.rotor.z0(st.node, omega);
            let resolve_clearance = |c: Option<f64>,
                                     c_nd: Option<f64>|
             -> Result<f64, ModelError> {
                match (c, c_nd) {
                    (Some(c), _) => Ok(c),
                    (None, Some(nd)) => {
                        if zs > 0.0 {
                            Ok(nd * zs)
                        } else {
                            Err(ModelError::Inconsistent {
                                what: format!("stator `{}`", spec.name()),
                                message: "clearance_nd needs a non-zero unbalance response |Z0|; give `clearance` in metres".into(),
                            })
                        }
                    }
                    _ => unreachable!("validated clearance"),
                }
            };
            let model = match spec {
                StatorSpec::Rod(r) => {
                    let clearance = resolve_clearance(r.clearance, r.clearance_nd)?;
                    let ks = match (r.stiffness_ratio, r.youngs_modulus) {
                        (Some(eps), _) => eps * kr,
                        (None, Some(e)) => e * r.area / r.length,
                        _ => unreachable!("validated rod stiffness"),
                    };
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
                StatorSpec::Ring(r) => {
                    let clearance = resolve_clearance(r.clearance, r.clearance_nd)?;
                    let ks = r
                        .stiffness
                        .unwrap_or_else(|| r.stiffness_ratio.unwrap_or(0.0) * kr);
                    StatorModel::ring(&r.name, si, st.radius, clearance, ks, r.mass, r.damping)
                }
                StatorSpec::Fe(f) => {
                    let mut m = StatorModel::from_fe(f, si)?;
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
            };
            stators.push(model);
        }
        Ok(Case {
            omega,
            speed_ratio: omega / wn,
            rotor: body,
            rotor_mass: self.rotor.reference_mass(),
            rotor_stiffness: kr,
            rotor_omega_max: self.rotor.omega_max(),
            stations: self.stations.clone(),
            stators,
            z0,
            unbalance_force: u[0].hypot(u[1]) * omega * omega,
        })
    }
}
