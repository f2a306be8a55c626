//! The spin of every frame in the HDF5 series: the plain group `/spin` and the VTKHDF field
//! data `/VTKHDF/FieldData` with its `Steps/FieldDataOffsets` (cargo feature `hdf5`).
//!
//! Per frame k (one value each, so frame k is row k):
//!
//! * `/spin/omega` Ω (rad/s), `/spin/speed_ratio` Ω/ω_n, `/spin/phi` the spin angle φ (rad,
//!   φ(0) = 0), `/spin/omega_dot` Ω̇ (rad/s²) — the speed profile's or a driven rotor's spin
//!   state at the frame's time (`/time`); at constant speed Ω, Ω/ω_n constant, φ = Ω t, Ω̇ = 0;
//! * `/VTKHDF/FieldData/<name>` for `TimeValue` (s) and the same four names, one tuple per step
//!   at `Steps/FieldDataOffsets/<name>` = k: VTK's `vtkHDFReader` gives them as the field data
//!   of step k.

use super::hdf5_io::{attr_str, Column};
use super::vtk::{field_values, FIELD_DATA};
use super::FrameState;
use hdf5_metno as h5;

/// Plain `/spin` columns, the VTKHDF field-data columns and their offsets.
pub(super) struct SpinColumns {
    plain: Vec<Column<f64>>,
    field: Vec<Column<f64>>,
    offsets: Vec<Column<i64>>,
}

/// Names and units of the `/spin` datasets, in the order of [`plain_values`].
const PLAIN: [(&str, &str); 4] = [
    ("omega", "rad/s"),
    ("speed_ratio", "1"),
    ("phi", "rad"),
    ("omega_dot", "rad/s^2"),
];

fn plain_values(st: &FrameState) -> [f64; 4] {
    [st.omega, st.speed_ratio, st.phi, st.omega_dot]
}

/// Unit of a field-data array of [`FIELD_DATA`].
fn field_unit(name: &str) -> &'static str {
    match name {
        "TimeValue" => "s",
        other => PLAIN
            .iter()
            .find(|(n, _)| *n == other)
            .map_or("", |(_, u)| u),
    }
}

impl SpinColumns {
    /// Creates `/spin` in `f`, `FieldData` in the VTKHDF group `v` and `FieldDataOffsets` in
    /// its `steps` group.
    pub(super) fn new(f: &h5::File, v: &h5::Group, steps: &h5::Group) -> h5::Result<Self> {
        let g = f.create_group("spin")?;
        attr_str(
            &g,
            "description",
            "spin state per frame: omega (rad/s), speed_ratio = omega/omega_n, phi (spin angle, rad, phi(0) = 0), omega_dot (rad/s^2)",
        )?;
        let plain = PLAIN
            .iter()
            .map(|(n, u)| Column::new(&g, n, 1, &[], u))
            .collect::<h5::Result<Vec<_>>>()?;
        let fd = v.create_group("FieldData")?;
        let fdo = steps.create_group("FieldDataOffsets")?;
        let field = FIELD_DATA
            .iter()
            .map(|n| Column::new(&fd, n, 1, &[], field_unit(n)))
            .collect::<h5::Result<Vec<_>>>()?;
        let offsets = FIELD_DATA
            .iter()
            .map(|n| Column::new(&fdo, n, 1, &[], ""))
            .collect::<h5::Result<Vec<_>>>()?;
        Ok(Self {
            plain,
            field,
            offsets,
        })
    }

    /// Appends frame `k`.
    pub(super) fn push(&mut self, k: i64, st: &FrameState) -> h5::Result<()> {
        for (c, v) in self.plain.iter_mut().zip(plain_values(st)) {
            c.push([v])?;
        }
        for ((c, o), v) in self
            .field
            .iter_mut()
            .zip(&mut self.offsets)
            .zip(field_values(st))
        {
            c.push([v])?;
            o.push([k])?;
        }
        Ok(())
    }

    /// Appends the buffered frames.
    pub(super) fn flush(&mut self) -> h5::Result<()> {
        for c in self.plain.iter_mut().chain(&mut self.field) {
            c.flush()?;
        }
        for o in &mut self.offsets {
            o.flush()?;
        }
        Ok(())
    }
}
