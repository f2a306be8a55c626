//! `[rotor]` and `[[station]]`: the rotor models (Jeffcott, finite elements) and the rotor
//! sections that can rub.

use super::{one, yes};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Rotor models.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum RotorSpec {
    /// Jeffcott rotor: one lateral mode, 2 DOF (x, y) at the disk (paper Eq. 50).
    Jeffcott(JeffcottSpec),
    /// Finite-element rotor: Timoshenko shaft segments, disks, bearings (`kind = "fe"`).
    Fe(FeRotorSpec),
}

/// Finite-element rotor. Nodes are numbered from the left end of the first shaft segment;
/// each segment adds `elements` equal elements. DOFs per node `[u_x, u_y, θ_x, θ_y]`, plus
/// `u_z` (m, along +z) with `axial = true` and `θ_z` (rad, counter-clockwise seen from +z, the
/// sense of the spin) with `torsion = true`; both off by default. Axial DOFs need at least one
/// `[[rotor.axial_support]]`, torsional DOFs at least one `[[rotor.torsional_support]]`.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FeRotorSpec {
    /// Shaft segments, left to right (`[[rotor.shaft]]`).
    pub shaft: Vec<ShaftSegmentSpec>,
    /// Rigid disks (`[[rotor.disk]]`).
    #[serde(default)]
    pub disk: Vec<FeDiskSpec>,
    /// Bearings (`[[rotor.bearing]]`).
    #[serde(default)]
    pub bearing: Vec<BearingSpec>,
    /// Point masses (`[[rotor.point_mass]]`).
    #[serde(default)]
    pub point_mass: Vec<PointMassSpec>,
    /// Unbalances (`[[rotor.unbalance]]`, with `node`).
    #[serde(default)]
    pub unbalance: Vec<UnbalanceSpec>,
    /// Rayleigh damping `[α, β]`: C += α M + β K (of what `rayleigh_on` says).
    #[serde(default)]
    pub rayleigh: [f64; 2],
    /// What the Rayleigh damping acts on: `"assembly"` (default: M and K(Ω) of the whole
    /// rotor, disks, point masses, pedestals and bearings included), `"shaft"` (the shaft
    /// elements' own M_e and K_e only, ROSS 2's element-level convention) or `"rotor"` (the
    /// mass of the shaft, disks and point masses and the shaft's stiffness, ROSS 3's
    /// rotor-level convention).
    #[serde(default, skip_serializing_if = "RayleighOn::is_assembly")]
    #[schemars(extend("default" = "assembly"))]
    pub rayleigh_on: RayleighOn,
    /// Shear deformation (Timoshenko); false = Euler–Bernoulli.
    #[serde(default = "yes")]
    pub shear: bool,
    /// Rotary inertia of the shaft's bending rotations in M (independent of `gyroscopic`:
    /// the shaft's G stays when this is off, as in ROSS).
    #[serde(default = "yes")]
    pub rotary_inertia: bool,
    /// Gyroscopic coupling (shaft and disks; false: G = 0).
    #[serde(default = "yes")]
    pub gyroscopic: bool,
    /// Axial DOF `u_z` per node: bar elements E A/L, consistent mass; disks and point masses
    /// add their mass. Uncoupled from bending (linear theory).
    #[serde(default, skip_serializing_if = "is_false")]
    #[schemars(extend("default" = false))]
    pub axial: bool,
    /// Torsional DOF `θ_z` per node: G J/L, G = E/(2(1+ν)), J = π(D⁴ − d⁴)/32; disks add I_p.
    /// Contact friction at a station of radius R loads it with the torque −R μ p (for Ω > 0).
    #[serde(default, skip_serializing_if = "is_false")]
    #[schemars(extend("default" = false))]
    pub torsion: bool,
    /// Thrust bearings: spring and dashpot from a node's `u_z` to ground
    /// (`[[rotor.axial_support]]`, N/m and N·s/m).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    #[schemars(extend("default" = []))]
    pub axial_support: Vec<GroundSpringSpec>,
    /// Torsional restraints (coupling or drive stiffness): spring and dashpot from a node's
    /// `θ_z` to ground (`[[rotor.torsional_support]]`, N·m/rad and N·m·s/rad).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    #[schemars(extend("default" = []))]
    pub torsional_support: Vec<GroundSpringSpec>,
    /// Modal damping (`[rotor.modal_damping]`): ζ on the lowest undamped modes, added to the
    /// Rayleigh and bearing damping.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub modal_damping: Option<ModalDampingSpec>,
}

/// `[rotor.modal_damping]`: `C += Σᵢ 2ζωᵢ (Mφᵢ)(Mφᵢ)ᵀ` over the mass-normalised undamped
/// modes φᵢ (at rest, bearings at the run's speed, no gyroscopics) with ωᵢ ≤ `max_frequency`,
/// at most `modes` of them (both optional: without either, every mode — a dense term of full
/// rank, slow for large rotors). A repeated frequency is never split. Higher modes get none.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ModalDampingSpec {
    /// ζ (dimensionless, ≥ 0).
    pub ratio: f64,
    /// Highest undamped natural frequency damped (rad/s).
    pub max_frequency: Option<f64>,
    /// Largest number of modes damped.
    pub modes: Option<usize>,
}

/// What `rotor.rayleigh = [α, β]` acts on (α in 1/s, β in s; the damping matrix C in N·s/m,
/// N·m·s/rad, added to the bearings', supports' and modal damping).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum RayleighOn {
    /// `C_R = α M + β K(Ω)` of the assembled rotor (bearings, disks, point masses, pedestals).
    #[default]
    Assembly,
    /// `C_R = Σ_e (α M_e + β K_e)` over the shaft elements alone (bending, and the axial and
    /// torsional elements when those DOFs are on): ROSS 2's convention, where α and β are
    /// shaft-element data (`ShaftElement.C`), and ROSS 3's when only the elements carry them.
    Shaft,
    /// `C_R = α (M_shaft + M_disks + M_point_masses) + β K_shaft`: the mass of the rotor
    /// without its bearings (every DOF: lateral, and the axial and torsional ones when on — a
    /// disk's m on u_z and I_p on θ_z, a point mass's m on u_z) and the shaft elements'
    /// stiffness; bearings, pedestals, axial and torsional supports add neither mass nor
    /// stiffness to it. ROSS 3's rotor-level `alpha`, `beta` (`Rotor._build_base_matrices`:
    /// `C0 = alpha M0 + beta K0` over every element but the bearings, whose own C is added).
    Rotor,
}

impl RayleighOn {
    fn is_assembly(&self) -> bool {
        *self == RayleighOn::Assembly
    }
}

fn is_false(b: &bool) -> bool {
    !*b
}

/// A spring and dashpot from one scalar DOF of a rotor node to ground: `u_z` for
/// `[[rotor.axial_support]]` (N/m, N·s/m), `θ_z` for `[[rotor.torsional_support]]`
/// (N·m/rad, N·m·s/rad).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GroundSpringSpec {
    /// Node.
    pub node: usize,
    /// Stiffness (> 0).
    pub stiffness: f64,
    /// Damping (≥ 0).
    #[serde(default)]
    pub damping: f64,
}

/// A shaft segment, uniform or conical (`outer_diameter_right`, `inner_diameter_right`: the
/// diameters at its right end, linear in z from the left ones; ROSS's tapered elements). Material by `material` name (`steel`: E 211 GPa, ν 0.3,
/// ρ 7810 kg/m³; `aluminium`: 69 GPa, 0.33, 2700; `titanium`: 110 GPa, 0.34, 4430) or by
/// `youngs_modulus`, `poisson`, `density` (these override the named values).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ShaftSegmentSpec {
    /// Segment length (m).
    pub length: f64,
    /// Outer diameter (m).
    pub outer_diameter: f64,
    /// Inner diameter (m), 0 for solid.
    #[serde(default)]
    pub inner_diameter: f64,
    /// Outer diameter at the segment's right end (m); default `outer_diameter` (uniform).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outer_diameter_right: Option<f64>,
    /// Inner diameter at the segment's right end (m); default `inner_diameter`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inner_diameter_right: Option<f64>,
    /// Number of equal elements.
    #[serde(default = "one")]
    pub elements: usize,
    /// Material name.
    pub material: Option<String>,
    /// E (Pa).
    pub youngs_modulus: Option<f64>,
    /// ν.
    pub poisson: Option<f64>,
    /// ρ (kg/m³).
    pub density: Option<f64>,
}

/// A rigid disk: give `mass`, `polar_inertia`, `diametral_inertia`, or the geometry
/// `outer_diameter`, `width`, `bore` (default 0) and `density` (or `material`).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FeDiskSpec {
    /// Node.
    pub node: usize,
    /// Mass (kg).
    pub mass: Option<f64>,
    /// I_p (kg·m²).
    pub polar_inertia: Option<f64>,
    /// I_d (kg·m²).
    pub diametral_inertia: Option<f64>,
    /// Outer diameter (m).
    pub outer_diameter: Option<f64>,
    /// Bore (m).
    #[serde(default)]
    pub bore: f64,
    /// Axial width (m).
    pub width: Option<f64>,
    /// Density (kg/m³).
    pub density: Option<f64>,
    /// Material name (for the density).
    pub material: Option<String>,
}

/// A scalar or a table aligned with `speeds`.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum ScalarOrTable {
    /// Constant.
    Scalar(f64),
    /// One value per entry of `speeds`.
    Table(Vec<f64>),
}

/// A bearing between a rotor node and ground (or a pedestal). Isotropic `stiffness` /
/// `damping`, or the 2×2 coefficients `kxx kxy kyx kyy`, `cxx cxy cyx cyy` (N/m, N·s/m);
/// each may be a table over `speeds` (rad/s).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BearingSpec {
    /// Node.
    pub node: usize,
    /// Isotropic stiffness (sets kxx = kyy).
    pub stiffness: Option<ScalarOrTable>,
    /// Isotropic damping (sets cxx = cyy).
    pub damping: Option<ScalarOrTable>,
    /// k_xx.
    pub kxx: Option<ScalarOrTable>,
    /// k_xy.
    pub kxy: Option<ScalarOrTable>,
    /// k_yx.
    pub kyx: Option<ScalarOrTable>,
    /// k_yy.
    pub kyy: Option<ScalarOrTable>,
    /// c_xx.
    pub cxx: Option<ScalarOrTable>,
    /// c_xy.
    pub cxy: Option<ScalarOrTable>,
    /// c_yx.
    pub cyx: Option<ScalarOrTable>,
    /// c_yy.
    pub cyy: Option<ScalarOrTable>,
    /// Speeds of the tables (rad/s, ascending).
    #[serde(default)]
    pub speeds: Vec<f64>,
    /// Pedestal between the bearing and ground.
    pub pedestal: Option<PedestalSpec>,
}

/// Pedestal: mass on isotropic spring and damper to ground.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PedestalSpec {
    /// Mass (kg).
    pub mass: f64,
    /// Stiffness to ground (N/m).
    pub stiffness: f64,
    /// Damping to ground (N·s/m).
    #[serde(default)]
    pub damping: f64,
}

/// A point mass on a node's translations.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PointMassSpec {
    /// Node.
    pub node: usize,
    /// Mass (kg).
    pub mass: f64,
}

/// `(E, ν, ρ)` of a named material.
pub fn material(name: &str) -> Option<(f64, f64, f64)> {
    match name.to_ascii_lowercase().as_str() {
        "steel" => Some((211e9, 0.3, 7810.0)),
        "aluminium" | "aluminum" => Some((69e9, 0.33, 2700.0)),
        "titanium" => Some((110e9, 0.34, 4430.0)),
        _ => None,
    }
}

/// Jeffcott rotor data. Give `mass` or `disk`; `stiffness` or `shaft`; `damping` or
/// `damping_ratio`.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(extend("allOf" = [
    {"oneOf": [{"required": ["mass"]}, {"required": ["disk"]}]},
    {"oneOf": [{"required": ["stiffness"]}, {"required": ["shaft"]}]},
    {"oneOf": [{"required": ["damping"]}, {"required": ["damping_ratio"]}]}
]))]
pub struct JeffcottSpec {
    /// Modal mass m_r (kg).
    pub mass: Option<f64>,
    /// Modal stiffness k_r (N/m).
    pub stiffness: Option<f64>,
    /// Viscous damping c_r (N·s/m).
    pub damping: Option<f64>,
    /// Damping ratio ξ (c = 2ξ√(m k)).
    pub damping_ratio: Option<f64>,
    /// Mass from a disk: m = ρ π D²/4 · t.
    pub disk: Option<DiskSpec>,
    /// Stiffness from a simply supported shaft with the disk at mid-span: k = 48 E I / L³.
    pub shaft: Option<ShaftSpec>,
    /// Unbalances (`[[rotor.unbalance]]`).
    #[serde(default)]
    pub unbalance: Vec<UnbalanceSpec>,
}

/// A solid disk.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DiskSpec {
    /// Outer diameter (m).
    pub diameter: f64,
    /// Axial thickness (m).
    pub thickness: f64,
    /// Density (kg/m³).
    pub density: f64,
}

/// A uniform solid shaft, simply supported at both ends.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ShaftSpec {
    /// Young's modulus (Pa).
    pub youngs_modulus: f64,
    /// Diameter (m).
    pub diameter: f64,
    /// Length between supports (m).
    pub length: f64,
}

/// An unbalance: force m_u e ω² (cos(ωt+φ), sin(ωt+φ)).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct UnbalanceSpec {
    /// Unbalance mass m_u (kg).
    pub mass: f64,
    /// Its radius e (m).
    pub radius: f64,
    /// Phase φ (degrees).
    #[serde(default)]
    pub phase_deg: f64,
    /// Rotor node (Jeffcott: 0).
    #[serde(default)]
    pub node: usize,
}

/// A contact station: a radially rigid circular rotor section.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StationSpec {
    /// Name the stators refer to.
    pub name: String,
    /// Rotor node of the section centre (Jeffcott: 0).
    #[serde(default)]
    pub node: usize,
    /// Section radius r (m).
    pub radius: f64,
    /// Coulomb friction coefficient μ (permanent slip, Eq. 19, unless `stick`).
    #[serde(default)]
    pub friction: f64,
    /// Coulomb friction with stick (issue 28): the tangential force `t` is a second unknown of
    /// every pair, inside the cone `|t| ≤ μ p`; a pair sticks — the section's surface, spin
    /// `R Ω` included, moves with the stator's material point — while the force it needs stays
    /// in the cone, and slips against the relative motion at `μ p` otherwise (docs/STICK.md).
    /// Default false: permanent slip, the force `μ p` always against the spin.
    #[serde(default)]
    pub stick: bool,
}
