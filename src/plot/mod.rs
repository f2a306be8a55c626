//! PNG figures: orbit grids, spectrum cascades, bifurcation diagrams, stacked time series,
//! log–log work-precision plots and plain line plots.
//!
//! All figures are rendered with `plotters` into a bitmap and written as PNG to exactly the
//! path given by the caller. Text uses the embedded DejaVu Sans font (the `ab_glyph` backend of
//! `plotters` has no system fonts), registered once under the family name `sans-serif`.
//! The bitmap encoder infers the format from the extension, so a target without a `.png`
//! extension (e.g. a temporary name) is rendered to a hidden `.png` sibling and renamed to it.
//!
//! Every function is robust to empty input (a page with the title and "no data" is written),
//! to non-finite values (skipped; lines are broken at them), to single points and to zero
//! data ranges (ranges are padded).
//!
//! The module is split by concern: `style` (font, palette, sizes, tick labels, writing the
//! PNG), `chart` (the frame and axes every chart is built with, shared drawing helpers), `geom`
//! (data ranges, clipping, equal aspect, markers), and one file per kind of figure: `orbit`,
//! `cascade`, `whirl` (full spectra of x + iy and their cascades), `xy` (bifurcation, stacked
//! series, log–log, lines), `mesh_field` and `mode_shape` (a mode along the rotor axis, 2-D
//! and 3-D).

mod cascade;
mod chart;
mod diagram;
mod geom;
mod map;
mod mesh_field;
mod mode_shape;
mod orbit;
mod style;
#[cfg(test)]
mod tests;
mod whirl;
mod xy;

pub use cascade::{cascade, CascadeLine};
pub use diagram::{branch_diagram, BranchLine};
pub use map::{category_map, field_map, MapGrid};
pub use mesh_field::mesh_field;
pub use mode_shape::{mode_shape_2d, mode_shape_3d, Shape3d, ShapeLine};
pub use orbit::{orbit_grid, Boundary, OrbitPanel};
pub use whirl::{full_cascade, full_spectrum, WhirlRow};
pub use xy::{bifurcation, equal_aspect, lines, loglog, loglog_marked, stacked_series};
pub use xy::{Curve, Series};
