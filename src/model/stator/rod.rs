//! The paper's elastic rod (scene `kind = "rod"`, Fig. 4): bar elements along a coordinate
//! axis, the tip facing the station at the clearance, the far end fixed, lateral DOFs guided.

use super::{Lumped, StatorElement, StatorModel};
use crate::error::ModelError;
use crate::math::V2;

impl StatorModel {
    /// The paper's rod: `elements` bars along direction `angle_deg` from the station centre,
    /// tip at distance `radius + clearance`, far end fixed, lateral DOFs guided.
    #[allow(clippy::too_many_arguments)]
    pub fn rod(
        name: &str,
        station: usize,
        radius: f64,
        clearance: f64,
        length: f64,
        ea: f64,
        youngs_modulus: f64,
        mass_per_length: f64,
        elements: usize,
        angle_deg: f64,
        rayleigh: [f64; 2],
    ) -> Result<Self, ModelError> {
        let t = angle_deg.to_radians();
        let dir = [t.cos(), t.sin()];
        let r0 = radius + clearance;
        let le = length / elements as f64;
        let nodes: Vec<V2> = (0..=elements)
            .map(|i| {
                let s = r0 + i as f64 * le;
                [s * dir[0], s * dir[1]]
            })
            .collect();
        // Guide: lateral motion is fixed. For an axis along x or y this is the other
        // component; for an oblique rod a skew constraint would be needed, so the rod axis is
        // restricted to the coordinate axes.
        let lateral = if dir[0].abs() > dir[1].abs() { 1 } else { 0 };
        if dir[lateral].abs() > 1e-9 {
            return Err(ModelError::Inconsistent {
                what: format!("stator `{name}`"),
                message: format!(
                    "rod angle {angle_deg}° is not along a coordinate axis (0, 90, 180, 270); use kind = \"fe\" for oblique rods"
                ),
            });
        }
        let mut fixed = vec![[false; 2]; elements + 1];
        for f in fixed.iter_mut() {
            f[lateral] = true;
        }
        fixed[elements] = [true, true];
        let bars = (0..elements)
            .map(|i| StatorElement::Bar {
                nodes: [i, i + 1],
                ea,
                youngs_modulus,
                length: le,
            })
            .collect();
        let mut mass_node = vec![0.0; elements + 1];
        for i in 0..elements {
            mass_node[i] += mass_per_length * le / 2.0;
            mass_node[i + 1] += mass_per_length * le / 2.0;
        }
        let mut s = Lumped {
            name,
            station,
            nodes,
            fixed,
            elements: bars,
            mass_node,
            rayleigh,
            contact_nodes: vec![0],
        }
        .assemble()?;
        s.clearance = clearance;
        s.angle_deg = Some(angle_deg);
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rod_stiffness_is_ea_over_l_whatever_the_elements() {
        for ne in [1, 3, 8] {
            let r = StatorModel::rod("r", 0, 0.06, 1e-4, 0.04, 75e3, 3e9, 0.0, ne, 90.0, [0.0; 2])
                .unwrap();
            let k = r.contact_stiffness_bound();
            assert!((k / (75e3 / 0.04) - 1.0).abs() < 1e-10, "{ne}: {k}");
            assert!(r.massless());
            // tip above the rotor at r + δ
            assert!((r.nodes[0][1] - 0.0601).abs() < 1e-15);
        }
    }
}
