//! VTK XML time series: one `.vtu` unstructured grid per frame (`vtk/frame_NNNNNN.vtu`,
//! written with `vtkio`, binary inline data) and a `.pvd` collection (`results.pvd`) listing
//! them with their times (s). Each frame is the [`Layout`]'s grid with only the pairs in
//! contact, and with the contact point of each ring at its position of that instant
//! ([`super::RingSlot`]). The `.pvd` is streamed too: its header is written when the run
//! starts, one `DataSet` line per frame, the footer at [`VtkSeries::finish`].
//!
//! Grid, arrays and units: [`super`] and `docs/OUTPUTS.md`. Rotors with torsional DOFs add the
//! point arrays `twist` (θ_z, rad) and `twist_rate` (rad/s), NaN on the stator points.

use super::{part, Fields, FrameState, Layout, RunInfo};
use crate::error::{Error, Result};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use vtkio::model::{
    Attribute, Attributes, ByteOrder, Cells, DataSet, IOBuffer, UnstructuredGridPiece, Version,
    VertexNumbers, Vtk,
};

/// Name of the collection, relative to the run's folder.
pub const PVD: &str = "results.pvd";
/// Folder of the frames, relative to the run's folder.
pub const FRAME_DIR: &str = "vtk";

/// Name of frame `i`, relative to the run's folder.
pub fn frame_name(i: usize) -> String {
    format!("{FRAME_DIR}/frame_{i:06}.vtu")
}

/// A `.pvd` + `.vtu` series being written.
#[derive(Debug)]
pub struct VtkSeries {
    dir: PathBuf,
    prefix: String,
    pvd: BufWriter<File>,
    pvd_path: PathBuf,
    frames: usize,
}

fn io_err(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::output(path, e)
}

impl VtkSeries {
    /// Creates `staging/prefix/results.pvd` (header written) and the frame folder.
    ///
    /// # Errors
    /// [`Error::Output`] naming the file or folder that cannot be created.
    pub fn create(staging: &Path, prefix: &str, info: &RunInfo) -> Result<Self> {
        let dir = staging.join(prefix);
        let frames = dir.join(FRAME_DIR);
        std::fs::create_dir_all(&frames).map_err(|e| io_err(&frames, e))?;
        let pvd_path = dir.join(PVD);
        let f = File::create(&pvd_path).map_err(|e| io_err(&pvd_path, e))?;
        let mut pvd = BufWriter::new(f);
        write!(
            pvd,
            "<?xml version=\"1.0\"?>\n<!-- rubsim {}: ω/ω_n = {}, ω = {} rad/s, Δt = {:e} s, {} integrator; times in s -->\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
            env!("CARGO_PKG_VERSION"),
            info.speed_ratio,
            info.omega,
            info.plan.dt,
            info.integrator
        )
        .map_err(|e| io_err(&pvd_path, e))?;
        Ok(Self {
            dir,
            prefix: prefix.to_string(),
            pvd,
            pvd_path,
            frames: 0,
        })
    }

    /// Writes one frame: the `.vtu` file and its line in the `.pvd`.
    ///
    /// # Errors
    /// [`Error::Output`] naming the file.
    pub fn write(&mut self, layout: &Layout, st: &FrameState, fields: &Fields) -> Result<()> {
        let name = frame_name(self.frames);
        let path = self.dir.join(&name);
        // Serialised in memory first, so that a write error (e.g. a full disk) is reported as
        // the I/O error it is.
        let mut xml = Vec::new();
        frame_vtk(layout, st, fields)
            .write_xml(&mut xml)
            .map_err(|e| io_err(&path, e))?;
        insert_field_data(&mut xml, st).map_err(|e| io_err(&path, e))?;
        std::fs::write(&path, &xml).map_err(|e| io_err(&path, e))?;
        writeln!(
            self.pvd,
            "    <DataSet timestep=\"{:.17e}\" group=\"\" part=\"0\" file=\"{name}\"/>",
            st.t
        )
        .map_err(|e| io_err(&self.pvd_path, e))?;
        self.frames += 1;
        Ok(())
    }

    /// Number of frames written so far.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// Writes the `.pvd` footer and closes it; returns the files written, relative to the
    /// staging folder.
    ///
    /// # Errors
    /// [`Error::Output`] naming the `.pvd`.
    pub fn finish(mut self) -> Result<Vec<String>> {
        self.pvd
            .write_all(b"  </Collection>\n</VTKFile>\n")
            .and_then(|_| self.pvd.flush())
            .map_err(|e| io_err(&self.pvd_path, e))?;
        let mut names = Vec::with_capacity(self.frames + 1);
        names.push(format!("{}{PVD}", self.prefix));
        names.extend((0..self.frames).map(|i| format!("{}{}", self.prefix, frame_name(i))));
        Ok(names)
    }
}

/// Names of the frame's field data (one tuple each), the values of [`field_values`]:
/// `TimeValue` the time t (s; the name VTK's readers take as a dataset's time), `omega` Ω
/// (rad/s), `speed_ratio` Ω/ω_n, `phi` the spin angle φ (rad, φ(0) = 0), `omega_dot` Ω̇
/// (rad/s²); see [`FrameState`].
pub const FIELD_DATA: [&str; 5] = ["TimeValue", "omega", "speed_ratio", "phi", "omega_dot"];

/// The values of [`FIELD_DATA`] at a frame.
pub fn field_values(st: &FrameState) -> [f64; 5] {
    [st.t, st.omega, st.speed_ratio, st.phi, st.omega_dot]
}

/// Inserts a `<FieldData>` block with [`field_values`] (ASCII, 17 significant digits) at the
/// start of the `.vtu`'s `UnstructuredGrid` element, where VTK reads a dataset's field data
/// (`vtkio` writes none).
fn insert_field_data(xml: &mut Vec<u8>, st: &FrameState) -> std::result::Result<(), String> {
    const TAG: &[u8] = b"<UnstructuredGrid>";
    let at = xml
        .windows(TAG.len())
        .position(|w| w == TAG)
        .ok_or("the serialised frame has no <UnstructuredGrid> element")?
        + TAG.len();
    let mut block = String::from("<FieldData>");
    for (name, v) in FIELD_DATA.iter().zip(field_values(st)) {
        block.push_str(&format!(
            "<DataArray type=\"Float64\" Name=\"{name}\" NumberOfTuples=\"1\" format=\"ascii\">{v:.17e}</DataArray>"
        ));
    }
    block.push_str("</FieldData>");
    xml.splice(at..at, block.into_bytes());
    Ok(())
}

fn flat3(v: &[[f64; 3]]) -> Vec<f64> {
    v.iter().flatten().copied().collect()
}

fn vectors(name: &str, v: Vec<f64>) -> Attribute {
    Attribute::vectors(name).with_data(IOBuffer::F64(v))
}

fn scalars(name: &str, v: IOBuffer) -> Attribute {
    Attribute::scalars(name, 1).with_data(v)
}

/// The grid of one frame: stator elements, rotor, and the pairs in contact.
fn frame_vtk(layout: &Layout, st: &FrameState, fields: &Fields) -> Vtk {
    let g = &layout.grid;
    let active: Vec<usize> = (0..layout.pairs.len())
        .filter(|&i| st.pair_p[i] > 0.0)
        .collect();
    let cells: Vec<usize> = (0..layout.body_cells)
        .chain(active.iter().map(|i| layout.body_cells + i))
        .collect();
    let mut connectivity = Vec::new();
    let mut offsets = Vec::with_capacity(cells.len());
    for &c in &cells {
        connectivity.extend(g.cell(c).iter().map(|p| *p as u64));
        offsets.push(connectivity.len() as u64);
    }
    let types = cells.iter().map(|&c| g.types[c]).collect();
    // Undeformed positions; a ring's contact point follows this frame's contact direction.
    let mut points = flat3(&g.points);
    for (ring, p) in layout.rings.iter().zip(&st.ring_contact) {
        points[3 * ring.contact_point..3 * ring.contact_point + 3].copy_from_slice(p);
    }
    let mut cell = vec![
        scalars(
            "part",
            IOBuffer::U8(cells.iter().map(|&c| g.part[c]).collect()),
        ),
        scalars(
            "stator",
            IOBuffer::I32(cells.iter().map(|&c| g.stator[c]).collect()),
        ),
        scalars(
            "index",
            IOBuffer::I64(cells.iter().map(|&c| g.index[c]).collect()),
        ),
    ];
    let point = point_data(layout, st, fields);
    if fields.contact_force {
        contact_cells(layout, st, &cells, &mut cell);
    }
    if fields.stress {
        for (name, v) in [
            ("axial_force", &st.axial_force),
            ("stress", &st.stress),
            ("strain", &st.strain),
        ] {
            cell.push(scalars(
                name,
                IOBuffer::F64(cells.iter().map(|&c| v[c]).collect()),
            ));
        }
    }
    Vtk {
        version: Version::new_xml(1, 0),
        title: format!("rubsim frame at t = {} s (step {})", st.t, st.step),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::inline(UnstructuredGridPiece {
            points: IOBuffer::F64(points),
            cells: Cells {
                cell_verts: VertexNumbers::XML {
                    connectivity,
                    offsets,
                },
                types,
            },
            data: Attributes { point, cell },
        }),
    }
}

/// A frame's point data as `fields` asks: displacement, velocity and contact force (vectors),
/// and on a rotor with θ_z its `twist` (rad) and `twist_rate` (rad/s), NaN on the stator points;
/// with wear, always, `worn_depth` (m).
fn point_data(layout: &Layout, st: &FrameState, fields: &Fields) -> Vec<Attribute> {
    let mut point = Vec::new();
    // Rotors with θ_z: `twist` (rad) and `twist_rate` (rad/s) on the rotor points, NaN on
    // the stator points.
    let torsion = layout.rotor_has_torsion();
    if fields.displacement {
        point.push(vectors("displacement", flat3(&st.displacement)));
        if torsion {
            let v = layout.rotor_point_values(&st.rotor_twist).collect();
            point.push(scalars("twist", IOBuffer::F64(v)));
        }
    }
    if fields.velocity {
        point.push(vectors("velocity", flat3(&st.velocity)));
        if torsion {
            let v = layout.rotor_point_values(&st.rotor_twist_rate).collect();
            point.push(scalars("twist_rate", IOBuffer::F64(v)));
        }
    }
    if fields.contact_force {
        point.push(vectors("contact_force", flat3(&st.contact_force)));
    }
    if let Some(depth) = &st.worn_depth {
        // With wear, always: the worn depth (m) of the stators' contact nodes.
        point.push(scalars("worn_depth", IOBuffer::F64(depth.clone())));
    }
    point
}

/// The contact cell data of a frame's `cells`: each pair line's normal force (N) and force on
/// the stator (vector), 0 on the other cells.
fn contact_cells(layout: &Layout, st: &FrameState, cells: &[usize], cell: &mut Vec<Attribute>) {
    let g = &layout.grid;
    let pair = |c: usize| {
        (g.part[c] == part::CONTACT)
            .then(|| (c - layout.body_cells, st.pair_force[c - layout.body_cells]))
    };
    cell.push(scalars(
        "normal_force",
        IOBuffer::F64(
            cells
                .iter()
                .map(|&c| pair(c).map_or(0.0, |(i, _)| st.pair_p[i]))
                .collect(),
        ),
    ));
    cell.push(vectors(
        "pair_force",
        cells
            .iter()
            .flat_map(|&c| {
                let f = pair(c).map_or([0.0; 2], |(_, f)| f);
                [f[0], f[1], 0.0]
            })
            .collect(),
    ));
}
