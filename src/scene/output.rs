//! `[output]`: pictures, the analysed node and component, time series.

use super::yes;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// What to write.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Write PNG pictures.
    #[serde(default = "yes")]
    pub png: bool,
    /// Orbit grids: each a list of ω/ω_n values (a 3×3 grid like Figs. 5–7).
    #[serde(default)]
    pub orbit_grids: Vec<Vec<f64>>,
    /// Speeds whose contact-force histories are plotted (Fig. 9).
    #[serde(default)]
    pub force_histories: Vec<f64>,
    /// A speed transient (`[run.speed_profile]`) only: speeds ω/ω_n whose orbits are drawn at
    /// every passage of the speed history through them (`orbit_snapshots.csv`, `.png`), over
    /// two revolutions of that speed centred on the passage. Always in
    /// ω/ω_n, whatever `run.speed_profile.unit`.
    #[serde(default)]
    pub snapshot_speeds: Vec<f64>,
    /// Response component analysed in spectra and cascades: `"y"` (vertical, default) or `"x"`.
    #[serde(default = "default_component")]
    #[schemars(extend("enum" = ["x", "y"]))]
    pub component: String,
    /// Upper frequency of cascades, in units of ω_n (default: the top speed).
    pub cascade_max_freq: Option<f64>,
    /// Rotor node whose orbit, Poincaré section, spectrum, cascade and |Z0| normalisation the
    /// analysis uses (default: the first station's node). Contact forces stay per station.
    pub node: Option<usize>,
    /// VTK XML time series: `.vtu` frames and a `.pvd` collection (absent: not written).
    pub vtk: Option<SeriesSpec>,
    /// HDF5 time series with a transient VTKHDF group (absent: not written).
    pub hdf5: Option<SeriesSpec>,
    /// Which speeds of a sweep write the time series above, into `speed_<ω/ω_n>/` sub-folders:
    /// `false` (default: none), `true` (all) or a list of ω/ω_n. `rubsim run` always writes them.
    #[serde(default)]
    pub per_speed: PerSpeed,
}

/// A time-series writer (`output.vtk`, `output.hdf5`): which frames, which fields.
///
/// Frames are taken at the integration steps that are multiples of `every` and lie within
/// `[from_revolution, to_revolution]` (revolutions of the rotor since t = 0).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SeriesSpec {
    /// Steps between frames (default: the recording interval, i.e. `run.samples_per_rev`
    /// frames per revolution, on the same instants as the analysis).
    pub every: Option<usize>,
    /// Fields to write (default: all).
    #[serde(default = "all_series_fields")]
    pub fields: Vec<SeriesField>,
    /// First revolution written (default 0, the start of the run).
    #[serde(default)]
    pub from_revolution: f64,
    /// Last revolution written (default: the end of the run, `run.revolutions`).
    pub to_revolution: Option<f64>,
}

/// Fields of the time series.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum SeriesField {
    /// Node displacements of rotor and stators (m).
    Displacement,
    /// Node velocities (m/s), by a backward difference over one time step.
    Velocity,
    /// Contact: pair normal forces (multipliers) and forces, node contact forces (N).
    ContactForce,
    /// Stator element axial force (N), stress (Pa) and strain.
    Stress,
}

/// All [`SeriesField`]s.
pub fn all_series_fields() -> Vec<SeriesField> {
    vec![
        SeriesField::Displacement,
        SeriesField::Velocity,
        SeriesField::ContactForce,
        SeriesField::Stress,
    ]
}

/// Per-speed time series of a sweep: `false`, `true` or a list of ω/ω_n.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum PerSpeed {
    /// None (`false`) or every speed (`true`).
    All(bool),
    /// These speeds ω/ω_n (each must be one of the sweep's speeds).
    Speeds(Vec<f64>),
}

impl Default for PerSpeed {
    fn default() -> Self {
        PerSpeed::All(false)
    }
}

impl Default for OutputSpec {
    fn default() -> Self {
        Self {
            png: true,
            orbit_grids: Vec::new(),
            force_histories: Vec::new(),
            snapshot_speeds: Vec::new(),
            component: default_component(),
            cascade_max_freq: None,
            node: None,
            vtk: None,
            hdf5: None,
            per_speed: PerSpeed::default(),
        }
    }
}

/// A lateral response component of a rotor node: what `output.component` names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Component {
    /// `"x"`: horizontal.
    X,
    /// `"y"`: vertical (the default).
    #[default]
    Y,
}

impl Component {
    /// The component named `"x"` or `"y"`; `None` for any other name.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "x" => Some(Component::X),
            "y" => Some(Component::Y),
            _ => None,
        }
    }
    /// Name as written in scene files.
    pub fn name(self) -> &'static str {
        match self {
            Component::X => "x",
            Component::Y => "y",
        }
    }
    /// Index in a node's `[u_x, u_y]`: 0 for x, 1 for y.
    pub fn index(self) -> usize {
        match self {
            Component::X => 0,
            Component::Y => 1,
        }
    }
}

fn default_component() -> String {
    "y".into()
}
