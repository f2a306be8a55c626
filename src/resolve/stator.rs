//! The stators resolved: the station each faces as an index, the clearance and the stiffness as
//! the one form the scene chose, general FE stators as nodes and elements, meshed stators with
//! their mesh read ([`super::mesh`]).

use super::mesh::{self, MeshStatorInput};
use super::Clearance;
use crate::error::Error;
use crate::math::V2;
use crate::scene::validate::{one_of, station_index, OneOf};
use crate::scene::{FeElementSpec, FeStatorSpec, LoadedScene, RingSpec, RodSpec, StatorSpec};

/// A rod's axial stiffness k_s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RodStiffness {
    /// k_s = ε k_r, k_r the rotor's reference stiffness (`stiffness_ratio`).
    Ratio(f64),
    /// k_s = E A / L from Young's modulus E (Pa) (`youngs_modulus`).
    YoungsModulus(f64),
}

/// A ring's support stiffness k_s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RingStiffness {
    /// k_s = ε k_r, k_r the rotor's reference stiffness (`stiffness_ratio`).
    Ratio(f64),
    /// k_s in N/m (`stiffness`).
    Absolute(f64),
}

impl RingStiffness {
    /// k_s (N/m) for a rotor of reference stiffness `k_r` (N/m).
    pub fn value(self, k_r: f64) -> f64 {
        match self {
            RingStiffness::Ratio(eps) => eps * k_r,
            RingStiffness::Absolute(k) => k,
        }
    }
}

/// The paper's elastic rod (scene `kind = "rod"`).
#[derive(Debug, Clone, PartialEq)]
pub struct RodInput {
    /// Stator name.
    pub name: String,
    /// Index of the station it faces.
    pub station: usize,
    /// Clearance δ between the rotor surface and the rod tip.
    pub clearance: Clearance,
    /// Rod length L (m).
    pub length: f64,
    /// Cross-section area A (m²).
    pub area: f64,
    /// Axial stiffness k_s.
    pub stiffness: RodStiffness,
    /// Density ρ (kg/m³); 0 for a massless rod.
    pub density: f64,
    /// Number of bar elements.
    pub elements: usize,
    /// Direction from the station centre to the tip (degrees from +x).
    pub angle_deg: f64,
    /// Rayleigh damping `[α, β]`.
    pub rayleigh: [f64; 2],
}

impl RodInput {
    /// k_s (N/m) for a rotor of reference stiffness `k_r` (N/m): ε k_r or E A / L.
    pub fn stiffness(&self, k_r: f64) -> f64 {
        match self.stiffness {
            RodStiffness::Ratio(eps) => eps * k_r,
            RodStiffness::YoungsModulus(e) => e * self.area / self.length,
        }
    }
}

/// A rigid ring on springs (scene `kind = "ring"`), isotropic unless `stiffness_y` or
/// `damping_y` is given.
#[derive(Debug, Clone, PartialEq)]
pub struct RingInput {
    /// Stator name.
    pub name: String,
    /// Index of the station it faces.
    pub station: usize,
    /// Radial clearance δ.
    pub clearance: Clearance,
    /// Support stiffness k_s (k_x of an anisotropic ring).
    pub stiffness: RingStiffness,
    /// Support stiffness along y (N/m) of an anisotropic ring; `None`: k_s.
    pub stiffness_y: Option<f64>,
    /// Ring mass (kg); 0 for a massless ring.
    pub mass: f64,
    /// Support damping (N·s/m; c_x of an anisotropic ring).
    pub damping: f64,
    /// Support damping along y (N·s/m); `None`: `damping`.
    pub damping_y: Option<f64>,
    /// Radially elastic stator (`kinematics = "radial"`): the ring's centre moves only along
    /// the contact normal; false (default): the ring takes the whole contact force.
    pub radial: bool,
}

/// An element of a general FE stator.
#[derive(Debug, Clone, PartialEq)]
pub enum FeElement {
    /// 2-node bar: axial stiffness E A / L, lumped mass ρ A L / 2 per node.
    Bar {
        /// The two node indices.
        nodes: [usize; 2],
        /// Young's modulus (Pa).
        youngs_modulus: f64,
        /// Area (m²).
        area: f64,
        /// Density (kg/m³).
        density: f64,
    },
    /// Grounded spring on one node along a direction.
    Spring {
        /// Node index.
        node: usize,
        /// Stiffness (N/m).
        stiffness: f64,
        /// Direction (degrees from +x).
        angle_deg: f64,
    },
}

/// A general 2-D FE stator (scene `kind = "fe"`): coordinates relative to the undeformed
/// station centre, node DOFs `[u_x, u_y]`. Node indices are those of `nodes` (checked by the
/// scene).
#[derive(Debug, Clone, PartialEq)]
pub struct FeStatorInput {
    /// Stator name.
    pub name: String,
    /// Index of the station it faces.
    pub station: usize,
    /// Node coordinates `[x, y]` (m).
    pub nodes: Vec<V2>,
    /// Elements.
    pub elements: Vec<FeElement>,
    /// Fixed DOFs `[node, component]`, component 0 = x, 1 = y.
    pub fixed: Vec<[usize; 2]>,
    /// Nodes that can touch the rotor.
    pub contact_nodes: Vec<usize>,
    /// Rayleigh damping `[α, β]`.
    pub rayleigh: [f64; 2],
    /// Lumped point masses `(node, kg)`.
    pub point_masses: Vec<(usize, f64)>,
}

/// A stator, resolved.
#[derive(Debug, Clone)]
pub enum StatorInput {
    /// Elastic rod.
    Rod(RodInput),
    /// Rigid ring on springs.
    Ring(RingInput),
    /// General 2-D FE stator.
    Fe(FeStatorInput),
    /// Meshed stator, its mesh read.
    Mesh(Box<MeshStatorInput>),
}

impl StatorInput {
    /// The stator's name.
    pub fn name(&self) -> &str {
        match self {
            StatorInput::Rod(s) => &s.name,
            StatorInput::Ring(s) => &s.name,
            StatorInput::Fe(s) => &s.name,
            StatorInput::Mesh(s) => &s.params.name,
        }
    }
    /// Index of the station it faces.
    pub fn station(&self) -> usize {
        match self {
            StatorInput::Rod(s) => s.station,
            StatorInput::Ring(s) => s.station,
            StatorInput::Fe(s) => s.station,
            StatorInput::Mesh(s) => s.params.station,
        }
    }
}

/// Resolves stator `i` of a checked scene (meshes are found, made by gmsh when out of date, and
/// read).
pub fn resolve(ls: &LoadedScene, i: usize, spec: &StatorSpec) -> Result<StatorInput, Error> {
    let station = station_index(ls, i, spec.station())?;
    Ok(match spec {
        StatorSpec::Rod(r) => StatorInput::Rod(rod(ls, i, station, r)?),
        StatorSpec::Ring(r) => StatorInput::Ring(ring(ls, i, station, r)?),
        StatorSpec::Fe(f) => StatorInput::Fe(fe(f, station)),
        StatorSpec::Mesh(m) => StatorInput::Mesh(Box::new(mesh::resolve(ls, i, station, m)?)),
    })
}

/// The clearance of stator `i`: `clearance` or `clearance_nd`, exactly one.
fn clearance(
    ls: &LoadedScene,
    i: usize,
    c: Option<f64>,
    c_nd: Option<f64>,
) -> Result<Clearance, crate::error::SceneError> {
    let at = format!("stator.{i}");
    Ok(one_of(ls, ("clearance", c), ("clearance_nd", c_nd), &at)?.into())
}

fn rod(ls: &LoadedScene, i: usize, station: usize, r: &RodSpec) -> Result<RodInput, Error> {
    let clearance = clearance(ls, i, r.clearance, r.clearance_nd)?;
    let stiffness = match one_of(
        ls,
        ("youngs_modulus", r.youngs_modulus),
        ("stiffness_ratio", r.stiffness_ratio),
        &format!("stator.{i}"),
    )? {
        OneOf::First(e) => RodStiffness::YoungsModulus(e),
        OneOf::Second(eps) => RodStiffness::Ratio(eps),
    };
    Ok(RodInput {
        name: r.name.clone(),
        station,
        clearance,
        length: r.length,
        area: r.area,
        stiffness,
        density: r.density,
        elements: r.elements,
        angle_deg: r.angle_deg,
        rayleigh: r.rayleigh,
    })
}

fn ring(ls: &LoadedScene, i: usize, station: usize, r: &RingSpec) -> Result<RingInput, Error> {
    let clearance = clearance(ls, i, r.clearance, r.clearance_nd)?;
    let stiffness = match one_of(
        ls,
        ("stiffness", r.stiffness),
        ("stiffness_ratio", r.stiffness_ratio),
        &format!("stator.{i}"),
    )? {
        OneOf::First(k) => RingStiffness::Absolute(k),
        OneOf::Second(eps) => RingStiffness::Ratio(eps),
    };
    Ok(RingInput {
        name: r.name.clone(),
        station,
        clearance,
        stiffness,
        stiffness_y: r.stiffness_y,
        mass: r.mass,
        damping: r.damping,
        damping_y: r.damping_y,
        radial: r.kinematics == "radial",
    })
}

/// A general FE stator facing station `station`.
pub fn fe(f: &FeStatorSpec, station: usize) -> FeStatorInput {
    FeStatorInput {
        name: f.name.clone(),
        station,
        nodes: f.nodes.clone(),
        elements: f
            .elements
            .iter()
            .map(|e| match *e {
                FeElementSpec::Bar {
                    nodes,
                    youngs_modulus,
                    area,
                    density,
                } => FeElement::Bar {
                    nodes,
                    youngs_modulus,
                    area,
                    density,
                },
                FeElementSpec::Spring {
                    node,
                    stiffness,
                    angle_deg,
                } => FeElement::Spring {
                    node,
                    stiffness,
                    angle_deg,
                },
            })
            .collect(),
        fixed: f.fixed.clone(),
        contact_nodes: f.contact_nodes.clone(),
        rayleigh: f.rayleigh,
        point_masses: f.point_masses.clone(),
    }
}
