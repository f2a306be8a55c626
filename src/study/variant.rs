//! The variants of a study: the scene once, once per value of `[run.sweep.vary]`, or once per
//! value (pair of values) of a map's scene keys — each a list of overrides of the scene.

use crate::error::{Error, Result};
use crate::scene::{toml_number, LoadedScene, VarySpec};

/// One variant of the scene in a study: the overrides it adds and the sub-folder its files go
/// to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Variant {
    /// Sub-folder of its files: `""` for a plain sweep or a map, else `<last key segment>_<value>/`.
    pub prefix: String,
    /// Overrides added to the command line's (`key=value`); empty for a plain sweep.
    pub overrides: Vec<String>,
}

impl Variant {
    /// True for the plain sweep (no override added).
    pub fn is_base(&self) -> bool {
        self.overrides.is_empty()
    }

    /// The overrides as shown to the user: `key=value, …`.
    pub fn label(&self) -> String {
        self.overrides.join(", ")
    }

    /// The pictures' title: the scene's, with the overrides in brackets for a variant.
    pub fn title(&self, scene_title: &str) -> String {
        if self.is_base() {
            scene_title.to_string()
        } else {
            format!("{scene_title} [{}]", self.label())
        }
    }

    /// A map's variant: the overrides, no sub-folder.
    fn of_map(overrides: Vec<String>) -> Self {
        Self {
            prefix: String::new(),
            overrides,
        }
    }
}

/// The sweeps of a scene: one plain sweep, or one per value of `[run.sweep.vary]`.
pub fn variants(vary: Option<&VarySpec>) -> Vec<Variant> {
    match vary {
        None => vec![Variant {
            prefix: String::new(),
            overrides: Vec::new(),
        }],
        Some(v) => v
            .values
            .iter()
            .map(|x| {
                let name = v.key.rsplit('.').next().unwrap_or("value");
                Variant {
                    prefix: format!("{name}_{x}/"),
                    overrides: vec![format!("{}={}", v.key, toml_number(*x))],
                }
            })
            .collect(),
    }
}

/// The axes of a map: keys and values, and which one (if any) is the speed.
#[derive(Debug, Clone, PartialEq)]
pub struct MapAxes {
    /// The horizontal and vertical keys.
    pub keys: [String; 2],
    /// Their values.
    pub values: [Vec<f64>; 2],
    /// Index of the speed axis (`speed_ratio`), if one is.
    pub speed: Option<usize>,
}

impl MapAxes {
    /// The grid position `(ix, iy)` of case `k` of the study (variant-major, `ns` speeds per
    /// variant): see [`map_variants`] for the expansion.
    pub fn cell(&self, k: usize, ns: usize) -> (usize, usize) {
        let (variant, s) = (k / ns, k % ns);
        match self.speed {
            Some(0) => (s, variant),
            Some(_) => (variant, s),
            None => (
                variant / self.values[1].len(),
                variant % self.values[1].len(),
            ),
        }
    }
}

/// The variants and speeds of a map scene, and its axes: with a speed axis, one variant per
/// value of the other key and the speed axis as the speeds; with two scene keys, one variant
/// per pair (x-major) at the scene's single speed (`run.speed_ratio`, or `run.speed` over
/// ω_n = `wn`, rad/s).
///
/// # Errors
/// [`Error::Study`] naming the scene file: no `[run.map]`, or a map of two scene keys without
/// a speed.
pub fn map_variants(
    ls: &LoadedScene,
    wn: Option<f64>,
) -> Result<(Vec<Variant>, Vec<f64>, MapAxes)> {
    let file = ls.file.display();
    let m = ls
        .scene
        .run
        .map
        .as_ref()
        .ok_or_else(|| Error::study(&file, "`rubsim map` needs a [run.map] table"))?;
    let axes = MapAxes {
        keys: [m.x.key.clone(), m.y.key.clone()],
        values: [m.x.resolved(), m.y.resolved()],
        speed: [&m.x, &m.y].iter().position(|a| a.is_speed()),
    };
    let over = |k: &str, v: f64| format!("{k}={}", toml_number(v));
    let (variants, speeds) = match axes.speed {
        Some(s) => {
            let o = 1 - s;
            let vs = axes.values[o]
                .iter()
                .map(|v| Variant::of_map(vec![over(&axes.keys[o], *v)]))
                .collect();
            (vs, axes.values[s].clone())
        }
        None => {
            let run = &ls.scene.run;
            let nu = match (run.speed_ratio, run.speed, wn) {
                (Some(r), _, _) => r,
                (None, Some(w), Some(wn)) => w / wn,
                _ => {
                    return Err(Error::study(
                        &file,
                        "a map of two scene keys runs at `run.speed_ratio` or `run.speed`",
                    ))
                }
            };
            let mut vs = Vec::new();
            for x in &axes.values[0] {
                for y in &axes.values[1] {
                    vs.push(Variant::of_map(vec![
                        over(&axes.keys[0], *x),
                        over(&axes.keys[1], *y),
                    ]));
                }
            }
            (vs, vec![nu])
        }
    };
    Ok((variants, speeds, axes))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn map_scene(x: &str, y: &str, speed: Option<&str>) -> LoadedScene {
        let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/regime_map.toml");
        let mut sets = vec![format!("run.map.x={x}"), format!("run.map.y={y}")];
        sets.extend(speed.map(String::from));
        crate::scene::load(&file, &sets).unwrap()
    }

    #[test]
    fn a_map_with_a_speed_axis_has_one_variant_per_value_of_the_other_key() {
        let ls = map_scene(
            "{ key = \"speed_ratio\", values = [0.8, 1.7, 3.1] }",
            "{ key = \"stator.0.clearance_nd\", values = [0.4, 0.6] }",
            None,
        );
        let (vs, speeds, axes) = map_variants(&ls, None).unwrap();
        assert_eq!(speeds, [0.8, 1.7, 3.1]);
        assert_eq!(vs.len(), 2);
        assert_eq!(vs[1].overrides, ["stator.0.clearance_nd=0.6"]);
        assert!(vs.iter().all(|v| v.prefix.is_empty()));
        // Case k (variant-major) lands on the cell of its speed (x) and its clearance (y).
        for k in 0..6 {
            let (ix, iy) = axes.cell(k, speeds.len());
            assert_eq!(axes.values[0][ix], speeds[k % 3]);
            assert_eq!(
                vs[k / 3].overrides[0],
                format!("stator.0.clearance_nd={}", axes.values[1][iy])
            );
        }
    }

    #[test]
    fn a_map_of_two_keys_runs_every_pair_at_the_scene_speed_or_names_the_scene() {
        let (x, y) = (
            "{ key = \"stator.0.clearance_nd\", values = [0.4, 0.6] }",
            "{ key = \"station.0.friction\", values = [0.1, 0.2, 0.3] }",
        );
        let ls = map_scene(x, y, Some("run.speed_ratio=2.5"));
        let (vs, speeds, axes) = map_variants(&ls, None).unwrap();
        assert_eq!(speeds, [2.5]);
        assert_eq!(vs.len(), 6);
        assert_eq!(
            vs[4].overrides,
            ["stator.0.clearance_nd=0.6", "station.0.friction=0.2"]
        );
        assert_eq!(axes.cell(4, 1), (1, 1));
        // `run.speed` (rad/s) is a ratio only with ω_n; without it the error names the scene.
        let ls = map_scene(x, y, Some("run.speed=300.0"));
        assert_eq!(map_variants(&ls, Some(100.0)).unwrap().1, [3.0]);
        let e = map_variants(&ls, None).unwrap_err().to_string();
        assert!(
            e.contains("regime_map.toml") && e.contains("run.speed"),
            "{e}"
        );
    }
}
