//! rubsim (being built).
#![warn(missing_docs)]
pub mod contact;
pub mod error;
pub mod linalg;
pub mod math;
pub mod model;
pub mod scene;
pub mod time;
pub mod analysis;
pub mod output;
pub mod plot;
pub mod signal;
