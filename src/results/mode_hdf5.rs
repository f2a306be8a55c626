//! A mode shape in HDF5 (`modes/mode_NN.vtkhdf`, cargo feature `hdf5`): plain datasets under
//! `/mode` for scripts, and a transient VTKHDF 2 `UnstructuredGrid` `/VTKHDF` — the rotor's
//! polyline, written once, with the static shape arrays of [`super::modes::shape_arrays`] and
//! the `displacement` of the [`super::modes::FRAMES`] frames of one period — that
//! `pyvista.read`/ParaView animate. Layout: `docs/OUTPUTS.md`, "Mode shapes".

use super::hdf5_io::{attr, attr_str, close_on_exec, static_ds, vtkhdf_group};
use super::modes::{frame_displacement, phases, shape_arrays, ShapeArrays, FRAMES};
use crate::error::{Error, Result};
use crate::linear::mode_shape::{node_shape, RotorLine};
use crate::linear::modes::Mode;
use hdf5_metno as h5;
use std::path::Path;

/// Writes mode `index` (0-based) of a modal analysis at spin speed `speed` (rad/s) to `path`.
///
/// # Errors
/// [`Error::Output`] naming the file.
pub fn write_mode(
    path: &Path,
    line: &RotorLine,
    mode: &Mode,
    index: usize,
    speed: f64,
) -> Result<()> {
    write_h5(path, line, mode, index, speed)
        .map_err(|e| Error::output(path, format!("writing HDF5: {e}")))
}

fn write_h5(
    path: &Path,
    line: &RotorLine,
    mode: &Mode,
    index: usize,
    speed: f64,
) -> h5::Result<()> {
    let f = h5::File::create(path)?;
    close_on_exec(&f);
    attr_str(&f, "format", "rubsim mode shape 1 (docs/OUTPUTS.md)")?;
    attr_str(&f, "rubsim_version", env!("CARGO_PKG_VERSION"))?;
    attr(&f, "mode", (index + 1) as i64)?;
    attr(&f, "speed_rad_s", speed)?;
    attr(&f, "omega_d_rad_s", mode.omega_d)?;
    attr(&f, "freq_hz", mode.freq_hz)?;
    attr(&f, "damping_ratio", mode.damping_ratio)?;
    attr(&f, "log_dec", mode.log_dec)?;
    attr_str(&f, "whirl", mode.whirl.label())?;
    attr_str(&f, "kind", mode.kind.label())?;
    let n = line.z.len();
    let g = f.create_group("mode")?;
    static_ds(&g, "node_z", &[n], &line.z, "m")?;
    let shape = node_shape(mode);
    let re: Vec<f64> = shape.iter().flat_map(|p| p.map(|c| c.re)).collect();
    let im: Vec<f64> = shape.iter().flat_map(|p| p.map(|c| c.im)).collect();
    let cols = "u_x u_y theta_x theta_y";
    let ds_re = static_ds(&g, "shape_re", &[n, 4], &re, "")?;
    attr_str(&ds_re, "columns", cols)?;
    let ds_im = static_ds(&g, "shape_im", &[n, 4], &im, "")?;
    attr_str(&ds_im, "columns", cols)?;
    static_ds(&g, "phase", &[FRAMES], &phases(), "rad")?;
    let disks: Vec<i64> = line.disk_nodes.iter().map(|&d| d as i64).collect();
    let bearings: Vec<i64> = line.bearing_nodes.iter().map(|&d| d as i64).collect();
    static_ds(&g, "disk_nodes", &[disks.len()], &disks, "")?;
    static_ds(&g, "bearing_nodes", &[bearings.len()], &bearings, "")?;
    vtkhdf(&f, line, mode)?;
    f.flush()?;
    Ok(())
}

/// The transient `/VTKHDF` group: the polyline once, the static shape arrays (offset 0 at every
/// step) and the frames' `displacement` (and `twist`).
fn vtkhdf(f: &h5::File, line: &RotorLine, mode: &Mode) -> h5::Result<()> {
    let n = line.z.len();
    let v = vtkhdf_group(f)?;
    static_ds(&v, "NumberOfPoints", &[1], &[n as i64], "")?;
    static_ds(&v, "NumberOfCells", &[1], &[1_i64], "")?;
    static_ds(&v, "NumberOfConnectivityIds", &[1], &[n as i64], "")?;
    let pts: Vec<f64> = line.z.iter().flat_map(|z| [0.0, 0.0, *z]).collect();
    static_ds(&v, "Points", &[n, 3], &pts, "m")?;
    let conn: Vec<i64> = (0..n as i64).collect();
    static_ds(&v, "Connectivity", &[n], &conn, "")?;
    static_ds(&v, "Offsets", &[2], &[0, n as i64], "")?;
    // VTK_POLY_LINE (4), or VTK_VERTEX (1) for a one-node rotor.
    let ty: u8 = if n > 1 { 4 } else { 1 };
    static_ds(&v, "Types", &[1], &[ty], "")?;
    let pd = v.create_group("PointData")?;
    v.create_group("CellData")?;
    v.create_group("FieldData")?;
    let steps = v.create_group("Steps")?;
    attr(&steps, "NSteps", FRAMES as i64)?;
    let times: Vec<f64> = phases()
        .iter()
        .map(|a| {
            if mode.omega_d > 0.0 {
                a / mode.omega_d
            } else {
                *a
            }
        })
        .collect();
    static_ds(&steps, "Values", &[FRAMES], &times, "s")?;
    static_ds(&steps, "NumberOfParts", &[FRAMES], &[1_i64; FRAMES], "")?;
    let zeros = [0_i64; FRAMES];
    for name in [
        "PartOffsets",
        "PointOffsets",
        "CellOffsets",
        "ConnectivityIdOffsets",
    ] {
        static_ds(&steps, name, &[FRAMES], &zeros, "")?;
    }
    let pdo = steps.create_group("PointDataOffsets")?;
    steps.create_group("CellDataOffsets")?;
    steps.create_group("FieldDataOffsets")?;
    let mut disp = Vec::with_capacity(FRAMES * n * 3);
    let mut twist = Vec::new();
    for a in phases() {
        let (d, t) = frame_displacement(mode, a);
        disp.extend(d);
        if let Some(t) = t {
            twist.extend(t);
        }
    }
    let per_step: Vec<i64> = (0..FRAMES as i64).map(|k| k * n as i64).collect();
    static_ds(&pd, "displacement", &[FRAMES * n, 3], &disp, "")?;
    static_ds(&pdo, "displacement", &[FRAMES], &per_step, "")?;
    if !twist.is_empty() {
        static_ds(&pd, "twist", &[FRAMES * n], &twist, "rad")?;
        static_ds(&pdo, "twist", &[FRAMES], &per_step, "")?;
    }
    let ShapeArrays { scalars, re, im } = shape_arrays(mode);
    static_ds(&pd, "shape_re", &[n, 3], &re, "")?;
    static_ds(&pdo, "shape_re", &[FRAMES], &zeros, "")?;
    static_ds(&pd, "shape_im", &[n, 3], &im, "")?;
    static_ds(&pdo, "shape_im", &[FRAMES], &zeros, "")?;
    for (name, vals) in scalars {
        static_ds(&pd, &name, &[n], &vals, "")?;
        static_ds(&pdo, &name, &[FRAMES], &zeros, "")?;
    }
    Ok(())
}
