//! Building the physical model from a resolved scene.
//!
//! [`Model`] is speed independent (rotor, stations, stators as far as they do not depend on
//! the speed). It is built from the resolve stage's plain data ([`crate::resolve::Resolved`]) by
//! [`Model::build`], or from a loaded scene in one call by [`Model::from_scene`] (resolve, then
//! build). [`Model::case`] evaluates everything that depends on the speed ω — the clearance
//! δ = δ_nd |Z0(ω)| when the scene gives it non-dimensionally, a stiffness ε k_r, the stator
//! geometry placed at that clearance — into a [`Case`] that the integrator runs.
//!
//! The model does no file I/O and runs no mesher: meshes come read with the resolved data.

mod blame;
pub mod bow;
pub mod drive;
pub mod events;
pub mod fe_rotor;
mod place;
pub mod reduce;
pub mod rotor;
pub mod section;
pub mod speed_profile;
pub mod stator;

use crate::contact::Dashpot;
use crate::error::{Error, ModelError};
use crate::resolve::{
    Clearance, FeRotorInput, FeStatorInput, Placement, Resolved, RingInput, RodInput, RotorInput,
    StatorInput,
};
use crate::scene::{LoadedScene, RayleighOn};
pub use drive::{Drive, DriveLaw};
pub use events::{ClearanceEvent, Events, UnbalanceEvent};
pub use reduce::ReducedRotor;
pub use rotor::{Jeffcott, RotatingLoad, RotorBody, UnbalanceLoad};
pub use speed_profile::{SpeedProfile, SpinState};
pub use stator::ring::RingSupport;
pub use stator::StatorModel;
use std::sync::Arc;

// The contact target is contact's type; re-exported for the paths `crate::model::Target` in use.
pub use crate::contact::Target;
// A station is resolved data; re-exported for the paths `crate::model::Station` in use.
pub use crate::resolve::Station;

/// An FE rotor with the quantities the non-dimensional inputs refer to.
#[derive(Debug, Clone)]
pub struct FeModel {
    /// The assembled rotor.
    pub rotor: fe_rotor::FeRotor,
    /// First undamped natural frequency at rest without gyroscopics (rad/s): the ω_n of ω/ω_n.
    pub omega_n: f64,
    /// Largest natural frequency (rad/s), for the explicit stability limit.
    pub omega_max: f64,
    /// Node whose response and stiffness define |Z0| and k_r (first station's node).
    pub reference_node: usize,
    /// Static stiffness at the reference node, k_r = 1/(K⁻¹)_yy (N/m): what ε = k_s/k_r uses.
    pub k_ref: f64,
    /// Damping ratio of the highest mode from Rayleigh damping, (α/ω + βω)/2 at ω_max.
    pub xi_max: f64,
    /// `(M⁻¹)_xx` per node (1/kg).
    pub inv_mass_node: Vec<f64>,
}

/// Rotor model kinds.
#[derive(Debug, Clone)]
pub enum Rotor {
    /// Jeffcott rotor.
    Jeffcott(Jeffcott),
    /// Finite-element rotor.
    Fe(Box<FeModel>),
}

impl Rotor {
    /// The polar moment of inertia of the rotor about its axis (kg·m²): the Jeffcott disk's
    /// `m D²/8`, or an FE rotor's shaft elements `ρ I_p ℓ` and disks `I_p`; `None` when the
    /// scene gives no geometry to compute it from (a Jeffcott `mass`, an FE rotor of
    /// massless elements).
    pub fn polar_inertia(&self) -> Option<f64> {
        match self {
            Rotor::Jeffcott(j) => j.polar_inertia,
            Rotor::Fe(f) => Some(f.rotor.total_polar_inertia),
        }
        .filter(|j| j.is_finite() && *j > 0.0)
    }

    /// First natural frequency ω_n (rad/s) used to normalise speeds.
    pub fn natural_frequency(&self) -> f64 {
        match self {
            Rotor::Jeffcott(j) => j.natural_frequency(),
            Rotor::Fe(f) => f.omega_n,
        }
    }
    /// |Z0(ω)| at a rotor node (m): the major semi-axis of the steady unbalance response
    /// without stator.
    ///
    /// # Errors
    /// [`ModelError`] when the dynamic stiffness `K − ω²M + iω(C + ωG)` of an FE rotor is
    /// singular at ω (an undamped rotor exactly at a critical speed): |Z0| is not defined there.
    pub fn z0(&self, node: usize, omega: f64) -> Result<f64, ModelError> {
        Ok(self.forced_ellipses(omega)?[node][0])
    }
    /// The steady unbalance response without stator at ω, per rotor node: the major
    /// semi-axes of the forced ellipses of the displacement `[u_x, u_y]` (m, |Z0| at the node)
    /// and of the rotation `[θ_x, θ_y]` (rad; 0 for the Jeffcott rotor).
    ///
    /// # Errors
    /// As [`Rotor::z0`].
    pub fn forced_ellipses(&self, omega: f64) -> Result<Vec<[f64; 2]>, ModelError> {
        match self {
            Rotor::Jeffcott(j) => Ok(vec![[j.z0(omega), 0.0]]),
            Rotor::Fe(f) => {
                let q = f.rotor.unbalance_response(omega)?;
                Ok((0..f.rotor.nodes())
                    .map(|i| {
                        let e = |k: usize| fe_rotor::ellipse_major(q[4 * i + k], q[4 * i + k + 1]);
                        [e(0), e(2)]
                    })
                    .collect())
            }
        }
    }
    /// The linear body at speed ω.
    pub fn body(&self, omega: f64) -> Result<RotorBody, ModelError> {
        match self {
            Rotor::Jeffcott(j) => Ok(j.body()),
            Rotor::Fe(f) => f.rotor.body(omega),
        }
    }
    /// Stiffness k_r that `stiffness_ratio` ε refers to (N/m).
    pub fn reference_stiffness(&self) -> f64 {
        match self {
            Rotor::Jeffcott(j) => j.stiffness,
            Rotor::Fe(f) => f.k_ref,
        }
    }
    /// Mass that the contact stiffness acts on, for the contact frequency √((k_r+k_s)/m) (kg).
    pub fn reference_mass(&self) -> f64 {
        match self {
            Rotor::Jeffcott(j) => j.mass,
            Rotor::Fe(f) => f.k_ref / (f.omega_n * f.omega_n),
        }
    }
    /// Largest natural frequency of the free rotor (rad/s).
    pub fn omega_max(&self) -> f64 {
        match self {
            Rotor::Jeffcott(j) => j.natural_frequency(),
            Rotor::Fe(f) => f.omega_max,
        }
    }
    /// `(M, K, C, G)` at speed ω: C without the gyroscopic part (modal damping included,
    /// dense), G per unit spin.
    #[allow(clippy::type_complexity)]
    pub fn matrices(
        &self,
        omega: f64,
    ) -> Result<
        (
            crate::linalg::Csc,
            crate::linalg::Csc,
            crate::linalg::Csc,
            crate::linalg::Csc,
        ),
        ModelError,
    > {
        Ok(match self {
            Rotor::Jeffcott(j) => {
                let b = j.body();
                (b.m, b.k, b.c, crate::linalg::Csc::zeros(2, 2))
            }
            Rotor::Fe(f) => (
                f.rotor.m.clone(),
                f.rotor.k(omega),
                f.rotor.c(omega)?,
                f.rotor.g.clone(),
            ),
        })
    }
    /// Whether a bearing's coefficients are tabulated over speed (K(Ω), C(Ω)): a transient run
    /// of such a rotor would need its stiffness and damping to follow Ω(t), which is not
    /// implemented. (The gyroscopic terms Ω G and Ω̇ K_st are: `time::spin`.)
    pub fn speed_tabulated(&self) -> bool {
        match self {
            Rotor::Jeffcott(_) => false,
            Rotor::Fe(f) => f.rotor.bearings.iter().any(|b| b.speeds.len() >= 2),
        }
    }
    /// Number of lateral DOFs (`0..n`): bending and pedestals (2 for a Jeffcott rotor). The
    /// axial and torsional DOFs of an FE rotor come after them, uncoupled.
    pub fn lateral_dofs(&self) -> usize {
        match self {
            Rotor::Jeffcott(_) => 2,
            Rotor::Fe(f) => f.rotor.ndof_lateral,
        }
    }
    /// The rigid-body modes `[axial, torsional]` of free axial and torsional DOFs
    /// ([`fe_rotor::FeRotor::rigid_body_modes`]); none for a Jeffcott rotor.
    pub fn rigid_body_modes(&self) -> [Option<Vec<f64>>; 2] {
        match self {
            Rotor::Jeffcott(_) => [None, None],
            Rotor::Fe(f) => f.rotor.rigid_body_modes(),
        }
    }
    /// Number of rotor nodes.
    pub fn node_count(&self) -> usize {
        match self {
            Rotor::Jeffcott(_) => 1,
            Rotor::Fe(f) => f.rotor.nodes(),
        }
    }
    /// `[u_x, u_y]` DOFs of a node.
    pub fn node_dofs(&self, node: usize) -> [usize; 2] {
        match self {
            Rotor::Jeffcott(_) => [0, 1],
            Rotor::Fe(_) => [4 * node, 4 * node + 1],
        }
    }
    /// Complex unbalance response vector at speed ω (see [`fe_rotor::FeRotor::unbalance_response`]).
    pub fn unbalance_response(
        &self,
        omega: f64,
    ) -> Result<Vec<num_complex::Complex64>, ModelError> {
        match self {
            Rotor::Jeffcott(j) => {
                let b = j.body();
                let u = b.unbalance_resultant();
                let f = num_complex::Complex64::new(u[0], u[1]) * omega * omega;
                let d = num_complex::Complex64::new(
                    j.stiffness - j.mass * omega * omega,
                    j.damping * omega,
                );
                let x = f / d;
                Ok(vec![x, x * num_complex::Complex64::new(0.0, -1.0)])
            }
            Rotor::Fe(f) => f.rotor.unbalance_response(omega),
        }
    }
    /// `(M⁻¹)_xx` at a node (1/kg).
    pub fn inv_mass(&self, node: usize) -> f64 {
        match self {
            Rotor::Jeffcott(j) => 1.0 / j.mass,
            Rotor::Fe(f) => f.inv_mass_node[node],
        }
    }
    /// Damping ratio used in the explicit stability limit of the highest rotor mode.
    pub fn damping_ratio_max(&self) -> f64 {
        match self {
            Rotor::Jeffcott(j) => j.damping_ratio(),
            Rotor::Fe(f) => f.xi_max,
        }
    }
    /// One-line description.
    pub fn describe(&self) -> String {
        match self {
            Rotor::Jeffcott(j) => format!(
                "Jeffcott rotor, 2 DOF: m = {:.6} kg, k = {:.6e} N/m, c = {:.6e} N·s/m (ξ = {:.4}), ω_n = {} rad/s ({} Hz, full precision)",
                j.mass,
                j.stiffness,
                j.damping,
                j.damping_ratio(),
                j.natural_frequency(),
                j.natural_frequency() / (2.0 * std::f64::consts::PI)
            ),
            Rotor::Fe(f) => format!(
                "FE rotor (Timoshenko): {} nodes, {} elements, {} DOF ({}), {} disks, {} bearings; mass {:.4} kg, polar inertia {:.4e} kg·m²; damping: {}; ω_n = {} rad/s ({} Hz, first lateral mode, full precision), highest free-rotor mode ω_max,rotor = {:.4e} rad/s; reference node {} with k_r = {:.4e} N/m",
                f.rotor.nodes(),
                f.rotor.nodes() - 1,
                f.rotor.ndof,
                {
                    let mut d = vec!["u_x u_y θ_x θ_y"];
                    if f.rotor.node_axial.iter().any(|a| a.is_some()) {
                        d.push("u_z");
                    }
                    if f.rotor.node_torsion.iter().any(|a| a.is_some()) {
                        d.push("θ_z");
                    }
                    d.join(" ") + " per node"
                },
                f.rotor.disks.len(),
                f.rotor.bearings.len(),
                f.rotor.total_mass,
                f.rotor.total_polar_inertia,
                {
                    let [a, b] = f.rotor.rayleigh;
                    let mut d = vec![format!("Rayleigh α = {a}, β = {b}")];
                    if let Some(md) = f.rotor.modal_damping {
                        d.push(format!(
                            "modal ζ = {} on modes ≤ {} rad/s, at most {}",
                            md.ratio,
                            if md.max_frequency.is_finite() { format!("{}", md.max_frequency) } else { "∞".into() },
                            if md.modes == usize::MAX { "all".into() } else { md.modes.to_string() }
                        ));
                    }
                    match f.rotor.rayleigh_on {
                        RayleighOn::Assembly => {}
                        RayleighOn::Shaft => d[0].push_str(" on the shaft elements only"),
                        RayleighOn::Rotor => d[0].push_str(" on the rotor's mass and the shaft's stiffness"),
                    }
                    d.push("bearings".into());
                    d.join(", ")
                },
                f.omega_n,
                f.omega_n / (2.0 * std::f64::consts::PI),
                f.omega_max,
                f.reference_node,
                f.k_ref
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
    /// Stators, in scene order, as far as they are speed independent.
    pub stators: Vec<StatorPlan>,
    /// The contact dashpot of each stator (`contact_damping`), in scene order.
    pub dashpots: Vec<Dashpot>,
    /// Rotor node the analysis observes (`output.node`); `None`: the first station's node.
    pub observed_node: Option<usize>,
    /// The rotor's modal reduction for the time loop (`[run.reduction]`): every case is
    /// reduced ([`Case::reduce`]); `None`: the full model.
    pub reduction: Option<crate::resolve::ReductionInput>,
    /// Each stator's wear (`[stator.wear]`), in scene order; `None` without wear.
    pub wear: Vec<Option<crate::resolve::WearInput>>,
}

/// A stator before a speed is chosen: what [`Model::case`] makes a [`StatorModel`] of.
#[derive(Debug, Clone)]
pub enum StatorPlan {
    /// A rod, built per speed (its clearance and stiffness may depend on it).
    Rod(RodInput),
    /// A ring, built per speed.
    Ring(RingInput),
    /// A general FE stator, built per speed; its clearance follows from its geometry.
    Fe(FeStatorInput),
    /// A meshed stator, assembled once, shared by every speed, and placed per speed.
    Mesh {
        /// The assembled stator as meshed.
        model: Arc<StatorModel>,
        /// Where it is placed at each speed.
        placement: Placement,
    },
}

impl StatorPlan {
    /// The stator's name.
    pub fn name(&self) -> &str {
        match self {
            StatorPlan::Rod(r) => &r.name,
            StatorPlan::Ring(r) => &r.name,
            StatorPlan::Fe(f) => &f.name,
            StatorPlan::Mesh { model, .. } => &model.name,
        }
    }
    /// Index of the station it faces.
    pub fn station(&self) -> usize {
        match self {
            StatorPlan::Rod(r) => r.station,
            StatorPlan::Ring(r) => r.station,
            StatorPlan::Fe(f) => f.station,
            StatorPlan::Mesh { model, .. } => model.station,
        }
    }
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
    /// Damping ratio of the highest rotor mode (for the stability limit).
    pub rotor_xi_max: f64,
    /// `(M⁻¹)_xx` at each station's node (1/kg), for the contact stability bound.
    pub station_inv_mass: Vec<f64>,
    /// Largest free-rotor natural frequency (rad/s).
    pub rotor_omega_max: f64,
    /// Stations.
    pub stations: Vec<Station>,
    /// Stators placed at this speed's clearance.
    pub stators: Vec<StatorModel>,
    /// Rotor node whose response the analysis reads (`output.node`; default: station 0's node,
    /// or node 0 without stations).
    pub observed_node: usize,
    /// |Z0(ω)| at the observed node (m): the unit of the non-dimensional orbits.
    pub z0: f64,
    /// Largest |Z0(ω)| over every rotor node (m): the length scale of the response wherever
    /// the stations and the observed node are.
    pub z0_max: f64,
    /// Largest amplitude of the forced rotation `[θ_x, θ_y]` over every rotor node (rad; 0 for
    /// the Jeffcott rotor).
    pub tilt0_max: f64,
    /// Unbalance force magnitude |Σ m_u e e^{iφ}| ω² (N).
    pub unbalance_force: f64,
    /// The rotor reduced for the time loop ([`Case::reduce`]); `None`: the loop integrates
    /// `rotor` itself.
    pub reduced: Option<Box<ReducedRotor>>,
}

impl Rotor {
    /// Why |Z0(ω)| = `z0` cannot scale a `clearance_nd`, naming the input responsible and the
    /// remedy, and whether only this speed is affected; `None` when `z0` is a usable positive
    /// finite length. In order: the rotor's mass, stiffness or damping is not finite (or the
    /// Jeffcott mass or stiffness not positive); ω ≤ 0 or ω² overflows; the unbalance is not
    /// finite or sums to zero; an undamped rotor at its critical speed (|Z0| infinite:
    /// `|k − mω²| ≤ 10⁻⁹ k` for the Jeffcott rotor); |Z0| zero or not finite for any other
    /// reason (a stiffness or damping so large the rotor does not move).
    pub fn z0_trouble(&self, omega: f64, z0: f64) -> Option<(String, bool)> {
        const METRES: &str = "give `clearance` in metres instead";
        let trouble = |cause: String| Some((format!("{cause}: {METRES}"), false));
        let finite = |a: &crate::linalg::Csc| a.values().iter().all(|v| v.is_finite());
        let resonance = match self {
            Rotor::Jeffcott(j) => {
                for (what, v, keys) in [
                    ("mass", j.mass, "`rotor.mass` or `rotor.disk`"),
                    (
                        "stiffness",
                        j.stiffness,
                        "`rotor.stiffness` or `rotor.shaft`",
                    ),
                    (
                        "damping",
                        j.damping,
                        "`rotor.damping` or `rotor.damping_ratio`",
                    ),
                ] {
                    if !v.is_finite() || (what != "damping" && v <= 0.0) {
                        return trouble(format!("and the rotor {what} is {v:e} (from {keys})"));
                    }
                }
                j.damping == 0.0
                    && (j.stiffness - j.mass * omega * omega).abs() <= 1e-9 * j.stiffness
            }
            Rotor::Fe(f) => {
                if !finite(&f.rotor.m) || !finite(&f.rotor.k(omega)) {
                    return trouble("and the rotor's mass or stiffness matrix is not finite (a `rotor.shaft`, `rotor.disk`, `rotor.mass` or `rotor.bearing` value overflows)".into());
                }
                false
            }
        };
        if !(omega * omega).is_finite() || omega <= 0.0 {
            return trouble(format!(
                "a speed out of range (lower or raise `--speed`, `run.speed_ratio`, `run.speed` or `run.sweep`; ω_n = {:e} rad/s)",
                self.natural_frequency()
            ));
        }
        let loads = match self {
            Rotor::Jeffcott(j) => &j.unbalance,
            Rotor::Fe(f) => &f.rotor.unbalance,
        };
        let u = loads.iter().fold([0.0_f64, 0.0], |a, l| {
            [a[0] + l.me * l.phase.cos(), a[1] + l.me * l.phase.sin()]
        });
        let key = "`rotor.unbalance` (mass, radius, phase_deg)";
        if !(u[0].is_finite() && u[1].is_finite()) {
            return trouble(format!(
                "and the unbalance Σ m_u e e^(iφ) is not finite: check {key}"
            ));
        }
        if u[0] == 0.0 && u[1] == 0.0 {
            return trouble(format!(
                "which is 0: the rotor has no net unbalance (none, zero masses or masses that cancel in {key})"
            ));
        }
        if resonance || z0.is_infinite() {
            let damping = match self {
                Rotor::Jeffcott(_) => "`rotor.damping_ratio` or `rotor.damping`",
                Rotor::Fe(_) => "`rotor.rayleigh`, `rotor.modal_damping` or bearing `damping`",
            };
            return Some((
                format!(
                    "which is infinite: the undamped rotor is at its critical speed (ω/ω_n = {:.6}); {METRES}, add damping ({damping}) or run another speed",
                    omega / self.natural_frequency()
                ),
                true,
            ));
        }
        if z0.is_finite() && z0 > 0.0 {
            return None;
        }
        trouble(format!(
            "which is {z0:e}: the rotor's stiffness or damping is so large that it does not respond (check `rotor.damping_ratio`, `rotor.stiffness`, `rotor.shaft`, the bearings)"
        ))
    }

    /// Builds the rotor of resolved data: an FE rotor is assembled and its ω_n (first lateral
    /// mode), ω_max, reference stiffness k_r and `(M⁻¹)_xx` per node are computed.
    pub fn build(input: &RotorInput) -> Result<Self, ModelError> {
        Ok(match input {
            RotorInput::Jeffcott(j) => Rotor::Jeffcott(Jeffcott::new(j)),
            RotorInput::Fe(f) => Rotor::Fe(Box::new(FeModel::build(f)?)),
        })
    }
}

impl FeModel {
    /// Assembles the FE rotor and the quantities the non-dimensional inputs refer to.
    pub fn build(f: &FeRotorInput) -> Result<Self, ModelError> {
        let mut rotor = fe_rotor::FeRotor::build(&f.data)?;
        if !fe_rotor::held_laterally(&f.data.bearings) {
            return Err(fe_rotor::pivots());
        }
        if !f.gyroscopic {
            rotor.g = crate::linalg::Csc::zeros(rotor.ndof, rotor.ndof);
        }
        // ω_n of ω/ω_n: the first lateral mode (axial and torsional modes, when the rotor has
        // those DOFs, are not what the speed ratio refers to); ω_max over all DOFs, for the
        // stability limit.
        let freqs = rotor.undamped_frequencies(0.0)?;
        let lateral = rotor.lateral_frequencies(0.0)?;
        let omega_n =
            lateral
                .iter()
                .copied()
                .find(|w| *w > 1e-6)
                .ok_or_else(|| ModelError::Singular {
                    what: "rotor".into(),
                    detail: "no positive natural frequency".into(),
                })?;
        let omega_max = freqs.last().copied().unwrap_or(omega_n);
        let reference_node = f.reference_node;
        let k_ref = rotor.node_stiffness(reference_node)?;
        let minv = fe_rotor::dense(&rotor.m)
            .try_inverse()
            .ok_or_else(|| ModelError::Singular {
                what: "rotor mass matrix".into(),
                detail: "not invertible".into(),
            })?;
        let inv_mass_node = (0..rotor.nodes()).map(|i| minv[(4 * i, 4 * i)]).collect();
        let [a, b] = f.data.rayleigh;
        let xi_max = (0.5 * (a / omega_max + b * omega_max)).min(1.0);
        Ok(FeModel {
            rotor,
            omega_n,
            omega_max,
            reference_node,
            k_ref,
            xi_max,
            inv_mass_node,
        })
    }
}

impl Model {
    /// Builds the model of a resolved scene: the rotor, the stations, the meshed stators
    /// (assembled once; the others are built per speed), then the case at ω_n, so that model
    /// errors (a singular stator, a clearance that cannot be placed) surface before any run.
    pub fn build(r: &Resolved) -> Result<Self, Error> {
        let rotor = Rotor::build(&r.rotor)?;
        let nodes = rotor.node_count();
        for (what, n) in r
            .stations
            .iter()
            .map(|st| (format!("station `{}`", st.name), st.node))
            .chain(r.observed_node.map(|n| ("observed node".to_string(), n)))
        {
            if n >= nodes {
                return Err(ModelError::Inconsistent {
                    what,
                    message: format!("node {n} does not exist (the rotor has {nodes} nodes)"),
                }
                .into());
            }
        }
        let mut stators = Vec::with_capacity(r.stators.len());
        for s in &r.stators {
            stators.push(match s {
                StatorInput::Rod(x) => StatorPlan::Rod(x.clone()),
                StatorInput::Ring(x) => StatorPlan::Ring(x.clone()),
                StatorInput::Fe(x) => StatorPlan::Fe(x.clone()),
                StatorInput::Mesh(ms) => {
                    // Axial positions of the stations a 3-D stator may face.
                    let stations_z: Vec<(usize, f64)> = ms
                        .stations
                        .iter()
                        .map(|&i| {
                            let z = match &rotor {
                                Rotor::Fe(f) => f.rotor.z[r.stations[i].node],
                                _ => 0.0,
                            };
                            (i, z)
                        })
                        .collect();
                    StatorPlan::Mesh {
                        model: Arc::new(stator::mesh::from_input(ms, &stations_z)?),
                        placement: ms.placement,
                    }
                }
            });
        }
        let m = Model {
            rotor,
            stations: r.stations.clone(),
            stators,
            dashpots: r.dashpots.clone(),
            observed_node: r.observed_node,
            reduction: r.reduction,
            wear: r.wear.clone(),
        };
        // An undamped rotor has no |Z0| at ω_n itself: that speed's runs say so; the model is
        // fine.
        match m.case(m.rotor.natural_frequency()) {
            Err(ModelError::ClearanceScale {
                at_this_speed_only: true,
                ..
            })
            | Ok(_) => Ok(m),
            Err(e) => Err(e.into()),
        }
    }

    /// Resolves a loaded scene ([`crate::resolve::resolve`]: checks, meshes) and builds its
    /// model.
    pub fn from_scene(ls: &LoadedScene) -> Result<Self, Error> {
        let r = crate::resolve::resolve(ls)?;
        Self::build(&r).map_err(|e| blame::stators(ls, blame::bearings(ls, &r, e)))
    }

    /// Index of a station by name.
    pub fn station_index(&self, name: &str) -> Option<usize> {
        self.stations.iter().position(|s| s.name == name)
    }

    /// Resolves the model at speed ω (rad/s), reduced as the scene asks (`[run.reduction]`).
    pub fn case(&self, omega: f64) -> Result<Case, ModelError> {
        self.case_with(omega, self.reduction.as_ref())
    }

    /// Resolves the model at speed ω (rad/s), reduced as `reduction` says (`None`: the full
    /// model) instead of as the scene asks: the reduced schemes of the error-target choice.
    pub fn case_with(
        &self,
        omega: f64,
        reduction: Option<&crate::resolve::ReductionInput>,
    ) -> Result<Case, ModelError> {
        let wn = self.rotor.natural_frequency();
        let observed_node = self
            .observed_node
            .unwrap_or_else(|| self.stations.first().map_or(0, |s| s.node));
        // One forced response for |Z0| at the observed node, at the stations and everywhere.
        let forced = self.rotor.forced_ellipses(omega)?;
        let z0 = forced[observed_node][0];
        let body = self.rotor.body(omega)?;
        let u = body.unbalance_resultant();
        let kr = self.rotor.reference_stiffness();
        let stators = self
            .stators
            .iter()
            .enumerate()
            .map(|(i, plan)| {
                // A placement that never meets the rotor names the stator's `approach_deg`.
                self.stator_at(plan, omega, kr, &forced)
                    .and_then(|m| self.with_dashpot(i, m))
                    .map(|m| self.with_wear(i, m))
                    .map_err(|e| blame::approach(i, e))
            })
            .collect::<Result<Vec<_>, _>>()?;
        Case {
            omega,
            speed_ratio: omega / wn,
            rotor: body,
            rotor_mass: self.rotor.reference_mass(),
            rotor_stiffness: kr,
            rotor_xi_max: self.rotor.damping_ratio_max(),
            station_inv_mass: self
                .stations
                .iter()
                .map(|s| self.rotor.inv_mass(s.node))
                .collect(),
            rotor_omega_max: self.rotor.omega_max(),
            stations: self.stations.clone(),
            stators,
            observed_node,
            z0,
            z0_max: forced.iter().map(|e| e[0]).fold(0.0, f64::max),
            tilt0_max: forced.iter().map(|e| e[1]).fold(0.0, f64::max),
            unbalance_force: u[0].hypot(u[1]) * omega * omega,
            reduced: None,
        }
        .reduced_by(reduction)
    }
}
