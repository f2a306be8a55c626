//! Mode shapes for ParaView and pyvista (`rubsim modal`): per mode the rotor as a polyline of
//! its nodes carrying the complex shape, and an animatable series of the shaft line over one
//! period of the mode — in VTK XML (`modes/mode_NN.vtu`, `modes/mode_NN.pvd` with
//! `modes/mode_NN/frame_KKK.vtu`) and in HDF5 (`modes/mode_NN.vtkhdf`, [`super::mode_hdf5`]).
//! Layout and arrays: `docs/OUTPUTS.md`, "Mode shapes".
//!
//! Points are the rotor nodes on the axis, `(0, 0, z)` (m), as in the time series. The shape is
//! the mode's normalised one ([`crate::linear::modes::Mode`]: largest entry 1, rotations
//! in rad per unit of it). Frame `k` of `N` ([`FRAMES`]) is the real shape at phase
//! `α_k = 2πk/N`, `Re(φ e^{iα_k})`, as the point vector `displacement` (warp by it to see the
//! line); its time is `α_k/ω_d` (s), so the series lasts one period of the damped mode,
//! without its decay.

use crate::error::{Error, Result};
use crate::linear::mode_shape::{at_phase, ellipses, node_shape, RotorLine};
use crate::linear::modes::Mode;
use num_complex::Complex64;
use std::f64::consts::TAU;
use std::path::Path;
use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataSet, IOBuffer, UnstructuredGridPiece,
    Version, VertexNumbers, Vtk,
};

/// Frames of the animated series: one period of the mode.
pub const FRAMES: usize = 36;

/// Base name of mode `index` (0-based): `mode_01`, `mode_02`, …
pub fn mode_name(index: usize) -> String {
    format!("mode_{:02}", index + 1)
}

/// The static point arrays of a mode, one value (or 3-vector) per node.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeArrays {
    /// `(name, values)`: the real and imaginary parts of `u_x`, `u_y`, `θ_x`, `θ_y` (and of
    /// `u_z`, `θ_z` when the rotor has them), then the whirl ellipse's `major` and signed
    /// `minor` semi-axes (positive forward).
    pub scalars: Vec<(String, Vec<f64>)>,
    /// `shape_re`: `[Re φ_x, Re φ_y, Re φ_z]` per node, flattened.
    pub re: Vec<f64>,
    /// `shape_im`: the imaginary parts, likewise.
    pub im: Vec<f64>,
}

/// The [`ShapeArrays`] of a mode.
pub fn shape_arrays(mode: &Mode) -> ShapeArrays {
    let shape = node_shape(mode);
    let mut scalars = Vec::new();
    for (c, name) in ["ux", "uy", "theta_x", "theta_y"].iter().enumerate() {
        scalars.push((
            format!("{name}_re"),
            shape.iter().map(|p| p[c].re).collect(),
        ));
        scalars.push((
            format!("{name}_im"),
            shape.iter().map(|p| p[c].im).collect(),
        ));
    }
    for (name, v) in [("uz", &mode.shape_axial), ("theta_z", &mode.shape_torsion)] {
        if !v.is_empty() {
            scalars.push((format!("{name}_re"), v.iter().map(|c| c.re).collect()));
            scalars.push((format!("{name}_im"), v.iter().map(|c| c.im).collect()));
        }
    }
    let el = ellipses(&shape);
    scalars.push(("major".into(), el.iter().map(|e| e.major).collect()));
    scalars.push(("minor".into(), el.iter().map(|e| e.minor).collect()));
    let axial = |i: usize| {
        mode.shape_axial
            .get(i)
            .copied()
            .unwrap_or(Complex64::new(0.0, 0.0))
    };
    let vec3 = |f: fn(Complex64) -> f64| -> Vec<f64> {
        shape
            .iter()
            .enumerate()
            .flat_map(|(i, p)| [f(p[0]), f(p[1]), f(axial(i))])
            .collect()
    };
    ShapeArrays {
        scalars,
        re: vec3(|c| c.re),
        im: vec3(|c| c.im),
    }
}

/// The displacement `[u_x, u_y, u_z]` of every node at phase `alpha` (and θ_z when the rotor
/// has it): `Re(φ e^{iα})`.
pub fn frame_displacement(mode: &Mode, alpha: f64) -> (Vec<f64>, Option<Vec<f64>>) {
    let e = Complex64::from_polar(1.0, alpha);
    let real = at_phase(&node_shape(mode), alpha);
    let d = real
        .iter()
        .enumerate()
        .flat_map(|(i, p)| {
            let uz = mode.shape_axial.get(i).map_or(0.0, |c| (c * e).re);
            [p[0], p[1], uz]
        })
        .collect();
    let twist = (!mode.shape_torsion.is_empty())
        .then(|| mode.shape_torsion.iter().map(|c| (c * e).re).collect());
    (d, twist)
}

/// The phases of the frames, `2πk/N`.
pub fn phases() -> Vec<f64> {
    (0..FRAMES)
        .map(|k| TAU * k as f64 / FRAMES as f64)
        .collect()
}

/// The `.vtu` of one mode: the polyline with the static arrays, plus `displacement` (and
/// `twist`) at `frame` phase when given.
fn mode_vtk(line: &RotorLine, mode: &Mode, title: String, frame: Option<f64>) -> Vtk {
    let n = line.z.len();
    let points: Vec<f64> = line.z.iter().flat_map(|z| [0.0, 0.0, *z]).collect();
    let ShapeArrays { scalars, re, im } = shape_arrays(mode);
    let mut point: Vec<Attribute> = Vec::new();
    if let Some(alpha) = frame {
        let (d, twist) = frame_displacement(mode, alpha);
        point.push(Attribute::vectors("displacement").with_data(IOBuffer::F64(d)));
        if let Some(t) = twist {
            point.push(Attribute::scalars("twist", 1).with_data(IOBuffer::F64(t)));
        }
    }
    point.push(Attribute::vectors("shape_re").with_data(IOBuffer::F64(re)));
    point.push(Attribute::vectors("shape_im").with_data(IOBuffer::F64(im)));
    for (name, v) in scalars {
        point.push(Attribute::scalars(name, 1).with_data(IOBuffer::F64(v)));
    }
    let cell_type = if n > 1 {
        CellType::PolyLine
    } else {
        CellType::Vertex
    };
    Vtk {
        version: Version::new_xml(1, 0),
        title,
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::inline(UnstructuredGridPiece {
            points: IOBuffer::F64(points),
            cells: Cells {
                cell_verts: VertexNumbers::XML {
                    connectivity: (0..n as u64).collect(),
                    offsets: vec![n as u64],
                },
                types: vec![cell_type],
            },
            data: Attributes {
                point,
                cell: Vec::new(),
            },
        }),
    }
}

fn xml(vtk: Vtk, name: &str) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    vtk.write_xml(&mut out)
        .map_err(|e| Error::output(Path::new(name), e))?;
    Ok(out)
}

/// The VTK files of mode `index` as `(name relative to the output directory, bytes)`:
/// `modes/mode_NN.vtu`, `modes/mode_NN.pvd` and its [`FRAMES`] frames
/// `modes/mode_NN/frame_KKK.vtu`.
///
/// # Errors
/// [`Error::Output`] when vtkio cannot serialise a grid.
pub fn vtk_files(line: &RotorLine, mode: &Mode, index: usize) -> Result<Vec<(String, Vec<u8>)>> {
    let base = mode_name(index);
    let what = format!(
        "rubsim mode {}: ω_d = {} rad/s, ζ = {}, {}",
        index + 1,
        mode.omega_d,
        mode.damping_ratio,
        mode.label()
    );
    let mut files = vec![(
        format!("modes/{base}.vtu"),
        xml(mode_vtk(line, mode, what.clone(), None), &base)?,
    )];
    let mut pvd = format!(
        "<?xml version=\"1.0\"?>\n<!-- {what}; frames at phase 2πk/{FRAMES}, times α/ω_d in s -->\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n"
    );
    for (k, alpha) in phases().into_iter().enumerate() {
        let rel = format!("{base}/frame_{k:03}.vtu");
        let t = if mode.omega_d > 0.0 {
            alpha / mode.omega_d
        } else {
            alpha
        };
        pvd.push_str(&format!(
            "    <DataSet timestep=\"{t:.17e}\" group=\"\" part=\"0\" file=\"{rel}\"/>\n"
        ));
        let title = format!("{what}; phase {alpha} rad");
        files.push((
            format!("modes/{rel}"),
            xml(mode_vtk(line, mode, title, Some(alpha)), &rel)?,
        ));
    }
    pvd.push_str("  </Collection>\n</VTKFile>\n");
    files.push((format!("modes/{base}.pvd"), pvd.into_bytes()));
    Ok(files)
}
