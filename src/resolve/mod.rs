//! The resolve stage: a loaded scene becomes the plain data the model is built from.
//!
//! [`resolve`] checks the scene ([`crate::scene::validate()`], the same rules and messages as
//! when it was loaded: its fields are public and may have changed since) and turns what the
//! user wrote into what the model needs:
//!
//! * names into indices: the station each stator faces, the further stations of a 3-D meshed
//!   stator;
//! * alternative keys and names into enums: a clearance in metres or times |Z0(ω)|
//!   ([`Clearance`]), a stiffness as ε k_r or from the material ([`stator::RodStiffness`],
//!   [`stator::RingStiffness`]), Jeffcott mass, stiffness and damping from whichever keys are
//!   given, a mesh's plane stress or strain;
//! * FE rotor specs into element, disk and bearing data ([`rotor::FeRotorData`]);
//! * geometry files into meshes: found beside the scene or in its ancestors, meshed by gmsh when
//!   the cached mesh is out of date, read ([`mesh`]).
//!
//! The choices are read from the rules that checked them ([`crate::scene::validate::one_of`]
//! and its siblings), so a resolved value never rests on an unchecked assumption, and an error
//! names the file, the dotted key and the line as validation does. File and gmsh errors are
//! [`crate::error::MeshError`]s naming the files.
//!
//! What depends on the speed (a clearance relative to |Z0(ω)|, a stiffness relative to k_r, the
//! placement of a meshed stator) stays in the enums and is evaluated by
//! [`crate::model::Model::case`].

pub mod mesh;
pub mod rotor;
pub mod stator;

pub use mesh::{MeshStatorInput, MeshStatorParams, Placement};
pub use rotor::{FeRotorData, FeRotorInput, JeffcottData, RotorInput};
pub use stator::{
    FeElement, FeStatorInput, RingInput, RingStiffness, RodInput, RodStiffness, StatorInput,
};

use crate::contact::Dashpot;
use crate::error::Error;
use crate::scene::validate::OneOf;
use crate::scene::{validate, LoadedScene, StationSpec};

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
    /// Coulomb friction with stick (`station.N.stick`): the tangential force an unknown inside
    /// the cone `|t| ≤ μ p`; false: permanent slip.
    pub stick: bool,
}

impl From<&StationSpec> for Station {
    fn from(st: &StationSpec) -> Self {
        Station {
            name: st.name.clone(),
            node: st.node,
            radius: st.radius,
            friction: st.friction,
            stick: st.stick,
        }
    }
}

/// A scene resolved: what [`crate::model::Model::build`] builds from.
#[derive(Debug, Clone)]
pub struct Resolved {
    /// The rotor.
    pub rotor: RotorInput,
    /// Contact stations, in scene order (stators refer to them by index).
    pub stations: Vec<Station>,
    /// Stators, in scene order.
    pub stators: Vec<StatorInput>,
    /// The contact dashpot of each stator, in scene order (`contact_damping`).
    pub dashpots: Vec<Dashpot>,
    /// Rotor node the analysis observes (`output.node`); `None`: the first station's node.
    pub observed_node: Option<usize>,
    /// The FE rotor's modal reduction (`[run.reduction]`); `None`: the full model.
    pub reduction: Option<ReductionInput>,
    /// Each stator's wear, in scene order (`[stator.wear]`); `None` without wear.
    pub wear: Vec<Option<WearInput>>,
}

/// A stator's Archard wear (`scene::wear`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WearInput {
    /// k (m²/N): Archard's dimensional wear coefficient.
    pub coefficient: f64,
    /// A: the wear magnification `run.wear_acceleration`.
    pub acceleration: f64,
    /// The elasto-plastic abradable coating (`[stator.abradable]`, `scene::abradable`); `None`
    /// without. A stator with a coating and no `[stator.wear]` has `coefficient` 0.
    pub layer: Option<AbradableLayer>,
}

/// A stator's elasto-plastic abradable coating (`scene::abradable`), the same for each of its
/// contact nodes but for the node's tributary area `A` (m²).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AbradableLayer {
    /// Thickness h (m).
    pub thickness: f64,
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Yield stress σ_y (Pa).
    pub yield_stress: f64,
    /// Linear hardening modulus H (Pa, ≥ 0).
    pub hardening_modulus: f64,
}

impl AbradableLayer {
    /// A node's coating of tributary area `area` (m²): `[k_a, f_0, k_h]` — the elastic
    /// stiffness `k_a = E A / h` (N/m), the initial yield force `f_0 = A σ_y` (N) and the
    /// hardening stiffness `k_h = H A / h` (N/m), so that the yield force after a plastic
    /// shortening `d_p` is `f_y = f_0 + k_h d_p`.
    pub fn at(&self, area: f64) -> [f64; 3] {
        [
            self.youngs_modulus * area / self.thickness,
            self.yield_stress * area,
            self.hardening_modulus * area / self.thickness,
        ]
    }
}

/// `[run.reduction]` resolved: the cut-off ω_cut (rad/s) is `cutoff` when given, else
/// `cutoff_factor × max(harmonics × ω, ω_c)` at each case's speed ω
/// ([`crate::model::Case::reduce`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReductionInput {
    /// A fixed cut-off (rad/s).
    pub cutoff: Option<f64>,
    /// κ of the default cut-off (≥ 1).
    pub cutoff_factor: f64,
    /// The paper rule's n (`run.harmonics`).
    pub harmonics: f64,
    /// Reduce the FE rotor.
    pub rotor: bool,
    /// Reduce every meshed stator with mass ([`crate::model::stator::reduce`]).
    pub stators: bool,
    /// Neither `cutoff` nor `cutoff_factor` given: with `run.auto_step` the factor is chosen
    /// from `run.tolerance` (`analysis::cutoff`), else it is the default.
    pub auto: bool,
}

/// Checks and resolves a loaded scene; meshes of meshed stators are found, made and read here.
pub fn resolve(ls: &LoadedScene) -> Result<Resolved, Error> {
    validate(ls)?;
    let s = &ls.scene;
    let rotor = rotor::resolve(ls)?;
    let stators = s
        .stators
        .iter()
        .enumerate()
        .map(|(i, spec)| stator::resolve(ls, i, spec))
        .collect::<Result<_, _>>()?;
    Ok(Resolved {
        rotor,
        stations: s.stations.iter().map(Station::from).collect(),
        stators,
        dashpots: s
            .stators
            .iter()
            .map(|spec| {
                let (c, mode) = spec.contact_damping();
                Dashpot {
                    c,
                    full: mode == "full",
                }
            })
            .collect(),
        observed_node: s.output.node,
        wear: s
            .stators
            .iter()
            .map(|spec| {
                let layer = spec.abradable().map(|a| AbradableLayer {
                    thickness: a.thickness,
                    youngs_modulus: a.youngs_modulus,
                    yield_stress: a.yield_stress,
                    hardening_modulus: a.hardening_modulus,
                });
                (spec.wear().is_some() || layer.is_some()).then(|| WearInput {
                    coefficient: spec.wear().map_or(0.0, |w| w.coefficient),
                    acceleration: s.run.wear_acceleration,
                    layer,
                })
            })
            .collect(),
        reduction: s.run.reduction.map(|r| ReductionInput {
            cutoff: r.cutoff,
            cutoff_factor: r
                .cutoff_factor
                .unwrap_or(crate::scene::DEFAULT_CUTOFF_FACTOR),
            harmonics: s.run.harmonics,
            rotor: r
                .rotor
                .unwrap_or(matches!(s.rotor, crate::scene::RotorSpec::Fe(_))),
            stators: r.stators.unwrap_or(false),
            auto: r.cutoff.is_none() && r.cutoff_factor.is_none(),
        }),
    })
}

/// A radial clearance δ between the rotor surface and a stator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Clearance {
    /// δ in metres (`clearance`).
    Metres(f64),
    /// δ = δ_nd |Z0(ω)| (`clearance_nd`), |Z0| the steady unbalance response without stator at
    /// the speed run, at the station's node: changes along a sweep.
    TimesZ0(f64),
}

impl Clearance {
    /// δ (m) at a speed where the unbalance response at the station is `z0()` (m), computed
    /// only when δ is relative to it; `None` when |Z0| is not positive (no unbalance).
    ///
    /// # Errors
    /// Those of `z0`.
    pub fn at<E>(self, z0: impl FnOnce() -> Result<f64, E>) -> Result<Option<f64>, E> {
        Ok(match self {
            Clearance::Metres(c) => Some(c),
            Clearance::TimesZ0(nd) => {
                let z = z0()?;
                (z > 0.0).then_some(nd * z)
            }
        })
    }
}

impl From<OneOf<f64, f64>> for Clearance {
    /// `clearance` (m) or `clearance_nd`, as the scene chose.
    fn from(c: OneOf<f64, f64>) -> Self {
        match c {
            OneOf::First(m) => Clearance::Metres(m),
            OneOf::Second(nd) => Clearance::TimesZ0(nd),
        }
    }
}
