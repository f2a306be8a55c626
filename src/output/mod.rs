//! Writing results: the output directory ([`OutDir`]) and its manifest ([`manifest`]),
//! `summary.json` ([`summary`]), every CSV table ([`csv`]), the PNG pictures ([`figures`]; mode
//! shapes and the critical speed map: [`rotordyn`]), a speed transient's tables and pictures
//! ([`transient`]) and the full spectra of x + iy ([`whirl`]). The VTK/HDF5 time series are
//! written by the frame sinks of [`crate::results`] into the same staging folder; a study's
//! case store is [`crate::study`]'s.
//!
//! Every file is first written into a staging folder inside the output directory and moved
//! into place only when the whole command has succeeded, by a journaled commit that moves
//! `summary.json` — the run's marker — last: at every instant, a directory that holds
//! `summary.json` holds exactly one run's complete results. A run locks the directory for its
//! whole life, so a second run into it fails at once; a killed commit is completed or
//! discarded by the next run; file data and directories are synced to the disk in the order
//! that keeps this true after a power loss ([`durable`]). The protocol, step by step, is in
//! [`outdir`]. The directory is checked for writability before any computation starts
//! ([`OutDir::prepare`]).

pub mod autonomous;
pub mod branch;
pub mod csv;
pub mod drawings;
pub mod durable;
pub mod figures;
pub mod manifest;
pub mod outdir;
pub mod rotordyn;
pub mod summary;
pub mod thermal;
pub mod transient;
pub mod transient_stress;
pub mod wear;
pub mod whirl;

pub use drawings::Drawings;
pub use manifest::{parse_manifest, Manifest, MANIFEST};
pub use outdir::OutDir;
