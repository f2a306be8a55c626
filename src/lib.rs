//! rubsim (being built).
#![warn(missing_docs)]
pub mod analysis;
pub mod assembly;
pub mod contact;
pub mod element;
pub mod error;
pub mod linalg;
pub mod math;
pub mod mesh;
pub mod model;
pub mod output;
pub mod plot;
pub mod resolve;
pub mod results;
pub mod scene;
pub mod signal;
pub mod time;
