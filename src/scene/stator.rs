//! `[[stator]]`: rods, rings, general 2-D FE stators and meshed stators, each facing a station.

use super::one;
use crate::element::solid2d::Plane;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Stator models.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum StatorSpec {
    /// The paper's elastic rod, meshed with 2-D bar elements, its axis radial.
    Rod(RodSpec),
    /// Rigid ring on springs around the station (classic rub model): isotropic, or `stiffness_y`
    /// / `damping_y` along y.
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
    /// The contact dashpot: `(contact_damping, contact_damping_mode)`.
    pub fn contact_damping(&self) -> (f64, &str) {
        match self {
            StatorSpec::Rod(s) => (s.contact_damping, &s.contact_damping_mode),
            StatorSpec::Ring(s) => (s.contact_damping, &s.contact_damping_mode),
            StatorSpec::Fe(s) => (s.contact_damping, &s.contact_damping_mode),
            StatorSpec::Mesh(s) => (s.contact_damping, &s.contact_damping_mode),
        }
    }
    /// True when the scene gives the stator mass (a ring's `mass`, a density, a point mass);
    /// the model decides in the end ([`crate::model::StatorModel::massless`]).
    pub fn has_mass(&self) -> bool {
        match self {
            StatorSpec::Rod(s) => s.density > 0.0,
            StatorSpec::Ring(s) => s.mass > 0.0,
            StatorSpec::Fe(s) => {
                !s.point_masses.is_empty()
                    || s.elements
                        .iter()
                        .any(|e| matches!(e, FeElementSpec::Bar { density, .. } if *density > 0.0))
            }
            StatorSpec::Mesh(s) => {
                s.density > 0.0
                    || s.regions.iter().any(|r| r.density.is_some_and(|d| d > 0.0))
                    || s.frames.iter().any(|f| f.density > 0.0)
            }
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
    /// Its `[stator.abradable]`, if any.
    pub fn abradable(&self) -> Option<&super::abradable::AbradableSpec> {
        match self {
            StatorSpec::Rod(s) => s.abradable.as_ref(),
            StatorSpec::Ring(s) => s.abradable.as_ref(),
            StatorSpec::Fe(s) => s.abradable.as_ref(),
            StatorSpec::Mesh(s) => s.abradable.as_ref(),
        }
    }
    /// Its `[stator.wear]`, if any.
    pub fn wear(&self) -> Option<&super::wear::WearSpec> {
        match self {
            StatorSpec::Rod(s) => s.wear.as_ref(),
            StatorSpec::Ring(s) => s.wear.as_ref(),
            StatorSpec::Fe(s) => s.wear.as_ref(),
            StatorSpec::Mesh(s) => s.wear.as_ref(),
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
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(extend("not" = {"required": ["clearance", "clearance_nd"]}))]
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
    #[schemars(extend("enum" = [1, 2]))]
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
    #[schemars(extend("enum" = ["stress", "strain"]))]
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
    /// Archard wear of the contact nodes (`[stator.wear]`, `scene::wear`); rods and meshed
    /// stators only. Absent: no wear.
    #[serde(default)]
    pub wear: Option<super::wear::WearSpec>,
    /// An elasto-plastic abradable coating on the contact nodes (`[stator.abradable]`,
    /// `scene::abradable`); rods and meshed stators only. Absent: no coating.
    #[serde(default)]
    pub abradable: Option<super::abradable::AbradableSpec>,
    /// Contact dashpot c_d (N·s/m), massless stators only: while a pair of this stator carries
    /// force, a dashpot between the rotor section and ground in parallel with the contact damps
    /// the rate of the stator's deflection at the contact point (docs/IMPLICIT.md §6).
    /// 0 (default): none.
    #[serde(default)]
    pub contact_damping: f64,
    /// What the contact dashpot damps: `"normal"` (default, the normal velocity) or `"full"`
    /// (also the tangential velocity of the rotor section, as ROSS's rub model does).
    #[serde(default = "normal_mode")]
    #[schemars(extend("enum" = ["normal", "full"]))]
    pub contact_damping_mode: String,
}

impl MeshStatorSpec {
    /// The 2-D idealisation `plane` names (`"stress"` or `"strain"`); `None` for any other name.
    pub fn plane(&self) -> Option<Plane> {
        match self.plane.as_str() {
            "stress" => Some(Plane::Stress),
            "strain" => Some(Plane::Strain),
            _ => None,
        }
    }
}

/// Material of a region (physical group) of a meshed stator; unset values are the stator's.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SpringSupportSpec {
    /// Physical group name.
    pub group: String,
    /// Total stiffness `[k_x, k_y]` (N/m).
    pub stiffness: [f64; 2],
}

/// Bars (without `inertia`) or frames (with it) on the line elements of a group.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
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
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(extend("allOf" = [
    {"oneOf": [{"required": ["clearance"]}, {"required": ["clearance_nd"]}]},
    {"oneOf": [{"required": ["youngs_modulus"]}, {"required": ["stiffness_ratio"]}]}
]))]
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
    /// Archard wear of the contact nodes (`[stator.wear]`, `scene::wear`); rods and meshed
    /// stators only. Absent: no wear.
    #[serde(default)]
    pub wear: Option<super::wear::WearSpec>,
    /// An elasto-plastic abradable coating on the contact nodes (`[stator.abradable]`,
    /// `scene::abradable`); rods and meshed stators only. Absent: no coating.
    #[serde(default)]
    pub abradable: Option<super::abradable::AbradableSpec>,
    /// Contact dashpot c_d (N·s/m), massless stators only: while a pair of this stator carries
    /// force, a dashpot between the rotor section and ground in parallel with the contact damps
    /// the rate of the stator's deflection at the contact point (docs/IMPLICIT.md §6).
    /// 0 (default): none.
    #[serde(default)]
    pub contact_damping: f64,
    /// What the contact dashpot damps: `"normal"` (default, the normal velocity) or `"full"`
    /// (also the tangential velocity of the rotor section, as ROSS's rub model does).
    #[serde(default = "normal_mode")]
    #[schemars(extend("enum" = ["normal", "full"]))]
    pub contact_damping_mode: String,
}

/// Rigid ring on springs k_s: the ring's centre moves by the whole contact force
/// `N(n + μa)/k_s` (friction included) and the rotor touches it when its displacement relative
/// to the moving centre reaches δ. The springs are isotropic unless `stiffness_y` (and, for a
/// ring with mass, `damping_y`) gives the vertical support its own value: the support is then
/// `diag(k_x, k_y)`, `diag(c_x, c_y)` (a casing held more stiffly one way than the other).
/// `kinematics = "radial"` keeps instead the classic radially elastic stator (Black): force
/// `k_s(R − δ)` along the rotor's radius R, friction reacted by ground.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(extend("allOf" = [
    {"oneOf": [{"required": ["clearance"]}, {"required": ["clearance_nd"]}]},
    {"oneOf": [{"required": ["stiffness"]}, {"required": ["stiffness_ratio"]}]}
]))]
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
    /// Support stiffness along y (N/m) when it differs from the one along x (`stiffness` or
    /// `stiffness_ratio`, then k_x): an anisotropic ring. Left out: isotropic.
    pub stiffness_y: Option<f64>,
    /// Ring mass (kg); 0 (default) makes it massless.
    #[serde(default)]
    pub mass: f64,
    /// Support damping (N·s/m), only with mass; c_x when `damping_y` is given.
    #[serde(default)]
    pub damping: f64,
    /// Support damping along y (N·s/m) when it differs from `damping` (c_x), only with mass.
    /// Left out: `damping`.
    pub damping_y: Option<f64>,
    /// Archard wear of the contact nodes (`[stator.wear]`, `scene::wear`); rods and meshed
    /// stators only. Absent: no wear.
    #[serde(default)]
    pub wear: Option<super::wear::WearSpec>,
    /// An elasto-plastic abradable coating on the contact nodes (`[stator.abradable]`,
    /// `scene::abradable`); rods and meshed stators only. Absent: no coating.
    #[serde(default)]
    pub abradable: Option<super::abradable::AbradableSpec>,
    /// Contact dashpot c_d (N·s/m), massless stators only: while a pair of this stator carries
    /// force, a dashpot between the rotor section and ground in parallel with the contact damps
    /// the rate of the stator's deflection at the contact point (docs/IMPLICIT.md §6).
    /// 0 (default): none.
    #[serde(default)]
    pub contact_damping: f64,
    /// What the contact dashpot damps: `"normal"` (default, the normal velocity) or `"full"`
    /// (also the tangential velocity of the rotor section, as ROSS's rub model does).
    #[serde(default = "normal_mode")]
    #[schemars(extend("enum" = ["normal", "full"]))]
    pub contact_damping_mode: String,
    /// `"exact"` (default): the ring's centre takes the whole contact force, its
    /// friction-driven tangential displacement enters the gap (docs/VALIDATION.md §15.1).
    /// `"radial"`: the classic radially elastic stator of the full-annular-rub literature
    /// (docs/ORACLES.md §2–3): the ring's centre moves only along the contact normal, the
    /// friction force goes to ground; massless rings only.
    #[serde(default = "exact_kinematics")]
    #[schemars(extend("enum" = ["exact", "radial"]))]
    pub kinematics: String,
}

fn exact_kinematics() -> String {
    "exact".into()
}

/// General 2-D FE stator in the station plane, coordinates relative to the undeformed station
/// centre. Node DOFs are `[u_x, u_y]`.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
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
    /// Archard wear of the contact nodes (`[stator.wear]`, `scene::wear`); rods and meshed
    /// stators only. Absent: no wear.
    #[serde(default)]
    pub wear: Option<super::wear::WearSpec>,
    /// An elasto-plastic abradable coating on the contact nodes (`[stator.abradable]`,
    /// `scene::abradable`); rods and meshed stators only. Absent: no coating.
    #[serde(default)]
    pub abradable: Option<super::abradable::AbradableSpec>,
    /// Contact dashpot c_d (N·s/m), massless stators only: while a pair of this stator carries
    /// force, a dashpot between the rotor section and ground in parallel with the contact damps
    /// the rate of the stator's deflection at the contact point (docs/IMPLICIT.md §6).
    /// 0 (default): none.
    #[serde(default)]
    pub contact_damping: f64,
    /// What the contact dashpot damps: `"normal"` (default, the normal velocity) or `"full"`
    /// (also the tangential velocity of the rotor section, as ROSS's rub model does).
    #[serde(default = "normal_mode")]
    #[schemars(extend("enum" = ["normal", "full"]))]
    pub contact_damping_mode: String,
}

/// Elements of the general FE stator.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
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

fn normal_mode() -> String {
    "normal".into()
}

fn ninety() -> f64 {
    90.0
}
