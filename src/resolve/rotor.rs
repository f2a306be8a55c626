//! The rotor resolved: Jeffcott data (mass, stiffness and damping from whichever keys the
//! scene gives) or FE rotor data (elements, disks, bearings, supports, unbalances), and the
//! node that the non-dimensional inputs refer to.

use crate::element::timoshenko::ShaftSection;
use crate::error::SceneError;
use crate::scene::validate::{one_of, OneOf};
use crate::scene::{
    material, BearingSpec, FeRotorSpec, GroundSpringSpec, JeffcottSpec, LoadedScene, RayleighOn,
    RotorSpec, ScalarOrTable,
};
use std::f64::consts::PI;

/// The rotor, resolved.
#[derive(Debug, Clone)]
pub enum RotorInput {
    /// Jeffcott rotor (paper Eq. 50).
    Jeffcott(JeffcottData),
    /// Finite-element rotor.
    Fe(Box<FeRotorInput>),
}

/// Jeffcott rotor data: modal mass, stiffness and damping at the disk, and its unbalances.
#[derive(Debug, Clone, PartialEq)]
pub struct JeffcottData {
    /// m_r (kg).
    pub mass: f64,
    /// k_r (N/m).
    pub stiffness: f64,
    /// c_r (N·s/m).
    pub damping: f64,
    /// Unbalances `(m_u e (kg·m), phase φ (rad))`.
    pub unbalances: Vec<(f64, f64)>,
    /// Polar moment of inertia of the disk about the axis, `m D²/8` (kg·m²); `None` when the
    /// mass was given without a disk's geometry.
    pub polar_inertia: Option<f64>,
}

/// An FE rotor with what the model needs beside its matrices.
#[derive(Debug, Clone)]
pub struct FeRotorInput {
    /// Elements, disks, bearings, supports, unbalances, damping.
    pub data: FeRotorData,
    /// Gyroscopic coupling on (`false`: G = 0).
    pub gyroscopic: bool,
    /// Node whose response and stiffness define |Z0| and k_r: the first station's node, else
    /// the first unbalance's, else 0.
    pub reference_node: usize,
}

/// Resolves `[rotor]` of a checked scene.
pub fn resolve(ls: &LoadedScene) -> Result<RotorInput, SceneError> {
    let s = &ls.scene;
    Ok(match &s.rotor {
        RotorSpec::Jeffcott(j) => RotorInput::Jeffcott(jeffcott(ls, j)?),
        RotorSpec::Fe(f) => RotorInput::Fe(Box::new(FeRotorInput {
            data: fe_rotor(ls, f)?,
            gyroscopic: f.gyroscopic,
            reference_node: s
                .stations
                .first()
                .map_or_else(|| f.unbalance.first().map_or(0, |u| u.node), |st| st.node),
        })),
    })
}

/// Jeffcott data: mass from `mass` or the disk (ρ π D²/4 t), stiffness from `stiffness` or the
/// simply supported shaft with the disk at mid-span (48 E I / L³, I = π d⁴/64), damping from
/// `damping` or `damping_ratio` (c = 2ξ√(m k)). Errors name the pair of keys when not exactly
/// one of each is given (as [`crate::scene::validate()`]).
pub fn jeffcott(ls: &LoadedScene, s: &JeffcottSpec) -> Result<JeffcottData, SceneError> {
    let (mass, polar_inertia) =
        match one_of(ls, ("mass", s.mass), ("disk", s.disk.as_ref()), "rotor")? {
            OneOf::First(m) => (m, None),
            OneOf::Second(d) => {
                let m = d.density * PI * d.diameter * d.diameter / 4.0 * d.thickness;
                (m, Some(m * d.diameter * d.diameter / 8.0))
            }
        };
    let stiffness = match one_of(
        ls,
        ("stiffness", s.stiffness),
        ("shaft", s.shaft.as_ref()),
        "rotor",
    )? {
        OneOf::First(k) => k,
        OneOf::Second(sh) => {
            let i = PI * sh.diameter.powi(4) / 64.0;
            48.0 * sh.youngs_modulus * i / sh.length.powi(3)
        }
    };
    let damping = match one_of(
        ls,
        ("damping", s.damping),
        ("damping_ratio", s.damping_ratio),
        "rotor",
    )? {
        OneOf::First(c) => {
            // The ratio `rotor.damping` makes (`rotor.damping_ratio` is bounded in validation).
            let xi = c / (2.0 * (mass * stiffness).sqrt());
            crate::scene::validate::damping_ratio_bound(ls, "rotor.damping", xi)?;
            c
        }
        OneOf::Second(xi) => 2.0 * xi * (mass * stiffness).sqrt(),
    };
    Ok(JeffcottData {
        mass,
        stiffness,
        damping,
        unbalances: s
            .unbalance
            .iter()
            .map(|u| (u.mass * u.radius, u.phase_deg.to_radians()))
            .collect(),
        polar_inertia,
    })
}

/// A bearing's 2×2 stiffness and damping on `[u_x, u_y]`, possibly tabulated against speed.
#[derive(Debug, Clone, PartialEq)]
pub struct Bearing {
    /// Rotor node.
    pub node: usize,
    /// Speeds (rad/s) of the table; empty for constant coefficients.
    pub speeds: Vec<f64>,
    /// `[kxx, kxy, kyx, kyy]` per table row (N/m).
    pub k: Vec<[f64; 4]>,
    /// `[cxx, cxy, cyx, cyy]` per table row (N·s/m).
    pub c: Vec<[f64; 4]>,
    /// Pedestal `(mass kg, stiffness N/m, damping N·s/m)` between bearing and ground.
    pub pedestal: Option<(f64, f64, f64)>,
}

impl Bearing {
    /// Coefficients at speed ω (linear interpolation in the table, constant outside).
    pub fn coefficients(&self, omega: f64) -> ([f64; 4], [f64; 4]) {
        if self.speeds.len() < 2 {
            return (self.k[0], self.c[0]);
        }
        let s = &self.speeds;
        let i = match s.iter().position(|v| *v >= omega) {
            None => return (self.k[s.len() - 1], self.c[s.len() - 1]),
            Some(0) => return (self.k[0], self.c[0]),
            Some(i) => i,
        };
        let t = (omega - s[i - 1]) / (s[i] - s[i - 1]);
        let lerp = |a: [f64; 4], b: [f64; 4]| {
            [
                a[0] + t * (b[0] - a[0]),
                a[1] + t * (b[1] - a[1]),
                a[2] + t * (b[2] - a[2]),
                a[3] + t * (b[3] - a[3]),
            ]
        };
        (
            lerp(self.k[i - 1], self.k[i]),
            lerp(self.c[i - 1], self.c[i]),
        )
    }
}

/// A spring and dashpot from one scalar DOF of a rotor node to ground: a thrust bearing on
/// `u_z` (stiffness N/m, damping N·s/m) or a torsional restraint on `θ_z` — coupling or drive
/// stiffness (N·m/rad, N·m·s/rad). Adds `stiffness` to `K` and `damping` to `C` on that DOF.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundSpring {
    /// Rotor node.
    pub node: usize,
    /// Stiffness (> 0): N/m axial, N·m/rad torsional.
    pub stiffness: f64,
    /// Damping (≥ 0): N·s/m axial, N·m·s/rad torsional.
    pub damping: f64,
}

/// A rigid disk. With axial DOFs it adds its mass to `u_z`, with torsional DOFs its polar
/// inertia `I_p` to `θ_z`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Disk {
    /// Node.
    pub node: usize,
    /// Mass (kg).
    pub mass: f64,
    /// Polar moment of inertia I_p (kg·m²).
    pub ip: f64,
    /// Diametral moment of inertia I_d (kg·m²).
    pub id: f64,
}

impl Disk {
    /// Disk from geometry: annulus of outer diameter `od`, bore `bore`, width `w`, density ρ:
    /// m = ρπ(D²−d²)w/4, I_p = m(R²+r²)/2, I_d = m(3(R²+r²) + w²)/12.
    pub fn from_geometry(node: usize, od: f64, bore: f64, width: f64, density: f64) -> Self {
        let r2 = (od / 2.0).powi(2) + (bore / 2.0).powi(2);
        let mass = density * std::f64::consts::PI * (od * od - bore * bore) / 4.0 * width;
        Disk {
            node,
            mass,
            ip: mass * r2 / 2.0,
            id: mass * (3.0 * r2 + width * width) / 12.0,
        }
    }
}

/// Modal damping: the ratio ζ on every undamped mode (at rest, bearings at the run's speed,
/// without gyroscopics) up to `max_frequency` and at most `modes` modes, lowest first; a
/// repeated frequency (the x and y bending modes of an axisymmetric rotor) is never split.
/// The other modes get none from it (add Rayleigh damping for them).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModalDamping {
    /// ζ (dimensionless).
    pub ratio: f64,
    /// Highest undamped frequency that gets ζ (rad/s); infinite: no limit.
    pub max_frequency: f64,
    /// Largest number of modes that get ζ; `usize::MAX`: no limit.
    pub modes: usize,
}

/// Everything needed to build an FE rotor ([`crate::model::fe_rotor::FeRotor::build`]).
#[derive(Debug, Clone)]
pub struct FeRotorData {
    /// Elements in order along the shaft.
    pub elements: Vec<ShaftSection>,
    /// Disks.
    pub disks: Vec<Disk>,
    /// Point masses `(node, kg)`.
    pub point_masses: Vec<(usize, f64)>,
    /// Bearings.
    pub bearings: Vec<Bearing>,
    /// Unbalances `(node, m_u e kg·m, phase rad)`.
    pub unbalances: Vec<(usize, f64, f64)>,
    /// Rayleigh `[α, β]`.
    pub rayleigh: [f64; 2],
    /// What the Rayleigh damping acts on: the assembly (`α M + β K(Ω)`, disks, point masses,
    /// bearings included), the shaft elements alone (`Σ_e α M_e + β K_e`) or the rotor without
    /// its bearings (`α M_rotor + β K_shaft`); see [`RayleighOn`].
    pub rayleigh_on: RayleighOn,
    /// Modal damping.
    pub modal_damping: Option<ModalDamping>,
    /// Axial DOF `u_z` per node (axial bar elements, see
    /// [`crate::element::timoshenko::axial_element`]); needs `axial_supports`.
    pub axial: bool,
    /// Torsional DOF `θ_z` per node (see [`crate::element::timoshenko::torsion_element`]);
    /// needs `torsional_supports`.
    pub torsion: bool,
    /// Thrust bearings on `u_z`.
    pub axial_supports: Vec<GroundSpring>,
    /// Torsional restraints on `θ_z`.
    pub torsional_supports: Vec<GroundSpring>,
}

/// The data of an FE rotor spec: shaft segments cut into equal elements (material by name,
/// overridden by the given values), disks from their inertias or geometry, bearing tables row
/// by row, unbalances as `m_u e` (kg·m) and phase (rad).
///
/// # Errors
/// A shaft segment whose material is unknown, or that has neither a material nor both
/// `youngs_modulus` and `density` (what [`crate::scene::validate()`] refuses too, with the
/// same key and line).
pub fn fe_rotor(ls: &LoadedScene, s: &FeRotorSpec) -> Result<FeRotorData, SceneError> {
    let elements = shaft_elements(ls, s)?;
    let disks = disks(ls, s)?;
    let bearings = s.bearing.iter().map(bearing).collect();
    let springs = |v: &[GroundSpringSpec]| -> Vec<GroundSpring> {
        v.iter()
            .map(|g| GroundSpring {
                node: g.node,
                stiffness: g.stiffness,
                damping: g.damping,
            })
            .collect()
    };
    Ok(FeRotorData {
        axial: s.axial,
        torsion: s.torsion,
        axial_supports: springs(&s.axial_support),
        torsional_supports: springs(&s.torsional_support),
        elements,
        disks,
        point_masses: s.point_mass.iter().map(|p| (p.node, p.mass)).collect(),
        bearings,
        unbalances: s
            .unbalance
            .iter()
            .map(|u| (u.node, u.mass * u.radius, u.phase_deg.to_radians()))
            .collect(),
        rayleigh: s.rayleigh,
        rayleigh_on: s.rayleigh_on,
        modal_damping: s.modal_damping.as_ref().map(|m| ModalDamping {
            ratio: m.ratio,
            max_frequency: m.max_frequency.unwrap_or(f64::INFINITY),
            modes: m.modes.unwrap_or(usize::MAX),
        }),
    })
}

/// The shaft's elements, segment by segment: each segment's material (named or given), its
/// `elements` equal elements, cylindrical or — a segment with right diameters — conical, the
/// diameters linear in z along the segment.
fn shaft_elements(ls: &LoadedScene, s: &FeRotorSpec) -> Result<Vec<ShaftSection>, SceneError> {
    let mut elements = Vec::new();
    for (i, seg) in s.shaft.iter().enumerate() {
        let named = match seg.material.as_deref() {
            Some(m) => Some(material(m).ok_or_else(|| {
                ls.invalid(
                    &format!("rotor.shaft.{i}.material"),
                    format!("unknown material `{m}` (known: steel, aluminium, titanium; or give youngs_modulus, poisson, density)"),
                )
            })?),
            None => None,
        };
        let (Some(youngs_modulus), Some(density)) = (
            seg.youngs_modulus.or(named.map(|m| m.0)),
            seg.density.or(named.map(|m| m.2)),
        ) else {
            return Err(ls.invalid(
                &format!("rotor.shaft.{i}"),
                "give `material` or `youngs_modulus` and `density`",
            ));
        };
        let section = ShaftSection::cylinder(
            seg.length / seg.elements as f64,
            seg.outer_diameter,
            seg.inner_diameter,
            youngs_modulus,
            seg.poisson.or(named.map(|m| m.1)).unwrap_or(0.3),
            density,
            s.shear,
            s.rotary_inertia,
        );
        let (od_r, id_r) = (
            seg.outer_diameter_right.unwrap_or(seg.outer_diameter),
            seg.inner_diameter_right.unwrap_or(seg.inner_diameter),
        );
        if od_r == seg.outer_diameter && id_r == seg.inner_diameter {
            elements.extend(std::iter::repeat_n(section, seg.elements));
        } else {
            // A conical segment: equal elements, diameters linear in z along the segment.
            let n = seg.elements as f64;
            let at = |l: f64, r: f64, j: usize| l + (r - l) * j as f64 / n;
            elements.extend((0..seg.elements).map(|j| ShaftSection {
                outer_diameter: at(seg.outer_diameter, od_r, j),
                inner_diameter: at(seg.inner_diameter, id_r, j),
                outer_diameter_right: at(seg.outer_diameter, od_r, j + 1),
                inner_diameter_right: at(seg.inner_diameter, id_r, j + 1),
                ..section
            }));
        }
    }
    Ok(elements)
}

/// The rotor's disks: a given mass and inertias, or a geometry (outer diameter, bore, width)
/// and a density or material.
fn disks(ls: &LoadedScene, s: &FeRotorSpec) -> Result<Vec<Disk>, SceneError> {
    let mut disks = Vec::with_capacity(s.disk.len());
    for (i, d) in s.disk.iter().enumerate() {
        disks.push(match d.mass {
            Some(m) => Disk {
                node: d.node,
                mass: m,
                ip: d.polar_inertia.unwrap_or(0.0),
                id: d.diametral_inertia.unwrap_or(0.0),
            },
            None => {
                let rho = d
                    .density
                    .or_else(|| d.material.as_deref().and_then(material).map(|m| m.2));
                let (Some(od), Some(w), Some(rho)) = (d.outer_diameter, d.width, rho) else {
                    return Err(ls.invalid(
                        &format!("rotor.disk.{i}"),
                        "geometry needs `outer_diameter`, `width` and `density` or `material`",
                    ));
                };
                Disk::from_geometry(d.node, od, d.bore, w, rho)
            }
        });
    }
    Ok(disks)
}

/// A bearing's coefficient tables, row by row: `kxx`/`kyy` (`cxx`/`cyy`) where given, else the
/// isotropic `stiffness` (`damping`); absent coefficients are 0.
fn bearing(b: &BearingSpec) -> Bearing {
    let n = b.speeds.len().max(1);
    let at = |v: &Option<ScalarOrTable>, i: usize| -> f64 {
        match v {
            None => 0.0,
            Some(ScalarOrTable::Scalar(x)) => *x,
            Some(ScalarOrTable::Table(t)) => t[i],
        }
    };
    let pick = |iso: &Option<ScalarOrTable>, own: &Option<ScalarOrTable>, i: usize| {
        if own.is_some() {
            at(own, i)
        } else {
            at(iso, i)
        }
    };
    Bearing {
        node: b.node,
        speeds: b.speeds.clone(),
        k: (0..n)
            .map(|i| {
                [
                    pick(&b.stiffness, &b.kxx, i),
                    at(&b.kxy, i),
                    at(&b.kyx, i),
                    pick(&b.stiffness, &b.kyy, i),
                ]
            })
            .collect(),
        c: (0..n)
            .map(|i| {
                [
                    pick(&b.damping, &b.cxx, i),
                    at(&b.cxy, i),
                    at(&b.cyx, i),
                    pick(&b.damping, &b.cyy, i),
                ]
            })
            .collect(),
        pedestal: b
            .pedestal
            .as_ref()
            .map(|p| (p.mass, p.stiffness, p.damping)),
    }
}
