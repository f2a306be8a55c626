//! What a run with wear (`[stator.wear]`, `scene::wear`, `time::wear`) tells: the volume worn
//! and the worn depth against time, the worn depth of every contact node at the end — around
//! the circumference and, on a 3-D stator, along the axis — and whether the rub has worn
//! itself free. With an abradable coating (`[stator.abradable]`, `time::abradable`) the depth
//! a node receded is its worn depth plus its coating's plastic shortening, which
//! [`AbradableResults`] and [`WornNode::abraded_m`] also give apart.

use crate::math::V2;
use crate::model::{Case, Target};
use crate::time::Record;
use serde::Serialize;
use std::f64::consts::PI;

/// One contact node of a stator that wears, at the run's end.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WornNode {
    /// The stator's name.
    pub stator: String,
    /// The node's index in the stator's mesh (0-based; the rod's tip for a rod).
    pub node: usize,
    /// Position in the station plane relative to the station's centre, as placed (m).
    pub x: f64,
    /// y (m).
    pub y: f64,
    /// Axial position along the rotor (m): a 3-D stator's node; 0 in 2-D.
    pub z: f64,
    /// Angle of the position from +x, counter-clockwise (degrees, 0 … 360).
    pub angle_deg: f64,
    /// Tributary area (m²) the worn volume is spread over.
    pub area_m2: f64,
    /// Abradable coating (`[stator.abradable]`): its plastic shortening d_p (m), part of
    /// `depth_m`; 0 without a coating.
    pub abraded_m: f64,
    /// Worn depth (m): how far the surface receded (Archard's wear plus the coating's `d_p`).
    pub depth_m: f64,
}

/// What the rub cut off the abradable coatings (`[stator.abradable]`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AbradableResults {
    /// Volume cut off the coatings (m³): `Σ A d_p` over the coated nodes.
    pub volume_m3: f64,
    /// Plastic work done on the coatings (J): `Σ p Δd_p` over the run's solves, which equals
    /// `Σ A (σ_y d_p + H d_p² / (2h))` as Δd_p → 0.
    pub plastic_work_j: f64,
    /// Largest plastic shortening d_p of a node (m).
    pub max_depth_m: f64,
    /// The node of the largest d_p (none when nothing was cut).
    pub deepest: Option<WornNode>,
}

/// The wear of a run (module docs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WearResults {
    /// The wear magnification A (`run.wear_acceleration`): the run's time t is a wear time A t.
    pub acceleration: f64,
    /// Volume removed from the stators at the run's end (m³): worn by Archard's law and cut
    /// off abradable coatings.
    pub volume_m3: f64,
    /// Largest worn depth at the run's end (m).
    pub max_depth_m: f64,
    /// The node of the largest depth.
    pub deepest: Option<WornNode>,
    /// No pair carried force over the run's last revolution: the rub has worn itself free.
    pub free_at_end: bool,
    /// The abradable coatings' part (`[stator.abradable]`); `None` without a coating.
    pub abradable: Option<AbradableResults>,
    /// Per recorded sample: t (s), volume worn so far (m³), largest worn depth so far (m).
    #[serde(skip)]
    pub history: Vec<[f64; 3]>,
    /// Every contact node of the stators that wear, stator by stator, in target order.
    #[serde(skip)]
    pub nodes: Vec<WornNode>,
}

/// The wear of the run of `case` that recorded `rec`, with the spin angle `phi` (rad) at each
/// sample; `None` when no stator of the case wears.
pub fn of_record(case: &Case, rec: &Record, phi: &[f64]) -> Option<WearResults> {
    let acceleration = case
        .stators
        .iter()
        .find_map(|s| s.wear.as_ref())?
        .acceleration;
    let mut nodes = Vec::new();
    let mut ci = 0;
    for s in &case.stators {
        for (t, tg) in s.targets.iter().enumerate() {
            let depth = rec.worn.get(ci).copied().unwrap_or(0.0);
            let abraded = rec.abraded.get(ci).copied().unwrap_or(0.0);
            ci += 1;
            let (Some(w), Target::Node { node, x0, .. }) = (&s.wear, tg) else {
                continue;
            };
            let z = s
                .mesh
                .as_ref()
                .and_then(|m| m.node_z.get(*node).map(|z| z + m.axial_origin))
                .unwrap_or(0.0);
            let mut n = worn_node(&s.name, *node, *x0, z, w.areas[t], depth);
            n.abraded_m = abraded;
            nodes.push(n);
        }
    }
    let history: Vec<[f64; 3]> = (rec.t.iter().zip(&rec.wear))
        .map(|(t, w)| [*t, w[0], w[1]])
        .collect();
    let last = history.last().copied().unwrap_or([0.0; 3]);
    let deepest = nodes
        .iter()
        .max_by(|a, b| a.depth_m.total_cmp(&b.depth_m))
        .filter(|n| n.depth_m > 0.0)
        .cloned();
    // The last revolution's samples: no pair carrying force at any of them.
    let end = phi.last().copied().unwrap_or(0.0);
    let from = phi.partition_point(|p| *p < end - 2.0 * PI);
    let free_at_end = phi.len() > 1
        && rec.active[from.min(rec.active.len())..]
            .iter()
            .all(|a| *a == 0);
    let coated = case
        .stators
        .iter()
        .any(|s| s.wear.as_ref().is_some_and(|w| w.layer.is_some()));
    let abradable = coated.then(|| {
        let deepest = nodes
            .iter()
            .max_by(|a, b| a.abraded_m.total_cmp(&b.abraded_m))
            .filter(|n| n.abraded_m > 0.0)
            .cloned();
        AbradableResults {
            volume_m3: rec.abradable[0],
            plastic_work_j: rec.abradable[1],
            max_depth_m: deepest.as_ref().map_or(0.0, |n| n.abraded_m),
            deepest,
        }
    });
    Some(WearResults {
        abradable,
        acceleration,
        volume_m3: last[1],
        max_depth_m: last[2],
        deepest,
        free_at_end,
        history,
        nodes,
    })
}

/// A [`WornNode`] of stator `stator`'s node `node` at `x0` (m), axial `z` (m).
fn worn_node(stator: &str, node: usize, x0: V2, z: f64, area: f64, depth: f64) -> WornNode {
    let angle = x0[1].atan2(x0[0]).to_degrees();
    WornNode {
        stator: stator.to_string(),
        node,
        x: x0[0],
        y: x0[1],
        z,
        angle_deg: if angle < 0.0 { angle + 360.0 } else { angle },
        area_m2: area,
        abraded_m: 0.0,
        depth_m: depth,
    }
}
