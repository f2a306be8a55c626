//! Scene files: what the user asks for, as plain validated data.
//!
//! A scene is a TOML file read with serde; unknown keys are rejected. All physical values are SI
//! (kg, m, s, N, Pa, rad/s); angles are given in degrees where the key says `_deg`. The paper's
//! non-dimensional inputs (Table 2) are accepted beside the SI ones:
//!
//! * `clearance_nd` = δ/|Z0(ω)|, with |Z0| the steady unbalance response without stator at the
//!   speed being run, so the clearance changes along a sweep;
//! * `speed_ratio` = ω/ω_n;
//! * `damping_ratio` ξ, with c = 2ξ√(m k);
//! * `stiffness_ratio` ε = k_s/k_r.
//!
//! [`load`] reads a file, applies `--set key=value` overrides, deserialises and validates. Errors
//! name the file, the dotted key and the line ([`crate::error::SceneError`]).

use crate::error::SceneError;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A whole scene.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Free text shown in reports.
    #[serde(default)]
    pub title: String,
    /// The rotor model.
    pub rotor: RotorSpec,
    /// Contact stations: rotor sections that can rub (`[[station]]`).
    #[serde(default, rename = "station")]
    pub stations: Vec<StationSpec>,
    /// Stators, each facing one station (`[[stator]]`).
    #[serde(default, rename = "stator")]
    pub stators: Vec<StatorSpec>,
    /// What to run.
    pub run: RunSpec,
    /// What to write.
    #[serde(default)]
    pub output: OutputSpec,
}

/// Rotor models.
#[derive(Debug, Clone, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Serialize, Deserialize)]
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
    /// Rayleigh damping `[α, β]`: C += α M + β K.
    #[serde(default)]
    pub rayleigh: [f64; 2],
    /// Shear deformation (Timoshenko); false = Euler–Bernoulli.
    #[serde(default = "yes")]
    pub shear: bool,
    /// Rotary inertia of the shaft.
    #[serde(default = "yes")]
    pub rotary_inertia: bool,
    /// Gyroscopic coupling (shaft and disks).
    #[serde(default = "yes")]
    pub gyroscopic: bool,
    /// Axial DOF `u_z` per node: bar elements E A/L, consistent mass; disks and point masses
    /// add their mass. Uncoupled from bending (linear theory).
    #[serde(default, skip_serializing_if = "is_false")]
    pub axial: bool,
    /// Torsional DOF `θ_z` per node: G J/L, G = E/(2(1+ν)), J = π(D⁴ − d⁴)/32; disks add I_p.
    /// Contact friction at a station of radius R loads it with the torque −R μ p (for Ω > 0).
    #[serde(default, skip_serializing_if = "is_false")]
    pub torsion: bool,
    /// Thrust bearings: spring and dashpot from a node's `u_z` to ground
    /// (`[[rotor.axial_support]]`, N/m and N·s/m).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub axial_support: Vec<GroundSpringSpec>,
    /// Torsional restraints (coupling or drive stiffness): spring and dashpot from a node's
    /// `θ_z` to ground (`[[rotor.torsional_support]]`, N·m/rad and N·m·s/rad).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
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
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModalDampingSpec {
    /// ζ (dimensionless, ≥ 0).
    pub ratio: f64,
    /// Highest undamped natural frequency damped (rad/s).
    pub max_frequency: Option<f64>,
    /// Largest number of modes damped.
    pub modes: Option<usize>,
}

fn is_false(b: &bool) -> bool {
    !*b
}

/// A spring and dashpot from one scalar DOF of a rotor node to ground: `u_z` for
/// `[[rotor.axial_support]]` (N/m, N·s/m), `θ_z` for `[[rotor.torsional_support]]`
/// (N·m/rad, N·m·s/rad).
#[derive(Debug, Clone, Serialize, Deserialize)]
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

/// A uniform shaft segment. Material by `material` name (`steel`: E 211 GPa, ν 0.3,
/// ρ 7810 kg/m³; `aluminium`: 69 GPa, 0.33, 2700; `titanium`: 110 GPa, 0.34, 4430) or by
/// `youngs_modulus`, `poisson`, `density` (these override the named values).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShaftSegmentSpec {
    /// Segment length (m).
    pub length: f64,
    /// Outer diameter (m).
    pub outer_diameter: f64,
    /// Inner diameter (m), 0 for solid.
    #[serde(default)]
    pub inner_diameter: f64,
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
#[derive(Debug, Clone, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
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
#[derive(Debug, Clone, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StationSpec {
    /// Name the stators refer to.
    pub name: String,
    /// Rotor node of the section centre (Jeffcott: 0).
    #[serde(default)]
    pub node: usize,
    /// Section radius r (m).
    pub radius: f64,
    /// Coulomb friction coefficient μ (permanent slip, Eq. 19).
    #[serde(default)]
    pub friction: f64,
}

/// Stator models.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum StatorSpec {
    /// The paper's elastic rod, meshed with 2-D bar elements, its axis radial.
    Rod(RodSpec),
    /// Rigid ring on isotropic radial springs around the station (classic rub model).
    Ring(RingSpec),
    /// General 2-D finite-element stator given as nodes, elements and fixed DOFs.
    Fe(FeStatorSpec),
    /// Stator meshed by gmsh from a parametric `.geo`, a CAD file or a `.msh` file.
    Mesh(Box<MeshStatorSpec>),
}

impl StatorSpec {
    /// The stator's name.
    pub fn name(&self) -> &str {
        match self {
            StatorSpec::Rod(s) => &s.name,
            StatorSpec::Ring(s) => &s.name,
            StatorSpec::Fe(s) => &s.name,
            StatorSpec::Mesh(s) => &s.name,
        }
    }
    /// The station it faces.
    pub fn station(&self) -> &str {
        match self {
            StatorSpec::Rod(s) => &s.station,
            StatorSpec::Ring(s) => &s.station,
            StatorSpec::Fe(s) => &s.station,
            StatorSpec::Mesh(s) => &s.station,
        }
    }
}

/// Stator meshed by gmsh (`kind = "mesh"`).
///
/// The geometry is a parametric gmsh `.geo` (its `DefineConstant` parameters set from
/// `parameters`), a CAD file (`.step`, `.stp`, `.brep`, `.iges`: imported through OpenCASCADE,
/// its bodies grouped as `stator` and each boundary entity as `boundary_<tag>`), or a ready
/// `.msh` (MSH 4.1). Relative paths are resolved against the scene file's directory, then its
/// ancestors (so `geometry/annulus.geo` works from `scenes/stators/`). Meshes are cached in
/// `meshes/` by content; an up-to-date mesh never runs gmsh.
///
/// Coordinates of the geometry are relative to the undeformed centre of the station (m), rotor
/// axis z. Physical groups are the contract: `contact_group` (curves in 2-D, surfaces in 3-D)
/// holds the nodes that can touch the rotor, the `fixed*` groups the supports; 2-D groups of a
/// 2-D mesh (volumes of a 3-D mesh) are material regions, `regions` overriding the default
/// material per group.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshStatorSpec {
    /// Stator name.
    pub name: String,
    /// Station it faces.
    pub station: String,
    /// Geometry file (`.geo`, `.step`/`.stp`/`.brep`/`.iges`/`.igs`, or `.msh`).
    pub geometry: String,
    /// gmsh parameters (`-setnumber name value`), declared by the geometry's `DefineConstant`.
    #[serde(default)]
    pub parameters: std::collections::BTreeMap<String, f64>,
    /// Element order: 1 (linear) or 2 (quadratic).
    #[serde(default = "one_u8")]
    pub order: u8,
    /// Quadrilaterals instead of triangles (gmsh `Mesh.RecombineAll`); 2-D only.
    #[serde(default)]
    pub quads: bool,
    /// 8-node instead of 9-node quadratic quadrilaterals.
    #[serde(default)]
    pub serendipity: bool,
    /// Factor on every mesh size of the geometry (gmsh `-clscale`).
    #[serde(default = "unit")]
    pub size_factor: f64,
    /// 2-D meshes: `"stress"` (default) or `"strain"`.
    #[serde(default = "plane_stress")]
    pub plane: String,
    /// 2-D meshes: out-of-plane thickness (m).
    pub thickness: Option<f64>,
    /// Young's modulus E (Pa) of the default material.
    pub youngs_modulus: f64,
    /// Poisson's ratio ν of the default material.
    pub poisson_ratio: f64,
    /// Density ρ (kg/m³) of the default material; 0 everywhere makes the stator massless.
    #[serde(default)]
    pub density: f64,
    /// Material of particular regions (physical groups of the mesh's dimension).
    #[serde(default)]
    pub regions: Vec<RegionSpec>,
    /// Physical group of the contact boundary.
    #[serde(default = "contact_group")]
    pub contact_group: String,
    /// Physical groups whose nodes are fixed in every direction (frame nodes: clamped, θ too).
    #[serde(default = "fixed_groups")]
    pub fixed: Vec<String>,
    /// Physical groups whose nodes have u_x = 0 (symmetry planes, guides).
    #[serde(default)]
    pub fixed_x: Vec<String>,
    /// Physical groups whose nodes have u_y = 0.
    #[serde(default)]
    pub fixed_y: Vec<String>,
    /// 3-D meshes: physical groups whose nodes have u_z = 0.
    #[serde(default)]
    pub fixed_z: Vec<String>,
    /// Grounded springs on the nodes of a group.
    #[serde(default)]
    pub springs: Vec<SpringSupportSpec>,
    /// Bars and frames (beam-columns) on the line elements of a group (2-D meshes).
    #[serde(default)]
    pub frames: Vec<FrameSpec>,
    /// Rayleigh damping `[α, β]`, C = α M + β K (only with mass).
    #[serde(default)]
    pub rayleigh: [f64; 2],
    /// Place the mesh so its nearest contact node is at clearance δ (m) from the rotor surface,
    /// by a rigid translation along `approach_deg`. Without `clearance`/`clearance_nd` the
    /// geometry's own position sets the clearance.
    pub clearance: Option<f64>,
    /// As `clearance`, given as δ/|Z0(ω)| (re-placed at every speed).
    pub clearance_nd: Option<f64>,
    /// Direction (degrees from +x) from the station centre toward the stator along which it is
    /// translated to its clearance.
    #[serde(default = "ninety")]
    pub approach_deg: f64,
    /// 3-D meshes: further stations the contact nodes may face; each contact node is assigned
    /// to the one (of these and `station`) nearest to its axial position.
    #[serde(default)]
    pub stations: Vec<String>,
    /// 3-D meshes: axial position along the rotor (m) of the mesh's z = 0.
    #[serde(default)]
    pub axial_origin: f64,
}

/// Material of a region (physical group) of a meshed stator; unset values are the stator's.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionSpec {
    /// Physical group name.
    pub group: String,
    /// Young's modulus (Pa).
    pub youngs_modulus: Option<f64>,
    /// Poisson's ratio.
    pub poisson_ratio: Option<f64>,
    /// Density (kg/m³).
    pub density: Option<f64>,
    /// Thickness (m), 2-D.
    pub thickness: Option<f64>,
}

/// Grounded springs on the nodes of a group: the stiffness is the group's total, shared
/// equally by its nodes.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringSupportSpec {
    /// Physical group name.
    pub group: String,
    /// Total stiffness `[k_x, k_y]` (N/m).
    pub stiffness: [f64; 2],
}

/// Bars (without `inertia`) or frames (with it) on the line elements of a group.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrameSpec {
    /// Physical group of lines (dimension 1).
    pub group: String,
    /// Young's modulus (Pa).
    pub youngs_modulus: f64,
    /// Cross-section area (m²).
    pub area: f64,
    /// Second moment of area about z (m⁴); absent: pin-jointed bars.
    pub inertia: Option<f64>,
    /// Shear correction factor κ: Timoshenko frames; absent: Euler–Bernoulli.
    pub shear_factor: Option<f64>,
    /// Poisson's ratio (for G = E / (2(1+ν))).
    #[serde(default = "poisson")]
    pub poisson_ratio: f64,
    /// Density (kg/m³).
    #[serde(default)]
    pub density: f64,
}

fn one_u8() -> u8 {
    1
}
fn unit() -> f64 {
    1.0
}
fn poisson() -> f64 {
    0.3
}
fn plane_stress() -> String {
    "stress".into()
}
fn contact_group() -> String {
    "stator_contact".into()
}
fn fixed_groups() -> Vec<String> {
    vec!["stator_fixed".into()]
}

/// Elastic rod stator (paper Fig. 4). The tip faces the station at clearance δ along
/// `angle_deg` (90° = +y, above the rotor); the far end is fixed; lateral DOFs are guided so the
/// bar model is not singular. Stiffness k_s = E A / L, or ε k_r when `stiffness_ratio` is given.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RodSpec {
    /// Stator name.
    pub name: String,
    /// Station it faces.
    pub station: String,
    /// Clearance δ between rotor surface and rod tip (m).
    pub clearance: Option<f64>,
    /// Clearance as δ/|Z0(ω)| (paper's δ_nd).
    pub clearance_nd: Option<f64>,
    /// Rod length L (m).
    pub length: f64,
    /// Cross-section area A (m²).
    pub area: f64,
    /// Young's modulus E (Pa); ignored for stiffness when `stiffness_ratio` is given.
    pub youngs_modulus: Option<f64>,
    /// ε = k_s/k_r; overrides E so that E A / L = ε k_r.
    pub stiffness_ratio: Option<f64>,
    /// Density ρ (kg/m³); 0 (default) makes the rod massless.
    #[serde(default)]
    pub density: f64,
    /// Number of bar elements along the rod.
    #[serde(default = "one")]
    pub elements: usize,
    /// Direction from the station centre to the tip (degrees from +x, counter-clockwise).
    #[serde(default = "ninety")]
    pub angle_deg: f64,
    /// Rayleigh damping `[α, β]`, C = α M + β K (only with mass).
    #[serde(default)]
    pub rayleigh: [f64; 2],
}

/// Rigid ring on isotropic springs: radial force k_s (R − δ) when the rotor displacement R
/// relative to the ring exceeds δ.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RingSpec {
    /// Stator name.
    pub name: String,
    /// Station it faces.
    pub station: String,
    /// Radial clearance δ (m).
    pub clearance: Option<f64>,
    /// Clearance as δ/|Z0(ω)|.
    pub clearance_nd: Option<f64>,
    /// Support stiffness k_s (N/m).
    pub stiffness: Option<f64>,
    /// ε = k_s/k_r.
    pub stiffness_ratio: Option<f64>,
    /// Ring mass (kg); 0 (default) makes it massless.
    #[serde(default)]
    pub mass: f64,
    /// Support damping (N·s/m), only with mass.
    #[serde(default)]
    pub damping: f64,
}

/// General 2-D FE stator in the station plane, coordinates relative to the undeformed station
/// centre. Node DOFs are `[u_x, u_y]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FeStatorSpec {
    /// Stator name.
    pub name: String,
    /// Station it faces.
    pub station: String,
    /// Node coordinates `[x, y]` (m).
    pub nodes: Vec<[f64; 2]>,
    /// Elements.
    pub elements: Vec<FeElementSpec>,
    /// Fixed DOFs as `[node, component]` with component 0 = x, 1 = y.
    pub fixed: Vec<[usize; 2]>,
    /// Nodes that can touch the rotor (the contact boundary).
    pub contact_nodes: Vec<usize>,
    /// Rayleigh damping `[α, β]`, C = α M + β K (only with mass).
    #[serde(default)]
    pub rayleigh: [f64; 2],
    /// Lumped point masses `[node, kg]` added to element masses.
    #[serde(default)]
    pub point_masses: Vec<(usize, f64)>,
}

/// Elements of the general FE stator.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum FeElementSpec {
    /// 2-node bar (truss) element: axial stiffness E A / L, lumped mass ρ A L / 2 per node.
    Bar {
        /// The two node indices.
        nodes: [usize; 2],
        /// Young's modulus (Pa).
        youngs_modulus: f64,
        /// Area (m²).
        area: f64,
        /// Density (kg/m³); 0 for massless.
        #[serde(default)]
        density: f64,
    },
    /// Grounded spring on one node along a direction (N/m).
    Spring {
        /// Node index.
        node: usize,
        /// Stiffness (N/m).
        stiffness: f64,
        /// Direction (degrees from +x).
        angle_deg: f64,
    },
}

/// Time integrators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum IntegratorKind {
    /// The paper's scheme: explicit central differences with forward-increment Lagrange
    /// multipliers (Eqs. 34–47), massless stators by Eq. 49. First order in Δt with a massless
    /// stator; unconditionally stable with respect to the stator stiffness.
    ForwardIncrement,
    /// Central differences with the massless stator's contact force solved at tₙ from the rotor
    /// position at tₙ (stator force collocated with the displacement). Second order; its stable
    /// step shrinks as the stator stiffens (Δt < 2/√((k_r + k_s)/m)). Stators with mass are
    /// coupled by forward increment as in the paper.
    Collocated,
}

impl IntegratorKind {
    /// Name as written in scene files.
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::ForwardIncrement => "forward_increment",
            IntegratorKind::Collocated => "collocated",
        }
    }
    /// Nominal order in Δt with a massless stator (used by the error estimate).
    pub fn nominal_order(self) -> f64 {
        match self {
            IntegratorKind::ForwardIncrement => 1.0,
            IntegratorKind::Collocated => 2.0,
        }
    }
}

/// What to run.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    /// Speed as ω/ω_n (single run).
    pub speed_ratio: Option<f64>,
    /// Speed ω (rad/s) (single run).
    pub speed: Option<f64>,
    /// Speed sweep over ω/ω_n.
    pub sweep: Option<SweepSpec>,
    /// Total simulated revolutions.
    #[serde(default = "default_revs")]
    pub revolutions: usize,
    /// Revolutions cut as transient before analysis.
    #[serde(default = "default_transient")]
    pub transient_revolutions: usize,
    /// Integrator; default `collocated` (see docs/VALIDATION.md for why).
    #[serde(default = "default_integrator")]
    pub integrator: IntegratorKind,
    /// Time step override (s). Rounded down so a revolution holds a whole number of steps.
    pub dt: Option<f64>,
    /// The paper's rule Δt ≤ min(T_min/(32 n), 2π/(32 n ω)) with n = `harmonics`.
    #[serde(default = "default_harmonics")]
    pub harmonics: f64,
    /// Recorded samples per revolution (a power of two is best for the FFT).
    #[serde(default = "default_spr")]
    pub samples_per_rev: usize,
    /// Estimate the discretisation error by a companion run at 2Δt.
    #[serde(default = "yes")]
    pub error_estimate: bool,
    /// Initial rotor station displacement `[x, y]` (m) at node 0.
    #[serde(default)]
    pub initial_displacement: [f64; 2],
    /// Initial rotor station velocity `[vx, vy]` (m/s) at node 0.
    #[serde(default)]
    pub initial_velocity: [f64; 2],
}

/// Speed sweep over ω/ω_n, inclusive of both ends.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSpec {
    /// First ω/ω_n.
    pub from: f64,
    /// Last ω/ω_n.
    pub to: f64,
    /// Increment.
    pub step: f64,
    /// Optional parameter study: one sweep per value of a scene key (Sec. 4.2 sensitivity).
    pub vary: Option<VarySpec>,
}

/// A sensitivity study: the sweep is repeated for each value of one scene key.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VarySpec {
    /// Dotted key, as for `--set` (e.g. `stator.0.clearance_nd`).
    pub key: String,
    /// Values to set.
    pub values: Vec<f64>,
}

/// What to write.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Write PNG pictures.
    #[serde(default = "yes")]
    pub png: bool,
    /// Orbit grids: each a list of ω/ω_n values (a 3×3 grid like Figs. 5–7).
    #[serde(default)]
    pub orbit_grids: Vec<Vec<f64>>,
    /// Speeds whose contact-force histories are plotted (Fig. 9).
    #[serde(default)]
    pub force_histories: Vec<f64>,
    /// Response component analysed in spectra and cascades: `"y"` (vertical, default) or `"x"`.
    #[serde(default = "default_component")]
    pub component: String,
    /// Upper frequency of cascades, in units of ω_n (default: the top speed).
    pub cascade_max_freq: Option<f64>,
    /// Rotor node whose orbit, Poincaré section, spectrum, cascade and |Z0| normalisation the
    /// analysis uses (default: the first station's node). Contact forces stay per station.
    pub node: Option<usize>,
    /// VTK XML time series: `.vtu` frames and a `.pvd` collection (absent: not written).
    pub vtk: Option<SeriesSpec>,
    /// HDF5 time series with a transient VTKHDF group (absent: not written).
    pub hdf5: Option<SeriesSpec>,
    /// Which speeds of a sweep write the time series above, into `speed_<ω/ω_n>/` sub-folders:
    /// `false` (default: none), `true` (all) or a list of ω/ω_n. `rubsim run` always writes them.
    #[serde(default)]
    pub per_speed: PerSpeed,
}

/// A time-series writer (`output.vtk`, `output.hdf5`): which frames, which fields.
///
/// Frames are taken at the integration steps that are multiples of `every` and lie within
/// `[from_revolution, to_revolution]` (revolutions of the rotor since t = 0).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SeriesSpec {
    /// Steps between frames (default: the recording interval, i.e. `run.samples_per_rev`
    /// frames per revolution, on the same instants as the analysis).
    pub every: Option<usize>,
    /// Fields to write (default: all).
    #[serde(default = "all_series_fields")]
    pub fields: Vec<SeriesField>,
    /// First revolution written (default 0, the start of the run).
    #[serde(default)]
    pub from_revolution: f64,
    /// Last revolution written (default: the end of the run, `run.revolutions`).
    pub to_revolution: Option<f64>,
}

/// Fields of the time series.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SeriesField {
    /// Node displacements of rotor and stators (m).
    Displacement,
    /// Node velocities (m/s), by a backward difference over one time step.
    Velocity,
    /// Contact: pair normal forces (multipliers) and forces, node contact forces (N).
    ContactForce,
    /// Stator element axial force (N), stress (Pa) and strain.
    Stress,
}

/// All [`SeriesField`]s.
pub fn all_series_fields() -> Vec<SeriesField> {
    vec![
        SeriesField::Displacement,
        SeriesField::Velocity,
        SeriesField::ContactForce,
        SeriesField::Stress,
    ]
}

/// Per-speed time series of a sweep: `false`, `true` or a list of ω/ω_n.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum PerSpeed {
    /// None (`false`) or every speed (`true`).
    All(bool),
    /// These speeds ω/ω_n (each must be one of the sweep's speeds).
    Speeds(Vec<f64>),
}

impl Default for PerSpeed {
    fn default() -> Self {
        PerSpeed::All(false)
    }
}

impl Default for OutputSpec {
    fn default() -> Self {
        Self {
            png: true,
            orbit_grids: Vec::new(),
            force_histories: Vec::new(),
            component: default_component(),
            cascade_max_freq: None,
            node: None,
            vtk: None,
            hdf5: None,
            per_speed: PerSpeed::default(),
        }
    }
}

fn one() -> usize {
    1
}
fn ninety() -> f64 {
    90.0
}
fn yes() -> bool {
    true
}
fn default_revs() -> usize {
    220
}
fn default_transient() -> usize {
    100
}
fn default_integrator() -> IntegratorKind {
    IntegratorKind::Collocated
}
fn default_harmonics() -> f64 {
    4.0
}
fn default_spr() -> usize {
    64
}
fn default_component() -> String {
    "y".into()
}

/// A scene with where it came from, for error messages.
#[derive(Debug, Clone)]
pub struct LoadedScene {
    /// The validated scene.
    pub scene: Scene,
    /// The file it was read from.
    pub file: PathBuf,
    /// The file's text (for locating keys in later errors).
    pub source: String,
    /// Overrides applied (`key=value`).
    pub overrides: Vec<String>,
}

impl LoadedScene {
    /// An `Invalid` error for `key`, with the line of that key in the file when present.
    pub fn invalid(&self, key: &str, message: impl Into<String>) -> SceneError {
        invalid_at(&self.file, &self.source, key, message)
    }
}

fn invalid_at(file: &Path, source: &str, key: &str, message: impl Into<String>) -> SceneError {
    SceneError::Invalid {
        file: file.to_path_buf(),
        key: key.to_string(),
        line: locate_key(source, key),
        message: message.into(),
    }
}

/// Reads, overrides, deserialises and validates a scene file.
pub fn load(path: &Path, overrides: &[String]) -> Result<LoadedScene, SceneError> {
    let source = std::fs::read_to_string(path).map_err(|e| SceneError::Read {
        file: path.to_path_buf(),
        source: e,
    })?;
    parse(path, &source, overrides)
}

/// Like [`load`] but from text already in memory (`path` is used in messages only).
pub fn parse(path: &Path, source: &str, overrides: &[String]) -> Result<LoadedScene, SceneError> {
    let mut value: toml::Value =
        toml::from_str(source).map_err(|e| parse_error(path, source, e))?;
    for a in overrides {
        apply_override(&mut value, a)?;
    }
    let scene: Scene = if overrides.is_empty() {
        toml::from_str(source).map_err(|e| parse_error(path, source, e))?
    } else {
        // No spans here (the lines of a re-serialised document would not be the file's): when
        // the file alone fails the same way, report that with its lines, else blame the --set.
        Scene::deserialize(value).map_err(|e| match toml::from_str::<Scene>(source) {
            Err(fe) if fe.message() == e.message() => parse_error(path, source, fe),
            _ => SceneError::Override {
                assignment: overrides.join(" --set "),
                message: e.to_string().trim_end().replace('\n', " "),
            },
        })?
    };
    let loaded = LoadedScene {
        scene,
        file: path.to_path_buf(),
        source: source.to_string(),
        overrides: overrides.to_vec(),
    };
    validate(&loaded)?;
    Ok(loaded)
}

/// A TOML/serde error in the file's own text. In a `kind`-tagged table (`[rotor]`,
/// `[[stator]]`) serde reports an unknown key at the table header; name the key's own line too.
fn parse_error(path: &Path, source: &str, e: toml::de::Error) -> SceneError {
    let mut message = e.to_string().trim_end().to_string();
    let key = e
        .message()
        .strip_prefix("unknown field `")
        .and_then(|r| r.split('`').next());
    if let (Some(span), Some(key)) = (e.span(), key) {
        let header = source[..span.start.min(source.len())].matches('\n').count();
        let is_header = |l: &str| {
            let l = l.trim_start();
            let name = l.trim_start_matches('[').trim_start();
            l.starts_with('[') && name.starts_with(|c: char| c.is_ascii_alphabetic() || c == '"')
        };
        let is_key = |l: &str| {
            let r = l.trim_start().strip_prefix(key).map(str::trim_start);
            r.is_some_and(|r| r.starts_with(['=', '.']))
        };
        let found = source
            .lines()
            .enumerate()
            .skip(header + 1)
            .take_while(|(_, l)| !is_header(l))
            .find(|(_, l)| is_key(l));
        if let Some((n, _)) = found {
            message.push_str(&format!("\n`{key}` is on line {}", n + 1));
        }
    }
    SceneError::Parse {
        file: path.to_path_buf(),
        message,
    }
}

/// Applies one `path.to.key=value` assignment; array elements are addressed by index
/// (`stator.0.clearance_nd=0.5`). The value is parsed as TOML (number, bool, array, inline
/// table, quoted string) and falls back to a bare string.
pub fn apply_override(root: &mut toml::Value, assignment: &str) -> Result<(), SceneError> {
    let err = |m: &str| SceneError::Override {
        assignment: assignment.to_string(),
        message: m.to_string(),
    };
    let (key, raw) = assignment
        .split_once('=')
        .ok_or_else(|| err("expected key=value"))?;
    let key = key.trim();
    if key.is_empty() {
        return Err(err("empty key"));
    }
    let raw = raw.trim();
    let value: toml::Value = match toml::from_str::<toml::Table>(&format!("v = {raw}")) {
        Ok(mut t) => t.remove("v").expect("parsed key"),
        Err(_) => toml::Value::String(raw.to_string()),
    };
    let parts: Vec<&str> = key.split('.').collect();
    let mut cur = root;
    for (i, part) in parts.iter().enumerate() {
        let last = i + 1 == parts.len();
        // Scene arrays of tables are named in the singular in TOML (`[[stator]]`).
        cur = match cur {
            toml::Value::Table(t) => {
                if last {
                    t.insert(part.to_string(), value);
                    return Ok(());
                }
                t.entry(part.to_string())
                    .or_insert_with(|| toml::Value::Table(toml::Table::new()))
            }
            toml::Value::Array(a) => {
                let idx: usize = part
                    .parse()
                    .map_err(|_| err(&format!("`{part}` is not an index into an array")))?;
                let len = a.len();
                let slot = a.get_mut(idx).ok_or_else(|| {
                    err(&format!(
                        "index {idx} out of range (array has {len} entries)"
                    ))
                })?;
                if last {
                    *slot = value;
                    return Ok(());
                }
                slot
            }
            _ => {
                return Err(err(&format!(
                    "`{}` is not a table or array",
                    parts[..i].join(".")
                )))
            }
        };
    }
    unreachable!("loop returns on the last part")
}

/// 1-based line of a dotted key (`stator.0.clearance_nd`, `rotor.mass`) in TOML text, if
/// present. Array indices count `[[name]]` headers. When the full key is absent, the line of its
/// deepest present parent is returned (e.g. the `[[stator]]` header of a missing key).
pub fn locate_key(source: &str, key: &str) -> Option<usize> {
    use toml_edit::{Item, Table, Value};
    enum Cur<'a> {
        Item(&'a Item),
        Table(&'a Table),
    }
    let doc: toml_edit::ImDocument<&str> = toml_edit::ImDocument::parse(source).ok()?;
    let mut cur = Cur::Table(doc.as_table());
    let mut span = None;
    for part in key.split('.') {
        let idx = part.parse::<usize>().ok();
        let next = match (&cur, idx) {
            (Cur::Table(t), None) => t.get_key_value(part).map(|(k, v)| (k.span(), Cur::Item(v))),
            (Cur::Item(Item::Table(t)), None) => {
                t.get_key_value(part).map(|(k, v)| (k.span(), Cur::Item(v)))
            }
            (Cur::Item(Item::Value(Value::InlineTable(t))), None) => t
                .get_key_value(part)
                .map(|(k, _)| (k.span(), Cur::Item(&Item::None))),
            (Cur::Item(Item::ArrayOfTables(a)), Some(i)) => {
                a.get(i).map(|t| (t.span(), Cur::Table(t)))
            }
            (Cur::Item(Item::Value(Value::Array(a))), Some(i)) => {
                a.get(i).map(|v| (v.span(), Cur::Item(&Item::None)))
            }
            _ => None,
        };
        match next {
            Some((s, c)) => {
                span = s.or(span);
                cur = c;
            }
            None => break,
        }
    }
    let start = span?.start;
    Some(source[..start.min(source.len())].matches('\n').count() + 1)
}

fn positive(ls: &LoadedScene, key: &str, v: f64) -> Result<(), SceneError> {
    if !(v.is_finite() && v > 0.0) {
        return Err(ls.invalid(key, format!("must be a positive finite number, got {v}")));
    }
    Ok(())
}

fn non_negative(ls: &LoadedScene, key: &str, v: f64) -> Result<(), SceneError> {
    if !(v.is_finite() && v >= 0.0) {
        return Err(ls.invalid(key, format!("must be zero or positive, got {v}")));
    }
    Ok(())
}

fn exactly_one(
    ls: &LoadedScene,
    key_a: &str,
    a: bool,
    key_b: &str,
    b: bool,
    at: &str,
) -> Result<(), SceneError> {
    match (a, b) {
        (true, true) => Err(ls.invalid(at, format!("give `{key_a}` or `{key_b}`, not both"))),
        (false, false) => Err(ls.invalid(at, format!("missing: give `{key_a}` or `{key_b}`"))),
        _ => Ok(()),
    }
}

/// Checks every admissibility rule that types cannot express.
pub fn validate(ls: &LoadedScene) -> Result<(), SceneError> {
    let s = &ls.scene;
    match &s.rotor {
        RotorSpec::Jeffcott(j) => {
            exactly_one(
                ls,
                "mass",
                j.mass.is_some(),
                "disk",
                j.disk.is_some(),
                "rotor",
            )?;
            exactly_one(
                ls,
                "stiffness",
                j.stiffness.is_some(),
                "shaft",
                j.shaft.is_some(),
                "rotor",
            )?;
            exactly_one(
                ls,
                "damping",
                j.damping.is_some(),
                "damping_ratio",
                j.damping_ratio.is_some(),
                "rotor",
            )?;
            if let Some(m) = j.mass {
                positive(ls, "rotor.mass", m)?;
            }
            if let Some(n) = s.output.node.filter(|n| *n != 0) {
                return Err(ls.invalid(
                    "output.node",
                    format!("node {n} does not exist (a Jeffcott rotor has node 0 only)"),
                ));
            }
            if let Some(k) = j.stiffness {
                positive(ls, "rotor.stiffness", k)?;
            }
            if let Some(c) = j.damping {
                non_negative(ls, "rotor.damping", c)?;
            }
            if let Some(z) = j.damping_ratio {
                non_negative(ls, "rotor.damping_ratio", z)?;
            }
            if let Some(d) = &j.disk {
                positive(ls, "rotor.disk.diameter", d.diameter)?;
                positive(ls, "rotor.disk.thickness", d.thickness)?;
                positive(ls, "rotor.disk.density", d.density)?;
            }
            if let Some(sh) = &j.shaft {
                positive(ls, "rotor.shaft.youngs_modulus", sh.youngs_modulus)?;
                positive(ls, "rotor.shaft.diameter", sh.diameter)?;
                positive(ls, "rotor.shaft.length", sh.length)?;
            }
            for (i, u) in j.unbalance.iter().enumerate() {
                non_negative(ls, &format!("rotor.unbalance.{i}.mass"), u.mass)?;
                non_negative(ls, &format!("rotor.unbalance.{i}.radius"), u.radius)?;
                if u.node != 0 {
                    return Err(ls.invalid(
                        &format!("rotor.unbalance.{i}.node"),
                        "a Jeffcott rotor has only node 0",
                    ));
                }
            }
        }
        RotorSpec::Fe(_) => {}
    }
    if let RotorSpec::Fe(f) = &s.rotor {
        validate_fe_rotor(ls, f)?;
    }
    let mut names = std::collections::HashSet::new();
    for (i, st) in s.stations.iter().enumerate() {
        let k = |f: &str| format!("station.{i}.{f}");
        positive(ls, &k("radius"), st.radius)?;
        non_negative(ls, &k("friction"), st.friction)?;
        if !names.insert(st.name.as_str()) {
            return Err(ls.invalid(&k("name"), format!("duplicate station name `{}`", st.name)));
        }
        if matches!(s.rotor, RotorSpec::Jeffcott(_)) && st.node != 0 {
            return Err(ls.invalid(&k("node"), "a Jeffcott rotor has only node 0"));
        }
    }
    for (i, stator) in s.stators.iter().enumerate() {
        let k = |f: &str| format!("stator.{i}.{f}");
        if !s.stations.iter().any(|st| st.name == stator.station()) {
            let known: Vec<&str> = s.stations.iter().map(|s| s.name.as_str()).collect();
            return Err(ls.invalid(
                &k("station"),
                format!(
                    "no station named `{}` (stations: {})",
                    stator.station(),
                    if known.is_empty() {
                        "none".to_string()
                    } else {
                        known.join(", ")
                    }
                ),
            ));
        }
        match stator {
            StatorSpec::Rod(r) => {
                validate_clearance(ls, i, r.clearance, r.clearance_nd)?;
                positive(ls, &k("length"), r.length)?;
                positive(ls, &k("area"), r.area)?;
                exactly_one(
                    ls,
                    "youngs_modulus",
                    r.youngs_modulus.is_some(),
                    "stiffness_ratio",
                    r.stiffness_ratio.is_some(),
                    &format!("stator.{i}"),
                )?;
                if let Some(e) = r.youngs_modulus {
                    positive(ls, &k("youngs_modulus"), e)?;
                }
                if let Some(e) = r.stiffness_ratio {
                    positive(ls, &k("stiffness_ratio"), e)?;
                }
                non_negative(ls, &k("density"), r.density)?;
                if r.elements == 0 {
                    return Err(ls.invalid(&k("elements"), "must be at least 1"));
                }
                for v in r.rayleigh {
                    non_negative(ls, &k("rayleigh"), v)?;
                }
            }
            StatorSpec::Ring(r) => {
                validate_clearance(ls, i, r.clearance, r.clearance_nd)?;
                exactly_one(
                    ls,
                    "stiffness",
                    r.stiffness.is_some(),
                    "stiffness_ratio",
                    r.stiffness_ratio.is_some(),
                    &format!("stator.{i}"),
                )?;
                if let Some(v) = r.stiffness {
                    positive(ls, &k("stiffness"), v)?;
                }
                if let Some(v) = r.stiffness_ratio {
                    positive(ls, &k("stiffness_ratio"), v)?;
                }
                non_negative(ls, &k("mass"), r.mass)?;
                non_negative(ls, &k("damping"), r.damping)?;
            }
            StatorSpec::Fe(f) => {
                let nn = f.nodes.len();
                if nn == 0 {
                    return Err(ls.invalid(&k("nodes"), "a stator needs at least one node"));
                }
                for (e, el) in f.elements.iter().enumerate() {
                    let ek = |x: &str| format!("stator.{i}.elements.{e}.{x}");
                    match el {
                        FeElementSpec::Bar {
                            nodes,
                            youngs_modulus,
                            area,
                            density,
                        } => {
                            for n in nodes {
                                if *n >= nn {
                                    return Err(ls.invalid(
                                        &ek("nodes"),
                                        format!("node {n} does not exist (stator has {nn} nodes)"),
                                    ));
                                }
                            }
                            let a = f.nodes[nodes[0]];
                            let b = f.nodes[nodes[1]];
                            if (a[0] - b[0]).hypot(a[1] - b[1]) <= 0.0 {
                                return Err(ls.invalid(&ek("nodes"), "zero-length bar"));
                            }
                            positive(ls, &ek("youngs_modulus"), *youngs_modulus)?;
                            positive(ls, &ek("area"), *area)?;
                            non_negative(ls, &ek("density"), *density)?;
                        }
                        FeElementSpec::Spring {
                            node, stiffness, ..
                        } => {
                            if *node >= nn {
                                return Err(ls.invalid(
                                    &ek("node"),
                                    format!("node {node} does not exist (stator has {nn} nodes)"),
                                ));
                            }
                            positive(ls, &ek("stiffness"), *stiffness)?;
                        }
                    }
                }
                for fx in &f.fixed {
                    if fx[0] >= nn || fx[1] > 1 {
                        return Err(ls.invalid(
                            &k("fixed"),
                            format!("[{}, {}] is not a valid [node, component] (component 0 = x, 1 = y)", fx[0], fx[1]),
                        ));
                    }
                }
                if f.contact_nodes.is_empty() {
                    return Err(ls.invalid(&k("contact_nodes"), "no contact nodes given"));
                }
                for c in &f.contact_nodes {
                    if *c >= nn {
                        return Err(ls.invalid(
                            &k("contact_nodes"),
                            format!("node {c} does not exist (stator has {nn} nodes)"),
                        ));
                    }
                }
                for (n, m) in &f.point_masses {
                    if *n >= nn {
                        return Err(
                            ls.invalid(&k("point_masses"), format!("node {n} does not exist"))
                        );
                    }
                    non_negative(ls, &k("point_masses"), *m)?;
                }
                for v in f.rayleigh {
                    non_negative(ls, &k("rayleigh"), v)?;
                }
            }
            StatorSpec::Mesh(m) => validate_mesh_stator(ls, i, m)?,
        }
    }
    let r = &s.run;
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
    if s.output.component != "x" && s.output.component != "y" {
        return Err(ls.invalid("output.component", "must be \"x\" or \"y\""));
    }
    validate_series(ls)?;
    Ok(())
}

fn validate_fe_rotor(ls: &LoadedScene, f: &FeRotorSpec) -> Result<(), SceneError> {
    if f.shaft.is_empty() {
        return Err(ls.invalid(
            "rotor.shaft",
            "an FE rotor needs at least one [[rotor.shaft]] segment",
        ));
    }
    let mut nodes = 1;
    for (i, seg) in f.shaft.iter().enumerate() {
        let k = |x: &str| format!("rotor.shaft.{i}.{x}");
        positive(ls, &k("length"), seg.length)?;
        positive(ls, &k("outer_diameter"), seg.outer_diameter)?;
        non_negative(ls, &k("inner_diameter"), seg.inner_diameter)?;
        if seg.inner_diameter >= seg.outer_diameter {
            return Err(ls.invalid(&k("inner_diameter"), "must be smaller than outer_diameter"));
        }
        if seg.elements == 0 {
            return Err(ls.invalid(&k("elements"), "must be at least 1"));
        }
        nodes += seg.elements;
        let named = match &seg.material {
            Some(m) => Some(material(m).ok_or_else(|| {
                ls.invalid(&k("material"), format!("unknown material `{m}` (known: steel, aluminium, titanium; or give youngs_modulus, poisson, density)"))
            })?),
            None => None,
        };
        if named.is_none() && (seg.youngs_modulus.is_none() || seg.density.is_none()) {
            return Err(ls.invalid(
                &format!("rotor.shaft.{i}"),
                "give `material` or `youngs_modulus` and `density`",
            ));
        }
        if let Some(e) = seg.youngs_modulus {
            positive(ls, &k("youngs_modulus"), e)?;
        }
        if let Some(r) = seg.density {
            non_negative(ls, &k("density"), r)?;
        }
        if let Some(nu) = seg.poisson {
            if !(nu > -1.0 && nu < 0.5) {
                return Err(ls.invalid(&k("poisson"), format!("must lie in (−1, 0.5), got {nu}")));
            }
        }
    }
    let node_ok = |key: String, n: usize| -> Result<(), SceneError> {
        if n >= nodes {
            Err(ls.invalid(
                &key,
                format!(
                    "node {n} does not exist (the shaft has nodes 0..={})",
                    nodes - 1
                ),
            ))
        } else {
            Ok(())
        }
    };
    for (i, d) in f.disk.iter().enumerate() {
        node_ok(format!("rotor.disk.{i}.node"), d.node)?;
        let inertial = d.mass.is_some();
        let geo = d.outer_diameter.is_some() || d.width.is_some();
        if inertial == geo {
            return Err(ls.invalid(&format!("rotor.disk.{i}"), "give `mass` (+ inertias) or the geometry `outer_diameter`, `width` (+ `bore`, `density`/`material`), not both"));
        }
        if geo
            && (d.outer_diameter.is_none()
                || d.width.is_none()
                || (d.density.is_none() && d.material.is_none()))
        {
            return Err(ls.invalid(
                &format!("rotor.disk.{i}"),
                "geometry needs `outer_diameter`, `width` and `density` or `material`",
            ));
        }
        for (name, v) in [
            ("mass", d.mass),
            ("polar_inertia", d.polar_inertia),
            ("diametral_inertia", d.diametral_inertia),
            ("outer_diameter", d.outer_diameter),
            ("width", d.width),
        ] {
            if let Some(v) = v {
                non_negative(ls, &format!("rotor.disk.{i}.{name}"), v)?;
            }
        }
        if let Some(m) = &d.material {
            if material(m).is_none() {
                return Err(ls.invalid(
                    &format!("rotor.disk.{i}.material"),
                    format!("unknown material `{m}`"),
                ));
            }
        }
    }
    if f.bearing.is_empty() {
        return Err(ls.invalid(
            "rotor",
            "an FE rotor needs at least one [[rotor.bearing]] (a free rotor has no equilibrium)",
        ));
    }
    for (i, b) in f.bearing.iter().enumerate() {
        node_ok(format!("rotor.bearing.{i}.node"), b.node)?;
        let n = b.speeds.len();
        for w in b.speeds.windows(2) {
            if w[1] <= w[0] {
                return Err(ls.invalid(
                    &format!("rotor.bearing.{i}.speeds"),
                    "must be strictly ascending",
                ));
            }
        }
        let all = [
            ("stiffness", &b.stiffness),
            ("damping", &b.damping),
            ("kxx", &b.kxx),
            ("kxy", &b.kxy),
            ("kyx", &b.kyx),
            ("kyy", &b.kyy),
            ("cxx", &b.cxx),
            ("cxy", &b.cxy),
            ("cyx", &b.cyx),
            ("cyy", &b.cyy),
        ];
        for (name, v) in all {
            if let Some(ScalarOrTable::Table(t)) = v {
                if t.len() != n {
                    return Err(ls.invalid(
                        &format!("rotor.bearing.{i}.{name}"),
                        format!("table has {} values but `speeds` has {n}", t.len()),
                    ));
                }
            }
        }
        if b.stiffness.is_some() && (b.kxx.is_some() || b.kyy.is_some()) {
            return Err(ls.invalid(
                &format!("rotor.bearing.{i}"),
                "give `stiffness` or `kxx`/`kyy`, not both",
            ));
        }
        if b.stiffness.is_none() && b.kxx.is_none() && b.kyy.is_none() {
            return Err(ls.invalid(
                &format!("rotor.bearing.{i}"),
                "missing stiffness (`stiffness` or `kxx`, `kyy`)",
            ));
        }
        if let Some(p) = &b.pedestal {
            positive(ls, &format!("rotor.bearing.{i}.pedestal.mass"), p.mass)?;
            positive(
                ls,
                &format!("rotor.bearing.{i}.pedestal.stiffness"),
                p.stiffness,
            )?;
            non_negative(
                ls,
                &format!("rotor.bearing.{i}.pedestal.damping"),
                p.damping,
            )?;
        }
    }
    for (name, on, flag, mode, list) in [
        ("axial_support", f.axial, "axial", "axial", &f.axial_support),
        (
            "torsional_support",
            f.torsion,
            "torsion",
            "torsional",
            &f.torsional_support,
        ),
    ] {
        for (i, g) in list.iter().enumerate() {
            node_ok(format!("rotor.{name}.{i}.node"), g.node)?;
            positive(ls, &format!("rotor.{name}.{i}.stiffness"), g.stiffness)?;
            non_negative(ls, &format!("rotor.{name}.{i}.damping"), g.damping)?;
            if !on {
                return Err(ls.invalid(
                    &format!("rotor.{name}.{i}"),
                    format!("needs `{flag} = true` in [rotor] (the rotor has no such DOFs)"),
                ));
            }
        }
        if on && list.is_empty() {
            return Err(ls.invalid(
                &format!("rotor.{flag}"),
                format!("`{flag} = true` needs at least one [[rotor.{name}]] (without one the rotor has a free rigid-body {mode} mode and no equilibrium)"),
            ));
        }
    }
    for (i, p) in f.point_mass.iter().enumerate() {
        node_ok(format!("rotor.point_mass.{i}.node"), p.node)?;
        non_negative(ls, &format!("rotor.point_mass.{i}.mass"), p.mass)?;
    }
    for (i, u) in f.unbalance.iter().enumerate() {
        node_ok(format!("rotor.unbalance.{i}.node"), u.node)?;
        non_negative(ls, &format!("rotor.unbalance.{i}.mass"), u.mass)?;
        non_negative(ls, &format!("rotor.unbalance.{i}.radius"), u.radius)?;
    }
    for v in f.rayleigh {
        non_negative(ls, "rotor.rayleigh", v)?;
    }
    if let Some(md) = &f.modal_damping {
        non_negative(ls, "rotor.modal_damping.ratio", md.ratio)?;
        if let Some(w) = md.max_frequency {
            positive(ls, "rotor.modal_damping.max_frequency", w)?;
        }
        if md.modes == Some(0) {
            return Err(ls.invalid("rotor.modal_damping.modes", "must be at least 1"));
        }
    }
    for (i, st) in ls.scene.stations.iter().enumerate() {
        node_ok(format!("station.{i}.node"), st.node)?;
    }
    if let Some(n) = ls.scene.output.node {
        node_ok("output.node".into(), n)?;
    }
    Ok(())
}

/// Checks `output.vtk`, `output.hdf5` and `output.per_speed`.
fn validate_series(ls: &LoadedScene) -> Result<(), SceneError> {
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

/// Admissibility of a meshed stator's values (what the mesh needs is checked when it is read).
fn validate_mesh_stator(ls: &LoadedScene, i: usize, m: &MeshStatorSpec) -> Result<(), SceneError> {
    let k = |f: &str| format!("stator.{i}.{f}");
    if m.geometry.trim().is_empty() {
        return Err(ls.invalid(&k("geometry"), "empty path"));
    }
    for (name, v) in &m.parameters {
        if !v.is_finite() {
            return Err(ls.invalid(&k(&format!("parameters.{name}")), "must be finite"));
        }
    }
    if !(m.order == 1 || m.order == 2) {
        return Err(ls.invalid(&k("order"), format!("must be 1 or 2, got {}", m.order)));
    }
    positive(ls, &k("size_factor"), m.size_factor)?;
    if m.plane != "stress" && m.plane != "strain" {
        return Err(ls.invalid(&k("plane"), "must be \"stress\" or \"strain\""));
    }
    if let Some(t) = m.thickness {
        positive(ls, &k("thickness"), t)?;
    }
    let poisson_ok = |key: &str, v: f64| {
        if v.is_finite() && v > -1.0 && v < 0.5 {
            Ok(())
        } else {
            Err(ls.invalid(key, format!("must lie in (−1, 0.5), got {v}")))
        }
    };
    positive(ls, &k("youngs_modulus"), m.youngs_modulus)?;
    poisson_ok(&k("poisson_ratio"), m.poisson_ratio)?;
    non_negative(ls, &k("density"), m.density)?;
    for (r, reg) in m.regions.iter().enumerate() {
        let rk = |f: &str| format!("stator.{i}.regions.{r}.{f}");
        if let Some(v) = reg.youngs_modulus {
            positive(ls, &rk("youngs_modulus"), v)?;
        }
        if let Some(v) = reg.poisson_ratio {
            poisson_ok(&rk("poisson_ratio"), v)?;
        }
        if let Some(v) = reg.density {
            non_negative(ls, &rk("density"), v)?;
        }
        if let Some(v) = reg.thickness {
            positive(ls, &rk("thickness"), v)?;
        }
    }
    for (r, sp) in m.springs.iter().enumerate() {
        for v in sp.stiffness {
            non_negative(ls, &format!("stator.{i}.springs.{r}.stiffness"), v)?;
        }
    }
    for (r, fr) in m.frames.iter().enumerate() {
        let fk = |f: &str| format!("stator.{i}.frames.{r}.{f}");
        positive(ls, &fk("youngs_modulus"), fr.youngs_modulus)?;
        positive(ls, &fk("area"), fr.area)?;
        if let Some(v) = fr.inertia {
            positive(ls, &fk("inertia"), v)?;
        }
        if let Some(v) = fr.shear_factor {
            positive(ls, &fk("shear_factor"), v)?;
            if fr.inertia.is_none() {
                return Err(ls.invalid(
                    &fk("shear_factor"),
                    "a shear factor needs `inertia` (bars carry no shear)",
                ));
            }
        }
        poisson_ok(&fk("poisson_ratio"), fr.poisson_ratio)?;
        non_negative(ls, &fk("density"), fr.density)?;
    }
    if m.clearance.is_some() && m.clearance_nd.is_some() {
        return Err(ls.invalid(
            &format!("stator.{i}"),
            "give `clearance` or `clearance_nd`, not both",
        ));
    }
    if let Some(v) = m.clearance {
        positive(ls, &k("clearance"), v)?;
    }
    if let Some(v) = m.clearance_nd {
        positive(ls, &k("clearance_nd"), v)?;
    }
    for v in m.rayleigh {
        non_negative(ls, &k("rayleigh"), v)?;
    }
    for (j, name) in m.stations.iter().enumerate() {
        if !ls.scene.stations.iter().any(|st| &st.name == name) {
            return Err(ls.invalid(
                &k(&format!("stations.{j}")),
                format!("no station named `{name}`"),
            ));
        }
    }
    if !m.axial_origin.is_finite() {
        return Err(ls.invalid(&k("axial_origin"), "must be finite"));
    }
    if m.fixed.is_empty() && m.fixed_x.is_empty() && m.fixed_y.is_empty() && m.springs.is_empty() {
        return Err(ls.invalid(
            &k("fixed"),
            "the stator has no supports: name a fixed group or springs",
        ));
    }
    Ok(())
}

fn validate_clearance(
    ls: &LoadedScene,
    i: usize,
    c: Option<f64>,
    c_nd: Option<f64>,
) -> Result<(), SceneError> {
    exactly_one(
        ls,
        "clearance",
        c.is_some(),
        "clearance_nd",
        c_nd.is_some(),
        &format!("stator.{i}"),
    )?;
    if let Some(v) = c {
        positive(ls, &format!("stator.{i}.clearance"), v)?;
    }
    if let Some(v) = c_nd {
        positive(ls, &format!("stator.{i}.clearance_nd"), v)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const OK: &str = r#"
title = "t"
[rotor]
kind = "jeffcott"
mass = 2.0
stiffness = 8.0e4
damping_ratio = 0.2
[[rotor.unbalance]]
mass = 0.01
radius = 0.05

[[station]]
name = "disk"
radius = 0.06
friction = 0.1

[[stator]]
kind = "rod"
name = "rod"
station = "disk"
clearance_nd = 0.6
length = 0.04
area = 25e-6
stiffness_ratio = 25

[run]
speed_ratio = 1.7
"#;

    fn p(text: &str, ov: &[&str]) -> Result<LoadedScene, SceneError> {
        let ov: Vec<String> = ov.iter().map(|s| s.to_string()).collect();
        parse(Path::new("scene.toml"), text, &ov)
    }

    #[test]
    fn parses_a_valid_scene() {
        let s = p(OK, &[]).unwrap();
        assert_eq!(s.scene.stators.len(), 1);
        assert_eq!(s.scene.run.integrator, IntegratorKind::Collocated);
    }

    #[test]
    fn unknown_key_names_line() {
        let bad = OK.replace("radius = 0.06", "radius = 0.06\nfrobnicate = 1");
        let e = p(&bad, &[]).unwrap_err().to_string();
        assert!(e.contains("frobnicate"), "{e}");
        assert!(e.contains("line 15"), "{e}");
    }

    #[test]
    fn negative_mass_names_key_and_line() {
        let bad = OK.replace("mass = 2.0", "mass = -2.0");
        let e = p(&bad, &[]).unwrap_err().to_string();
        assert!(
            e.contains("rotor.mass") && e.contains("scene.toml:5"),
            "{e}"
        );
    }

    #[test]
    fn clearance_in_array_of_tables_is_located() {
        let bad = OK.replace("clearance_nd = 0.6", "clearance_nd = -0.6");
        let e = p(&bad, &[]).unwrap_err().to_string();
        assert!(
            e.contains("stator.0.clearance_nd") && e.contains(":21"),
            "{e}"
        );
    }

    #[test]
    fn override_changes_values_and_is_validated() {
        let s = p(OK, &["stator.0.clearance_nd=0.3", "run.speed_ratio=2.5"]).unwrap();
        match &s.scene.stators[0] {
            StatorSpec::Rod(r) => assert_eq!(r.clearance_nd, Some(0.3)),
            _ => panic!(),
        }
        assert_eq!(s.scene.run.speed_ratio, Some(2.5));
        let e = p(OK, &["station.0.friction=-1"]).unwrap_err().to_string();
        assert!(e.contains("station.0.friction"), "{e}");
        let e = p(OK, &["stator.3.clearance=1"]).unwrap_err().to_string();
        assert!(e.contains("out of range"), "{e}");
    }

    #[test]
    fn missing_section_is_named() {
        let bad = OK.replace("[run]\nspeed_ratio = 1.7", "");
        let e = p(&bad, &[]).unwrap_err().to_string();
        assert!(e.contains("run"), "{e}");
    }
}
