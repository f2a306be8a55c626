//! Results written by a run, read back: one speed through the output directory as the CLI
//! writes it, the `.vtu` frames and `.pvd` index with `vtkio`, the HDF5 datasets with
//! `hdf5-metno`.

use super::{data, file_model, settings};
use rubsim::analysis::{Keep, SpeedResults};
use rubsim::output::OutDir;
use rubsim::results;
use std::path::{Path, PathBuf};
use vtkio::model::{Attribute, CellType, DataSet, IOBuffer, Piece, VertexNumbers, Vtk};

/// Runs one speed with the scene's time series into `dir` (through the output directory's
/// staging folder and commit, as the CLI does, with a stand-in `summary.json`); returns the
/// committed series files (the summary left out).
pub fn run(name: &str, sets: &[&str], dir: &Path) -> (SpeedResults, Vec<PathBuf>) {
    run_scene(&data(name), sets, None, dir)
}

/// [`run`] of the scene file `path` at ω/ω_n = `speed` (default: the scene's `run.speed_ratio`;
/// give it for a sweep scene, as `rubsim run --speed` does).
pub fn run_scene(
    path: &Path,
    sets: &[&str],
    speed: Option<f64>,
    dir: &Path,
) -> (SpeedResults, Vec<PathBuf>) {
    let (ls, model) = file_model(path, sets);
    let s = settings(&ls);
    let mut out = OutDir::prepare(dir).expect("prepare");
    let staging = out.staging_dir().to_path_buf();
    let speed = speed.unwrap_or_else(|| ls.scene.run.speed_ratio.expect("single speed"));
    let prep = rubsim::analysis::prepare(&model, &s.request(speed)).expect("prepare");
    let mut sink = results::ResultsSink::for_output(
        &model,
        &prep,
        &ls.scene.output,
        &serde_json::to_string(&ls.scene).unwrap(),
        &staging,
        "",
    )
    .expect("run");
    let mut sinks: Vec<&mut dyn rubsim::time::FrameSink> =
        sink.iter_mut().map(|w| w as _).collect();
    let r = prep
        .run(
            Keep {
                orbit: true,
                ..Keep::default()
            },
            &mut sinks,
        )
        .expect("run");
    let names = sink.map_or(Ok(Vec::new()), |w| w.finish()).expect("run");
    for n in &names {
        out.adopt(n).expect("adopt");
    }
    // The run's marker: a directory's results are complete only with a `summary.json`.
    out.write("summary.json", b"{}").expect("summary");
    let files = out.commit().expect("commit");
    (
        r,
        files
            .into_iter()
            .filter(|p| !p.ends_with("summary.json"))
            .collect(),
    )
}

/// The first piece of a `.vtu` file.
pub fn vtu(path: &Path) -> vtkio::model::UnstructuredGridPiece {
    let vtk = Vtk::import(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    match vtk.data {
        DataSet::UnstructuredGrid { pieces, .. } => match pieces.into_iter().next() {
            Some(Piece::Inline(p)) => *p,
            _ => panic!("no inline piece"),
        },
        _ => panic!("not an unstructured grid"),
    }
}

/// The values of an `f64` buffer.
pub fn f64s(b: &IOBuffer) -> Vec<f64> {
    match b {
        IOBuffer::F64(v) => v.clone(),
        other => panic!("not f64: {other:?}"),
    }
}

/// True when a piece's data hold an array `name`.
pub fn has_array(attrs: &[Attribute], name: &str) -> bool {
    attrs
        .iter()
        .any(|a| matches!(a, Attribute::DataArray(d) if d.name == name))
}

/// The `f64` array `name` of a piece's data.
pub fn array(attrs: &[Attribute], name: &str) -> Vec<f64> {
    for a in attrs {
        if let Attribute::DataArray(d) = a {
            if d.name == name {
                return f64s(&d.data);
            }
        }
    }
    panic!("no array `{name}`")
}

/// An integer array (`part`, `stator`, `index`) of a piece's data.
pub fn ints(attrs: &[Attribute], name: &str) -> Vec<i64> {
    for a in attrs {
        if let Attribute::DataArray(d) = a {
            if d.name == name {
                return match &d.data {
                    IOBuffer::U8(v) => v.iter().map(|x| *x as i64).collect(),
                    IOBuffer::I32(v) => v.iter().map(|x| *x as i64).collect(),
                    IOBuffer::I64(v) => v.clone(),
                    other => panic!("`{name}` is not an integer array: {other:?}"),
                };
            }
        }
    }
    panic!("no array `{name}`")
}

/// Points `[x, y, z]` of a `.vtu` piece.
pub fn points(g: &vtkio::model::UnstructuredGridPiece) -> Vec<[f64; 3]> {
    f64s(&g.points)
        .chunks(3)
        .map(|p| [p[0], p[1], p[2]])
        .collect()
}

/// Cells `(type, point indices)` of a `.vtu` piece.
pub fn cells(g: &vtkio::model::UnstructuredGridPiece) -> Vec<(CellType, Vec<usize>)> {
    let VertexNumbers::XML {
        connectivity,
        offsets,
    } = &g.cells.cell_verts
    else {
        panic!("legacy cell numbering in an XML file")
    };
    let mut start = 0;
    g.cells
        .types
        .iter()
        .zip(offsets)
        .map(|(t, end)| {
            let ids = connectivity[start..*end as usize]
                .iter()
                .map(|i| *i as usize)
                .collect();
            start = *end as usize;
            (*t, ids)
        })
        .collect()
}

/// A `[f64; 3]` vector array of a piece's point or cell data.
pub fn vectors3(attrs: &[Attribute], name: &str) -> Vec<[f64; 3]> {
    array(attrs, name)
        .chunks(3)
        .map(|p| [p[0], p[1], p[2]])
        .collect()
}

/// The rotor centre's `[u_x, u_y]` in a `.vtu` frame (the last point of a Jeffcott rotor's
/// grid).
pub fn rotor_in_frame(path: &Path) -> [f64; 2] {
    let d = array(&vtu(path).data.point, "displacement");
    let n = d.len();
    [d[n - 3], d[n - 2]]
}

/// `(time, file)` of every `DataSet` line of a `.pvd`.
pub fn pvd(path: &Path) -> Vec<(f64, String)> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| l.contains("<DataSet"))
        .map(|l| {
            let field = |k: &str| {
                let a = l.find(&format!("{k}=\"")).unwrap() + k.len() + 2;
                let b = a + l[a..].find('"').unwrap();
                l[a..b].to_string()
            };
            (field("timestep").parse().unwrap(), field("file"))
        })
        .collect()
}

/// Opens a written HDF5 file for reading, retrying for up to a second while it is locked: a
/// child process another test thread spawns holds copies of this process's descriptors between
/// its fork and exec (`O_CLOEXEC` closes them only at the exec), and with them libhdf5's
/// `flock` on a file just written and closed — the open then fails with "unable to lock file"
/// (errno 11) for that instant, as `OutDir`'s lock waits for its `LOCK_PATIENCE`.
#[cfg(feature = "hdf5")]
pub fn open_h5(path: &Path) -> hdf5_metno::File {
    let t0 = std::time::Instant::now();
    loop {
        match hdf5_metno::File::open(path) {
            Ok(f) => return f,
            Err(e)
                if e.to_string().contains("unable to lock file")
                    && t0.elapsed().as_secs_f64() < 1.0 =>
            {
                std::thread::sleep(std::time::Duration::from_millis(10));
            }
            Err(e) => panic!("{}: {e}", path.display()),
        }
    }
}

/// A whole dataset of an HDF5 file.
#[cfg(feature = "hdf5")]
pub fn read<T: hdf5_metno::H5Type + Clone>(f: &hdf5_metno::File, name: &str) -> Vec<T> {
    f.dataset(name)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .read_raw::<T>()
        .unwrap()
}
