//! # rubsim — rotor-to-stator rubbing vibration with finite elements
//!
//! A flexible rotor (Jeffcott, or Timoshenko beam elements with disks, bearings, unbalance and
//! gyroscopics) with radially rigid circular sections rubs a deformable stator of any geometry
//! (a rod, a ring, an FE truss or a gmsh-meshed 2-D/3-D solid). Contact is "node to nodes",
//! unilateral, with Coulomb friction, enforced by Lagrange multipliers; time integration is
//! explicit central differences with forward-increment multipliers — the algorithm of *A finite
//! element-based algorithm for rubbing induced vibration prediction in rotors* (the seed paper;
//! equation numbers in the code are the paper's).
//!
//! ## The pipeline: one-way stages
//!
//! ```text
//! scene ──► resolve ──► model ──► time ──► analysis ──► output / results
//! TOML,      indices,     rotor,    the       one speed,    summary.json, CSV, PNG;
//! --set,     enums,       stators,  Stepper   sweeps,       VTK/HDF5 writers, attached
//! file:line  meshes by    Case(ω)   (frames   regimes,      as frame sinks by the
//!            gmsh           │       to sinks) errors        command layer (src/cli)
//!                           └──► linear: modes, Campbell, critical speeds, unbalance
//!                                response (the frequency domain, beside the time loop)
//! ```
//!
//! Each stage takes plain data from the one before and knows nothing of the ones after; a
//! module imports only modules of its own stage or below, in this order (lowest first):
//!
//! 1. [`error`], [`math`] — error types of every layer; small dense kernels, `V2`;
//! 2. [`linalg`], [`signal`], [`mesh`], [`element`], [`assembly`], [`plot`] — sparse storage
//!    and factorisations (faer), spectra and Poincaré sections, gmsh meshes, pure element
//!    kernels, the element-to-global scatter, PNG figures;
//! 3. [`contact`] — pair conventions, targets, gap kernels, broad phase, the complementarity
//!    solver;
//! 4. [`scene`] — what the user wrote (serde, `--set`, validation with file, key and line);
//! 5. [`resolve`] — the scene as plain data: station indices, enums, clearances, meshes found
//!    or made by gmsh and read;
//! 6. [`model`] — rotor and stators built from resolved data; [`model::Case`] at a speed;
//! 7. [`linear`] — linear rotordynamics of the rotor alone, apart from the time loop: damped
//!    modes, Campbell diagram, critical speed map, mode shapes, unbalance response, static
//!    deflection;
//! 8. [`time`] — the step plan and the [`time::Stepper`] (predict → select → solve → correct →
//!    guard → record), frames for sinks;
//! 9. [`analysis`] — one path for a run ([`analysis::prepare`] once, then run with any sinks),
//!    sweeps, convergence, regimes, bench metrics, stress probe;
//! 10. [`output`], [`results`] — files: summary, CSV, figures; the VTK/HDF5 frame sinks;
//! 11. [`study`] — sweeps and maps as cases: variants × speeds, shards, the case store,
//!     resume and merge.
//!
//! The `rubsim` binary (`src/main.rs`, `src/cli/`) parses arguments, loads a scene, calls one
//! analysis, attaches sinks and hands results to `output`; it holds no numerics.
//!
//! ## Conventions (also written on the types)
//!
//! * SI units inside (`_deg` keys are the only non-SI input). Non-dimensional results (`_nd`):
//!   displacement over |Z0(ω)| (the steady unbalance response without stator), force over
//!   |Σ m_u e e^{iφ}| ω², frequency over ω_n.
//! * Rotor axis z, x horizontal, y vertical; Ω > 0 spins counter-clockwise seen from +z; an
//!   unbalance `m_u e` at phase φ loads `m_u e ω² (cos(ωt+φ), sin(ωt+φ))`.
//! * Rotor FE node DOFs `[u_x, u_y, θ_x, θ_y]` (θ_y = ∂u_x/∂z, θ_x = −∂u_y/∂z), axial `u_z` and
//!   torsional `θ_z` numbered after all lateral DOFs when modelled.
//! * Contact pair (C, A): n from the section centre C to the stator node A, gap
//!   `g = n·(x_A − x_C) − r ≥ 0` open; tangent `a = Ω × n`; normal force `p ≥ 0` in
//!   compression (the paper's λ_N = −p); force on the rotor `−(n + μa)p`, on the stator
//!   `+(n + μa)p` (permanent slip).
//!
//! ## Example: one speed of the paper's case
//!
//! ```
//! use rubsim::{analysis, model::Model, scene};
//! let sets = ["run.revolutions=40", "run.transient_revolutions=20", "run.error_estimate=false"];
//! let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
//! let ls = scene::load(std::path::Path::new("scenes/paper/partial_rub.toml"), &sets)?;
//! let model = Model::from_scene(&ls)?;
//! let settings = analysis::RunSettings::from_run(&ls.scene.run, &ls.scene.output.component);
//! // ω/ω_n = 1.7: the first quasi-resonance, synchronous (Poincaré period 1).
//! let r = analysis::run_speed(&model, &settings.request(1.7), analysis::Keep::default())?;
//! assert_eq!(r.period, 1);
//! assert!(r.stats.min_gap > -1e-12); // no penetration after the correction
//! # Ok::<(), rubsim::error::Error>(())
//! ```
#![warn(missing_docs)]
pub mod analysis;
pub mod assembly;
pub mod contact;
pub mod element;
pub mod error;
pub mod linalg;
pub mod linear;
pub mod math;
pub mod mesh;
pub mod model;
pub mod output;
pub mod plot;
pub mod resolve;
pub mod results;
pub mod scene;
pub mod signal;
pub mod study;
pub mod time;
