//! The per-speed VTK/HDF5 time series of a sweep's cases (`output.per_speed`): which cases
//! keep them in the store, the output settings they are stamped with, and their linking into
//! the results.

use super::case::{CaseId, CaseSpec};
use super::store::CaseStore;
use super::{Kind, Study};
use crate::error::{Error, Result};
use crate::output::OutDir;
use crate::results::per_speed_selection;
use crate::scene::LoadedScene;

/// Which cases of a study keep their time series, and the stamp of the settings they are
/// written with.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SeriesPlan {
    /// (variant, bits of ω/ω_n) of the cases that keep series.
    wanted: Vec<(usize, u64)>,
    /// What the kept series depend on besides the case ([`SeriesPlan::stamp`]).
    stamp: String,
}

impl SeriesPlan {
    /// The cases whose series `output.per_speed` asks for (sweeps only; a map keeps none), and
    /// the stamp of `output.vtk` and `output.hdf5` (which the store's scene hash leaves out).
    ///
    /// # Errors
    /// [`Error::Scene`] naming `output.per_speed` when it selects no speed of the study.
    pub fn of(ls: &LoadedScene, study: &Study) -> Result<Self> {
        let o = &ls.scene.output;
        let mut h = crate::math::Fnv128::new();
        h.write(
            serde_json::to_string(&(&o.vtk, &o.hdf5))
                .unwrap_or_default()
                .as_bytes(),
        );
        let stamp = h.hex();
        if study.kind != Kind::Sweep {
            return Ok(Self {
                wanted: Vec::new(),
                stamp,
            });
        }
        let sel =
            per_speed_selection(o, &study.speeds).map_err(|m| ls.invalid("output.per_speed", m))?;
        let wanted = (0..study.variants.len())
            .flat_map(|i| {
                study
                    .speeds
                    .iter()
                    .zip(&sel)
                    .filter(|(_, s)| **s)
                    .map(move |(v, _)| (i, v.to_bits()))
            })
            .collect();
        Ok(Self { wanted, stamp })
    }

    /// Whether `case` keeps its time series.
    pub fn wants(&self, case: &CaseSpec) -> bool {
        self.wanted
            .contains(&(case.variant, case.speed_ratio.to_bits()))
    }

    /// The stamp of the output settings the series are written with.
    pub fn stamp(&self) -> &str {
        &self.stamp
    }

    /// Links (or, across file systems, copies) the kept series of case `id` from `store` into
    /// the staging folder of `outd` under their names in the results, and registers them for
    /// the commit.
    ///
    /// # Errors
    /// [`Error::Output`] naming the series missing from the store or a file that cannot be
    /// linked or copied.
    pub fn link(&self, store: &CaseStore, id: &CaseId, outd: &mut OutDir) -> Result<()> {
        let from = store.series_path(id);
        let files = store.series_files(id, &self.stamp)?.ok_or_else(|| {
            Error::output(
                &from,
                format!("the time series of case {id} are missing from the store"),
            )
        })?;
        for name in &files {
            let (src, dst) = (from.join(name), outd.staging_dir().join(name));
            if let Some(d) = dst.parent() {
                std::fs::create_dir_all(d).map_err(|e| Error::output(d, e))?;
            }
            if std::fs::hard_link(&src, &dst).is_err() {
                std::fs::copy(&src, &dst).map_err(|e| Error::output(&src, e))?;
            }
            outd.adopt(name)?;
        }
        Ok(())
    }

    /// For a merge: links the series of every case of `study` that keeps them from whichever
    /// store (shard) kept them into `outd`, so that the merged directory holds them as a
    /// one-machine run does.
    ///
    /// # Errors
    /// [`Error::Study`] naming a case whose series no store keeps and the stores searched; as
    /// [`SeriesPlan::link`].
    pub fn gather(&self, study: &Study, stores: &[CaseStore], outd: &mut OutDir) -> Result<()> {
        for case in study.cases().iter().filter(|c| self.wants(c)) {
            let mut from = None;
            for st in stores {
                if st.series_files(&case.id, &self.stamp)?.is_some() {
                    from = Some(st);
                    break;
                }
            }
            let Some(st) = from else {
                return Err(Error::study(
                    "",
                    format!(
                        "case {} (ω/ωn = {}) asks for its time series (`output.per_speed`), but \
                         none of the merged stores keeps them ({}); run its shard again",
                        case.id,
                        case.speed_ratio,
                        stores
                            .iter()
                            .map(|s| s.dir().display().to_string())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                ));
            };
            self.link(st, &case.id, outd)?;
        }
        Ok(())
    }
}
