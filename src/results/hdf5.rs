//! HDF5 time series (`results.vtkhdf`, one file per run, cargo feature `hdf5`).
//!
//! The file holds plain datasets for scripts (`/time`, `/rotor`, `/contact`, `/stators`, with a
//! `unit` attribute each; the resolved scene and the units as JSON attributes of `/`) and a
//! transient VTKHDF 2 `UnstructuredGrid` group `/VTKHDF` that VTK's `vtkHDFReader` (ParaView,
//! `pyvista.read`) opens as a time series: the grid is written once and every step's point and
//! cell data are appended, addressed through `/VTKHDF/Steps` offsets. The rotor DOF vector
//! `/rotor/u` comes with its map `/rotor/node_dofs`: each node's [`super::RotorNodeDofs`]
//! `[u_x, u_y, θ_x, θ_y, u_z, θ_z]` as int64, −1 where absent. The layout is documented in
//! `docs/OUTPUTS.md`.
//!
//! Streaming: every time-dependent dataset is chunked with an unlimited first axis; frames are
//! buffered in blocks of about 256 KiB per dataset and appended block by block, so memory does
//! not grow with the run.

use super::hdf5_io::{attr, attr_str, close_on_exec, static_ds, vtkhdf_group, Column};
use super::hdf5_spin::SpinColumns;
use super::{Fields, FramePlan, FrameState, Layout, RunInfo};
use crate::error::{Error, Result};
use crate::model::Case;
use hdf5_metno as h5;
use std::path::{Path, PathBuf};

/// Name of the file, relative to the run's folder.
pub const FILE: &str = "results.vtkhdf";
pub use super::hdf5_io::VTKHDF_VERSION;
/// A column written only when its field is asked for.
type MaybeColumn = Option<Column<f64>>;
/// A point data column of `/VTKHDF/PointData`, its offsets column and what it holds.
type PointColumn = (Column<f64>, Column<i64>, PointField);
/// A cell data column of `/VTKHDF/CellData`, its offsets column and what it holds.
type CellColumn = (Column<f64>, Column<i64>, CellField);

/// The columns of the VTKHDF group and the plain groups.
struct Columns {
    time: Column<f64>,
    step: Column<i64>,
    rotor_u: Option<Column<f64>>,
    rotor_v: Option<Column<f64>>,
    pair_p: Option<Column<f64>>,
    pair_force: Option<Column<f64>>,
    pair_normal: Option<Column<f64>>,
    station_force: Option<Column<f64>>,
    // VTKHDF
    values: Column<f64>,
    zero_offsets: Vec<Column<i64>>,
    parts: Column<i64>,
    point_data: Vec<PointColumn>,
    cell_data: Vec<CellColumn>,
    static_cell_offsets: Vec<Column<i64>>,
    spin: SpinColumns,
}

#[derive(Clone, Copy)]
enum PointField {
    Displacement,
    Velocity,
    ContactForce,
    /// θ_z of the rotor points (rad), NaN on the stator points.
    Twist,
    /// dθ_z/dt of the rotor points (rad/s), NaN on the stator points.
    TwistRate,
    /// With wear: the worn depth (m) of the stators' contact nodes, 0 elsewhere.
    WornDepth,
}

#[derive(Clone, Copy)]
enum CellField {
    NormalForce,
    AxialForce,
    Stress,
    Strain,
}

/// An HDF5 time series being written.
pub struct Hdf5Series {
    path: PathBuf,
    name: String,
    file: h5::File,
    cols: Columns,
    fields: Fields,
    frames: usize,
    steps_group: h5::Group,
}

impl std::fmt::Debug for Hdf5Series {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Hdf5Series")
            .field("path", &self.path)
            .field("frames", &self.frames)
            .finish_non_exhaustive()
    }
}

/// Units and conventions stored as the `units` attribute (JSON).
pub const UNITS_JSON: &str = r#"{"length":"m","time":"s","force":"N","stress":"Pa","strain":"1","velocity":"m/s","angle":"rad","frequency":"rad/s","axes":"x horizontal, y vertical, rotor axis z; rotor spins counter-clockwise seen from +z","rotations":"theta_x, theta_y right-handed about x, y (theta_y = du_x/dz, theta_x = -du_y/dz); theta_z (twist) counter-clockwise seen from +z, the sense of the spin; rotor DOFs of each node: /rotor/node_dofs","contact":"normal n from the section centre to the stator node; normal force p >= 0 in compression; force on the stator node (n + mu a) p, on the rotor its opposite"}"#;

impl Hdf5Series {
    /// Creates `staging/prefix/results.vtkhdf` and writes everything that does not change
    /// with time (attributes, the grid, the pair and stator tables).
    ///
    /// # Errors
    /// [`Error::Output`] naming the file.
    pub fn create(
        staging: &Path,
        prefix: &str,
        layout: &Layout,
        case: &Case,
        plan: &FramePlan,
        info: &RunInfo,
    ) -> Result<Self> {
        let dir = staging.join(prefix);
        std::fs::create_dir_all(&dir).map_err(|e| Error::output(&dir, e))?;
        let path = dir.join(FILE);
        let r = Self::create_h5(&path, layout, case, plan, info);
        r.map(|(file, cols, steps_group)| Self {
            name: format!("{prefix}{FILE}"),
            path: path.clone(),
            file,
            cols,
            fields: plan.fields,
            frames: 0,
            steps_group,
        })
        .map_err(|e| Error::output(&path, format!("writing HDF5: {e}")))
    }

    fn create_h5(
        path: &Path,
        layout: &Layout,
        case: &Case,
        plan: &FramePlan,
        info: &RunInfo,
    ) -> h5::Result<(h5::File, Columns, h5::Group)> {
        let f = h5::File::create(path)?;
        close_on_exec(&f);
        let fl = plan.fields;
        root_attrs(&f, plan, info)?;
        let time = Column::new(&f, "time", 1, &[], "s")?;
        let step = Column::new(&f, "step", 1, &[], "")?;
        let (rotor_u, rotor_v) = rotor_group(&f, layout, case, fl)?;
        let [pair_p, pair_force, pair_normal, station_force] = contact_group(&f, layout, case, fl)?;
        stator_groups(&f, layout, case)?;
        // VTKHDF: the grid once, data per step.
        let v = vtkhdf_grid(&f, layout)?;
        let st = vtkhdf_steps(&v, layout, fl)?;
        let spin = SpinColumns::new(&f, &v, &st.group)?;
        Ok((
            f,
            Columns {
                time,
                step,
                rotor_u,
                rotor_v,
                pair_p,
                pair_force,
                pair_normal,
                station_force,
                values: st.values,
                zero_offsets: st.zero_offsets,
                parts: st.parts,
                point_data: st.point_data,
                cell_data: st.cell_data,
                static_cell_offsets: st.static_cell_offsets,
                spin,
            },
            st.group,
        ))
    }

    fn write_h5(&mut self, layout: &Layout, st: &FrameState) -> h5::Result<()> {
        let c = &mut self.cols;
        let k = self.frames as i64;
        c.time.push([st.t])?;
        c.step.push([st.step as i64])?;
        if let Some(col) = &mut c.rotor_u {
            col.push(st.rotor_u.iter().copied())?;
        }
        if let Some(col) = &mut c.rotor_v {
            col.push(st.rotor_v.iter().copied())?;
        }
        if let Some(col) = &mut c.pair_p {
            col.push(st.pair_p.iter().copied())?;
        }
        if let Some(col) = &mut c.pair_force {
            col.push(st.pair_force.iter().flatten().copied())?;
        }
        if let Some(col) = &mut c.pair_normal {
            col.push(st.pair_normal.iter().flatten().copied())?;
        }
        if let Some(col) = &mut c.station_force {
            col.push(st.station_force.iter().flatten().copied())?;
        }
        c.values.push([st.t])?;
        c.parts.push([1])?;
        for z in &mut c.zero_offsets {
            z.push([0])?;
        }
        let npts = layout.num_points() as i64;
        for (data, off, field) in &mut c.point_data {
            match field {
                PointField::Displacement => data.push(st.displacement.iter().flatten().copied())?,
                PointField::Velocity => data.push(st.velocity.iter().flatten().copied())?,
                PointField::ContactForce => {
                    data.push(st.contact_force.iter().flatten().copied())?
                }
                PointField::Twist => data.push(layout.rotor_point_values(&st.rotor_twist))?,
                PointField::TwistRate => {
                    data.push(layout.rotor_point_values(&st.rotor_twist_rate))?
                }
                PointField::WornDepth => {
                    let depth = st.worn_depth.as_deref().unwrap_or_default();
                    data.push(depth.iter().copied())?
                }
            }
            off.push([k * npts])?;
        }
        let nc = layout.grid.num_cells() as i64;
        let body = layout.body_cells;
        for (data, off, field) in &mut c.cell_data {
            match field {
                CellField::NormalForce => {
                    data.push(std::iter::repeat_n(0.0, body).chain(st.pair_p.iter().copied()))?
                }
                CellField::AxialForce => data.push(st.axial_force.iter().copied())?,
                CellField::Stress => data.push(st.stress.iter().copied())?,
                CellField::Strain => data.push(st.strain.iter().copied())?,
            }
            off.push([k * nc])?;
        }
        for o in &mut c.static_cell_offsets {
            o.push([0])?;
        }
        c.spin.push(k, st)?;
        Ok(())
    }

    /// Appends one frame.
    ///
    /// # Errors
    /// [`Error::Output`] naming the file (e.g. the disk is full).
    pub fn write(&mut self, layout: &Layout, st: &FrameState, fields: &Fields) -> Result<()> {
        debug_assert_eq!(*fields, self.fields);
        self.write_h5(layout, st)
            .map_err(|e| Error::output(&self.path, format!("writing HDF5: {e}")))?;
        self.frames += 1;
        Ok(())
    }

    fn finish_h5(&mut self) -> h5::Result<()> {
        let c = &mut self.cols;
        c.time.flush()?;
        c.step.flush()?;
        for col in [
            &mut c.rotor_u,
            &mut c.rotor_v,
            &mut c.pair_p,
            &mut c.pair_force,
            &mut c.pair_normal,
            &mut c.station_force,
        ]
        .into_iter()
        .flatten()
        {
            col.flush()?;
        }
        c.values.flush()?;
        c.parts.flush()?;
        for z in c
            .zero_offsets
            .iter_mut()
            .chain(c.static_cell_offsets.iter_mut())
        {
            z.flush()?;
        }
        for (d, o, _) in &mut c.point_data {
            d.flush()?;
            o.flush()?;
        }
        for (d, o, _) in &mut c.cell_data {
            d.flush()?;
            o.flush()?;
        }
        c.spin.flush()?;
        self.steps_group
            .attr("NSteps")?
            .write_scalar(&(self.frames as i64))?;
        attr(&self.file, "frames", self.frames as i64)?;
        self.file.flush()?;
        Ok(())
    }

    /// Appends the buffered frames, records the number of steps and closes the file; returns
    /// its name relative to the staging folder.
    ///
    /// # Errors
    /// [`Error::Output`] naming the file.
    pub fn finish(mut self) -> Result<Vec<String>> {
        // The frames still buffered, for the error: the time column buffers the most frames.
        let pending = match (
            self.cols.step.first_buffered(),
            self.cols.time.first_buffered(),
        ) {
            (Some(step), Some(t)) => format!(
                "the frames buffered since step {step} (t = {t:.6e} s), {} of {} frames",
                self.cols.time.buffered_frames(),
                self.frames
            ),
            _ => format!("{} frames", self.frames),
        };
        self.finish_h5().map_err(|e| {
            Error::output(
                &self.path,
                format!("writing HDF5 at the end of the run ({pending}): {e}"),
            )
        })?;
        let name = self.name.clone();
        drop(self);
        Ok(vec![name])
    }
}

/// The attributes of `/`: format, version, the scene and units as JSON, the run and the
/// frame plan.
fn root_attrs(f: &h5::File, plan: &FramePlan, info: &RunInfo) -> h5::Result<()> {
    // 2: `/rotor/node_dofs` is the 6-column DOF map (1: `[u_x, u_y]` only).
    attr_str(f, "format", "rubsim results 2 (docs/OUTPUTS.md)")?;
    attr_str(f, "rubsim_version", env!("CARGO_PKG_VERSION"))?;
    attr_str(f, "scene", &info.scene_json)?;
    attr_str(f, "units", UNITS_JSON)?;
    attr_str(f, "integrator", info.integrator)?;
    attr(f, "speed_ratio", info.speed_ratio)?;
    attr(f, "omega_rad_s", info.omega)?;
    attr(f, "dt_s", info.plan.dt)?;
    attr(f, "steps_per_rev", info.plan.steps_per_rev as i64)?;
    attr(f, "steps", info.plan.steps as i64)?;
    attr(f, "every", plan.every as i64)?;
    attr(f, "first_step", plan.first as i64)?;
    attr(f, "last_step", plan.last as i64)?;
    Ok(())
}

/// `/rotor`: the DOF map and node positions; the columns `u` and `v` when asked for.
fn rotor_group(
    f: &h5::File,
    layout: &Layout,
    case: &Case,
    fl: Fields,
) -> h5::Result<(MaybeColumn, MaybeColumn)> {
    let rg = f.create_group("rotor")?;
    // Every DOF of each node, [u_x, u_y, θ_x, θ_y, u_z, θ_z], −1 where absent.
    let nn = layout.rotor_dofs.len();
    let nd: Vec<i64> = layout
        .rotor_dofs
        .iter()
        .flatten()
        .map(|d| d.map_or(-1, |d| d as i64))
        .collect();
    let ds = static_ds(&rg, "node_dofs", &[nn, 6], &nd, "")?;
    attr_str(&ds, "columns", &super::ROTOR_DOF_NAMES.join(" "))?;
    let z: Vec<f64> = layout.grid.points[layout.rotor_first_point..]
        .iter()
        .map(|p| p[2])
        .collect();
    static_ds(&rg, "node_z", &[nn], &z, "m")?;
    attr(&rg, "first_point", layout.rotor_first_point as i64)?;
    let ndof = case.rotor.ndof;
    // Translations in m, rotations (θ_x, θ_y, θ_z columns of node_dofs) in rad.
    let rotor_u = fl
        .displacement
        .then(|| Column::new(&rg, "u", 1, &[ndof], "m, rad"))
        .transpose()?;
    let rotor_v = fl
        .velocity
        .then(|| Column::new(&rg, "v", 1, &[ndof], "m/s, rad/s"))
        .transpose()?;
    Ok((rotor_u, rotor_v))
}

/// `/contact`: the pair table and station names; the columns `p`, `force`, `normal` and
/// `station_force` when contact forces are asked for.
fn contact_group(
    f: &h5::File,
    layout: &Layout,
    case: &Case,
    fl: Fields,
) -> h5::Result<[MaybeColumn; 4]> {
    let cg = f.create_group("contact")?;
    let np = layout.pairs.len();
    let pairs: Vec<i64> = layout
        .pairs
        .iter()
        .flat_map(|p| [p.station as i64, p.stator as i64, p.node as i64])
        .collect();
    static_ds(&cg, "pairs", &[np, 3], &pairs, "")?;
    let names = |v: &[String]| v.join("\n");
    attr_str(&cg, "station_names", &names(&layout.station_names))?;
    let nst = case.stations.len();
    Ok(if fl.contact_force {
        [
            Some(Column::new(&cg, "p", 1, &[np], "N")?),
            Some(Column::new(&cg, "force", 1, &[np, 2], "N")?),
            Some(Column::new(&cg, "normal", 1, &[np, 2], "1")?),
            Some(Column::new(&cg, "station_force", 1, &[nst, 2], "N")?),
        ]
    } else {
        [None, None, None, None]
    })
}

/// `/stators/<k>`: each stator's name, station, points, element cells, node DOFs, mesh.
fn stator_groups(f: &h5::File, layout: &Layout, case: &Case) -> h5::Result<()> {
    let sg = f.create_group("stators")?;
    for (k, s) in case.stators.iter().enumerate() {
        let g = sg.create_group(&k.to_string())?;
        attr_str(&g, "name", &s.name)?;
        attr(&g, "station", s.station as i64)?;
        attr(&g, "first_point", layout.stator_first_point[k] as i64)?;
        attr(&g, "num_points", layout.stator_num_points[k] as i64)?;
        attr(&g, "num_nodes", s.nodes.len() as i64)?;
        let cells: Vec<i64> = layout.element_cells[k]
            .iter()
            .map(|c| c.map_or(-1, |c| c as i64))
            .collect();
        static_ds(&g, "element_cells", &[cells.len()], &cells, "")?;
        let dofs: Vec<i64> = s
            .node_dofs
            .iter()
            .flat_map(|d| d.map(|x| x.map_or(-1, |x| x as i64)))
            .collect();
        static_ds(&g, "node_dofs", &[s.nodes.len(), 2], &dofs, "")?;
        if let Some(md) = &s.mesh {
            // Absolute when it can be resolved, so that the file can be found from anywhere.
            let mf = std::fs::canonicalize(&md.mesh_file).unwrap_or(md.mesh_file.clone());
            attr_str(&g, "mesh_file", &mf.to_string_lossy())?;
            attr(&g, "dim", md.dim as i64)?;
        }
        // 3-D meshed stators: the free DOF of u_z of every node.
        if let Some(md) = s.mesh.as_ref().filter(|m| !m.axial_dofs.is_empty()) {
            let ax: Vec<i64> = md
                .axial_dofs
                .iter()
                .map(|d| d.map_or(-1, |x| x as i64))
                .collect();
            static_ds(&g, "axial_dofs", &[ax.len()], &ax, "")?;
        }
    }
    Ok(())
}

/// `/VTKHDF` with its version, type and the grid (points, connectivity, offsets, types).
fn vtkhdf_grid(f: &h5::File, layout: &Layout) -> h5::Result<h5::Group> {
    let v = vtkhdf_group(f)?;
    let g = &layout.grid;
    let npts = g.points.len();
    let nc = g.num_cells();
    static_ds(&v, "NumberOfPoints", &[1], &[npts as i64], "")?;
    static_ds(&v, "NumberOfCells", &[1], &[nc as i64], "")?;
    static_ds(
        &v,
        "NumberOfConnectivityIds",
        &[1],
        &[g.connectivity.len() as i64],
        "",
    )?;
    let pts: Vec<f64> = g.points.iter().flatten().copied().collect();
    static_ds(&v, "Points", &[npts, 3], &pts, "m")?;
    static_ds(
        &v,
        "Connectivity",
        &[g.connectivity.len()],
        &g.connectivity,
        "",
    )?;
    static_ds(&v, "Offsets", &[g.offsets.len()], &g.offsets, "")?;
    let types: Vec<u8> = g.types.iter().map(|t| *t as u8).collect();
    static_ds(&v, "Types", &[nc], &types, "")?;
    Ok(v)
}

/// The time-dependent part of `/VTKHDF`: `Steps` and its offsets, the point and cell data.
struct StepColumns {
    group: h5::Group,
    values: Column<f64>,
    parts: Column<i64>,
    zero_offsets: Vec<Column<i64>>,
    point_data: Vec<PointColumn>,
    cell_data: Vec<CellColumn>,
    static_cell_offsets: Vec<Column<i64>>,
}

/// Creates the data groups and `Steps` of `/VTKHDF`, then the point and cell data columns
/// the fields ask for, and the cell arrays that do not change.
fn vtkhdf_steps(v: &h5::Group, layout: &Layout, fl: Fields) -> h5::Result<StepColumns> {
    let pd = v.create_group("PointData")?;
    let cd = v.create_group("CellData")?;
    let steps = v.create_group("Steps")?;
    attr(&steps, "NSteps", 0_i64)?;
    let values = Column::new(&steps, "Values", 1, &[], "s")?;
    let parts = Column::new(&steps, "NumberOfParts", 1, &[], "")?;
    let zero_offsets = [
        "PartOffsets",
        "PointOffsets",
        "CellOffsets",
        "ConnectivityIdOffsets",
    ]
    .iter()
    .map(|n| Column::new(&steps, n, 1, &[], ""))
    .collect::<h5::Result<Vec<_>>>()?;
    let pdo = steps.create_group("PointDataOffsets")?;
    let cdo = steps.create_group("CellDataOffsets")?;
    let point_data = point_columns(&pd, &pdo, layout, fl)?;
    let (cell_data, static_cell_offsets) = cell_columns(&cd, &cdo, layout, fl)?;
    Ok(StepColumns {
        group: steps,
        values,
        parts,
        zero_offsets,
        point_data,
        cell_data,
        static_cell_offsets,
    })
}

/// The point data columns (and their offsets) of the fields asked for.
fn point_columns(
    pd: &h5::Group,
    pdo: &h5::Group,
    layout: &Layout,
    fl: Fields,
) -> h5::Result<Vec<PointColumn>> {
    let npts = layout.grid.points.len();
    let mut point_data = Vec::new();
    let torsion = layout.rotor_has_torsion();
    for (on, name, field, unit, inner) in [
        (
            fl.displacement,
            "displacement",
            PointField::Displacement,
            "m",
            &[3][..],
        ),
        (fl.velocity, "velocity", PointField::Velocity, "m/s", &[3]),
        (
            fl.contact_force,
            "contact_force",
            PointField::ContactForce,
            "N",
            &[3],
        ),
        (
            fl.displacement && torsion,
            "twist",
            PointField::Twist,
            "rad",
            &[],
        ),
        (
            fl.velocity && torsion,
            "twist_rate",
            PointField::TwistRate,
            "rad/s",
            &[],
        ),
        (layout.wear, "worn_depth", PointField::WornDepth, "m", &[]),
    ] {
        if on {
            point_data.push((
                Column::new(pd, name, npts, inner, unit)?,
                Column::new(pdo, name, 1, &[], "")?,
                field,
            ));
        }
    }
    Ok(point_data)
}

/// The cell data columns (and their offsets) of the fields asked for, then the static cell
/// arrays `part`, `stator`, `index` (written once, every step pointing at offset 0).
fn cell_columns(
    cd: &h5::Group,
    cdo: &h5::Group,
    layout: &Layout,
    fl: Fields,
) -> h5::Result<(Vec<CellColumn>, Vec<Column<i64>>)> {
    let g = &layout.grid;
    let nc = g.num_cells();
    let mut cell_data = Vec::new();
    let mut cf = Vec::new();
    if fl.contact_force {
        cf.push(("normal_force", CellField::NormalForce, "N"));
    }
    if fl.stress {
        cf.push(("axial_force", CellField::AxialForce, "N"));
        cf.push(("stress", CellField::Stress, "Pa"));
        cf.push(("strain", CellField::Strain, "1"));
    }
    for (name, field, unit) in cf {
        cell_data.push((
            Column::new(cd, name, nc, &[], unit)?,
            Column::new(cdo, name, 1, &[], "")?,
            field,
        ));
    }
    // Cell arrays that do not change: written once, every step points at offset 0.
    static_ds(cd, "part", &[nc], &g.part, "")?;
    static_ds(cd, "stator", &[nc], &g.stator, "")?;
    static_ds(cd, "index", &[nc], &g.index, "")?;
    let static_cell_offsets = ["part", "stator", "index"]
        .iter()
        .map(|n| Column::new(cdo, n, 1, &[], ""))
        .collect::<h5::Result<Vec<_>>>()?;
    Ok((cell_data, static_cell_offsets))
}
