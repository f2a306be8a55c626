//! The scenes of the tests, each written once: the repository's scenes the tests build on, and
//! builders for the families of small scenes (a uniform steel shaft, the unit Jeffcott rotor,
//! the paper's rod swapped for another stator, …). Scene files of the tests' own are under
//! `tests/data/scenes/` (see [`super::data`]).

/// The paper's case study (Jeffcott rotor, partial rub on the rod, sweep 0.5…6.0).
pub const PAPER: &str = include_str!("../../scenes/paper/partial_rub.toml");
/// The paper's rotor as an 8-element Timoshenko FE model rubbing the rod.
pub const PAPER_FE: &str = include_str!("../../scenes/fe/paper_rotor_rub.toml");
/// [`PAPER_FE`] with torsional DOFs, driven through a 1000 N·m/rad coupling at node 0.
pub const PAPER_TORSION: &str = include_str!("../../scenes/fe/paper_rotor_rub_torsion.toml");
/// Friswell et al. (2010) Example 5.9.1 / ROSS `rotor_example`: 1.5 m, 50 mm steel shaft in 6
/// elements, disks (70 mm wide, bore 50 mm) of 280 mm at node 2 and 350 mm at node 4, bearings
/// of 1 MN/m at the ends.
pub const FRISWELL: &str = include_str!("../../scenes/fe/friswell_5_9_1.toml");

/// The `[run.sweep]` table of [`PAPER`].
const PAPER_SWEEP: &str = "[run.sweep]\nfrom = 0.5\nto = 6.0\nstep = 0.1";

/// [`PAPER`] without its sweep: a single-speed scene (`run.speed_ratio` set by override).
pub fn paper_single() -> String {
    PAPER.replace(PAPER_SWEEP, "")
}

/// [`paper_single`] with the rod's clearance given in metres (1.2e-4 m).
pub fn paper_single_si() -> String {
    paper_single().replace("clearance_nd = 0.6 ", "clearance = 1.2e-4")
}

/// [`paper_single`] with its rod replaced by the `[[stator]]` table `stator`.
pub fn paper_with_stator(stator: &str) -> String {
    let t = paper_single();
    let a = t.find("[[stator]]").unwrap();
    let b = t.find("[run]").unwrap();
    format!("{}{}\n{}", &t[..a], stator, &t[b..])
}

/// [`PAPER_FE`] with modal damping `ratio` (and the mode selection `limit`, e.g. `modes = 1`)
/// instead of Rayleigh damping.
pub fn paper_modal(ratio: f64, limit: &str) -> String {
    PAPER_FE.replace(
        "rayleigh = [65.3, 0.0]\n",
        &format!("\n[rotor.modal_damping]\nratio = {ratio}\n{limit}\n"),
    )
}

/// The `[run]` table of the FE shaft scenes.
pub const RUN: &str = "[run]\nspeed_ratio = 1.0\n";

/// An FE rotor of one uniform steel shaft (E = 2.1e11 Pa, ν = 0.3, ρ = 7800 kg/m³) of `length`
/// × `diameter` (m) in `n` elements on lateral bearings of `bearing` N/m at nodes 0 and `n`;
/// `options` are further `[rotor]` keys, `parts` (disks, supports) follow the bearings.
fn steel_shaft(
    options: &str,
    length: &str,
    diameter: &str,
    n: usize,
    bearing: &str,
    parts: &str,
) -> String {
    format!(
        r#"
[rotor]
kind = "fe"
{options}
[[rotor.shaft]]
length = {length}
outer_diameter = {diameter}
elements = {n}
youngs_modulus = 2.1e11
poisson = 0.3
density = 7800.0
[[rotor.bearing]]
node = 0
stiffness = {bearing}
[[rotor.bearing]]
node = {n}
stiffness = {bearing}
{parts}{RUN}"#
    )
}

/// Simply supported uniform shaft (2 m × 0.2 m, stiff bearings at both ends), `n` elements.
pub fn ss_shaft(n: usize, shear: bool) -> String {
    steel_shaft(&format!("shear = {shear}"), "2.0", "0.2", n, "1.0e14", "")
}

/// Uniform steel shaft of 2 m × 0.2 m in `n` elements, lateral bearings at the ends, axial
/// DOFs held by a very stiff thrust bearing at node 0 (fixed–free bar).
pub fn axial_bar(n: usize) -> String {
    steel_shaft(
        "axial = true",
        "2.0",
        "0.2",
        n,
        "1.0e9",
        "[[rotor.axial_support]]\nnode = 0\nstiffness = 1.0e16\n",
    )
}

/// Disk of polar inertia `ip` at the free end (node `n`) of a steel shaft 0.5 m × 20 mm in `n`
/// elements whose left end (node 0) is held in torsion by `k0` N·m/rad.
pub fn torsion_disk(n: usize, ip: f64, k0: f64) -> String {
    steel_shaft(
        "torsion = true",
        "0.5",
        "0.02",
        n,
        "1.0e7",
        &format!(
            "[[rotor.disk]]\nnode = {n}\nmass = 5.0\npolar_inertia = {ip}\ndiametral_inertia = 0.003\n[[rotor.torsional_support]]\nnode = 0\nstiffness = {k0}\n"
        ),
    )
}

/// A rotor with every lateral feature (cross-coupled bearing, pedestal, point mass, Rayleigh
/// damping, gyroscopics) for the golden comparison of the assembled matrices.
pub const GOLDEN_ROTOR: &str = r#"
[rotor]
kind = "fe"
rayleigh = [1.5, 2.0e-5]
[[rotor.shaft]]
length = 1.5
outer_diameter = 0.05
inner_diameter = 0.01
elements = 6
material = "steel"
[[rotor.disk]]
node = 2
outer_diameter = 0.28
bore = 0.05
width = 0.07
density = 7810.0
[[rotor.point_mass]]
node = 5
mass = 1.25
[[rotor.bearing]]
node = 0
kxx = 1.0e6
kxy = 2.0e5
kyx = -2.0e5
kyy = 1.5e6
cxx = 300.0
cyy = 400.0
[[rotor.bearing]]
node = 6
stiffness = 1.0e6
damping = 250.0
pedestal = { mass = 12.0, stiffness = 3.0e7, damping = 900.0 }
[run]
speed_ratio = 1.0
"#;

/// [`GOLDEN_ROTOR`] with `axial` and `torsion` set as given (and a support for each).
pub fn full_rotor(axial: bool, torsion: bool) -> String {
    let mut t = GOLDEN_ROTOR.replace(
        "rayleigh = [1.5, 2.0e-5]",
        &format!("rayleigh = [1.5, 2.0e-5]\naxial = {axial}\ntorsion = {torsion}"),
    );
    let mut extra = String::new();
    if axial {
        extra.push_str("[[rotor.axial_support]]\nnode = 0\nstiffness = 5.0e8\ndamping = 2.0e3\n");
    }
    if torsion {
        extra.push_str("[[rotor.torsional_support]]\nnode = 6\nstiffness = 2.0e4\ndamping = 3.0\n");
    }
    t = t.replace("[run]", &format!("{extra}[run]"));
    t
}

/// Jeffcott rotor with m = 1 kg, k = 1 N/m (ω_n = 1 rad/s), damping ratio `xi`, one station `s`
/// of radius 0.05 m and friction `mu`; `unbalance` and `stator` tables as given, `run` the body
/// of `[run]`.
fn unit_jeffcott(xi: f64, unbalance: &str, mu: f64, stator: &str, run: &str) -> String {
    format!(
        r#"
[rotor]
kind = "jeffcott"
mass = 1.0
stiffness = 1.0
damping_ratio = {xi}
{unbalance}[[station]]
name = "s"
radius = 0.05
friction = {mu}
{stator}
[run]
{run}"#
    )
}

/// Ring stator of stiffness ratio κ = 25 around the station `s` of the unit rotor, with the
/// radially elastic contact law of the full-annular-rub and dry-whip oracles
/// (`kinematics = "radial"`: force k_s(R − δ) along the rotor's radius, docs/ORACLES.md §2–3).
pub fn unit_ring(clearance: f64) -> String {
    format!(
        "[[stator]]\nkind = \"ring\"\nname = \"ring\"\nstation = \"s\"\nclearance = {clearance}\nstiffness_ratio = 25.0\nkinematics = \"radial\"\n"
    )
}

/// Ring stator taking the whole contact force (exact kinematics, the default) of stiffness
/// ratio `kappa` and clearance `clearance` (m) around the station `s` of the unit rotor.
pub fn unit_exact_ring(clearance: f64, kappa: f64) -> String {
    format!(
        "[[stator]]\nkind = \"ring\"\nname = \"ring\"\nstation = \"s\"\nclearance = {clearance}\nstiffness_ratio = {kappa}\n"
    )
}

/// The unit Jeffcott rotor with unbalance m_u e = 1e-3 kg·m (e = 1e-3 m), μ = 0.1, an optional
/// `stator` (e.g. [`unit_ring`]), 120 revolutions (60 cut) at ω/ω_n = 1.
pub fn unit_rotor(xi: f64, stator: &str) -> String {
    unit_jeffcott(
        xi,
        "[[rotor.unbalance]]\nmass = 1.0e-3\nradius = 1.0\n",
        0.1,
        stator,
        "speed_ratio = 1.0\nrevolutions = 120\ntransient_revolutions = 60\nerror_estimate = false\n",
    )
}

/// The unit Jeffcott rotor (ξ = 0.2) without unbalance inside a ring of clearance `delta`,
/// friction `mu`, at Ω = 2 ω_n for `revs` revolutions, none cut.
pub fn unit_rotor_in_ring(mu: f64, delta: f64, revs: usize) -> String {
    unit_jeffcott(
        0.2,
        "",
        mu,
        &unit_ring(delta),
        &format!(
            "speed_ratio = 2.0\nrevolutions = {revs}\ntransient_revolutions = 0\nharmonics = 16\nerror_estimate = false\n"
        ),
    )
}
