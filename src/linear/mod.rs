//! Linear rotordynamics of the rotor alone, in the frequency domain: damped modes at a speed
//! ([`modes`]), the Campbell diagram and critical speeds ([`mod@campbell`]), the undamped critical
//! speed map against bearing stiffness ([`mod@critical_map`]), a mode's whirl ellipses and shaft
//! lines ([`mode_shape`]), the unbalance response and the static deflection ([`response`]).
//!
//! This stage stands beside the time loop: it needs the model's matrices `M`, `K(Ω)`, `C(Ω)`,
//! `G` ([`crate::model::Rotor::matrices`]) and dense or sparse linear algebra, never a step.
//! The time-domain analysis may use it (a start from the linear response), not the other way.
//!
//! Units: speeds and frequencies in rad/s unless a name says Hz or rpm, displacements in m,
//! rotations in rad; a mode whirls forward when it turns with the spin (counter-clockwise seen
//! from +z for Ω > 0).

pub mod campbell;
pub mod critical_map;
pub mod mode_shape;
pub mod modes;
pub mod response;

pub use campbell::{campbell, CampbellResults, CriticalSpeed, Track};
pub use critical_map::{critical_map, log_range, CriticalMapResults, Swept};
pub use mode_shape::RotorLine;
pub use modes::{
    mac, modal, modal_in, mode_label, mode_mac, undamped_modes, ModalBasis, ModalResults, Mode,
    ModeKind, Whirl, FULL_BASIS,
};
pub use response::{
    default_response_nodes, lateral_at_nodes, peak_response, speed_list, static_deflection,
    unbalance_response, ResponsePoint,
};
