//! rubsim's integration tests as one test binary (one link, one harness running every test on
//! every core): `cargo test --release --test suite` runs them all, `--test suite autostep::`
//! one file's. tests/no_alloc.rs stays a binary of its own (its counting global allocator).
//! Each module is one former `tests/<name>.rs`; what they share is `common` (tests/common).

#[path = "../common/mod.rs"]
mod common;

mod abradable;
mod architecture;
mod autonomous;
mod autostep;
mod campbell;
mod cases;
mod check_outputs;
mod cli;
mod coexistence;
mod contact;
mod contact_damping;
mod continue_key;
mod convergence;
mod critical_map;
mod driven;
mod duration;
mod dynamics;
mod error_bound;
mod events;
mod fe_rotor;
mod floquet;
mod fuzz_corpus;
mod gmsh_guard;
mod hardening;
mod implicit;
mod import_ross;
mod io;
mod large_stator;
mod mesh;
mod mutation;
mod orbit_series;
mod orbit_snapshots;
mod outdir;
mod periodic;
mod reduction;
mod reduction_auto;
mod reduction_stator;
mod regression;
mod ring_kinematics;
mod ross_options;
mod schema;
mod segments;
mod steady;
mod step_refinement;
mod stick;
mod switch;
mod thermal;
mod thermal_conduction;
mod thermal_fe;
mod thermal_map;
mod transient_scenes;
mod transients;
mod variational;
mod verification;
mod wear;
mod whirl;
