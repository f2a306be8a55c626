//! The general 2-D FE stator (scene `kind = "fe"`): bars and grounded springs between given
//! nodes, lumped masses, fixed DOFs and contact nodes as given.

use super::{Lumped, StatorElement, StatorModel};
use crate::error::ModelError;
use crate::resolve::{FeElement, FeStatorInput};

impl StatorModel {
    /// Builds a general FE stator from nodes, elements and fixed DOFs: bars of stiffness
    /// E A / L with half of ρ A L lumped at each end, springs k along their direction, point
    /// masses added to the nodes. Its clearance is left to the caller (it follows from the
    /// geometry and the station radius).
    pub fn from_fe(spec: &FeStatorInput) -> Result<Self, ModelError> {
        let nn = spec.nodes.len();
        let mut fixed = vec![[false; 2]; nn];
        for f in &spec.fixed {
            fixed[f[0]][f[1]] = true;
        }
        let mut elements = Vec::new();
        let mut mass_node = vec![0.0; nn];
        for el in &spec.elements {
            match el {
                FeElement::Bar {
                    nodes,
                    youngs_modulus,
                    area,
                    density,
                } => {
                    let a = spec.nodes[nodes[0]];
                    let b = spec.nodes[nodes[1]];
                    let l = (b[0] - a[0]).hypot(b[1] - a[1]);
                    elements.push(StatorElement::Bar {
                        nodes: *nodes,
                        ea: youngs_modulus * area,
                        youngs_modulus: *youngs_modulus,
                        length: l,
                    });
                    let half = density * area * l / 2.0;
                    mass_node[nodes[0]] += half;
                    mass_node[nodes[1]] += half;
                }
                FeElement::Spring {
                    node,
                    stiffness,
                    angle_deg,
                } => {
                    let t = angle_deg.to_radians();
                    elements.push(StatorElement::Spring {
                        node: *node,
                        stiffness: *stiffness,
                        dir: [t.cos(), t.sin()],
                    });
                }
            }
        }
        for (n, m) in &spec.point_masses {
            mass_node[*n] += m;
        }
        Lumped {
            name: &spec.name,
            station: spec.station,
            nodes: spec.nodes.clone(),
            fixed,
            elements,
            mass_node,
            rayleigh: spec.rayleigh,
            contact_nodes: spec.contact_nodes.clone(),
        }
        .assemble()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unsupported_fe_stator_is_singular() {
        let spec = FeStatorInput {
            name: "free".into(),
            station: 0,
            nodes: vec![[0.0, 0.1], [0.0, 0.2]],
            elements: vec![FeElement::Bar {
                nodes: [0, 1],
                youngs_modulus: 1e9,
                area: 1e-4,
                density: 0.0,
            }],
            fixed: vec![],
            contact_nodes: vec![0],
            rayleigh: [0.0; 2],
            point_masses: vec![],
        };
        let e = StatorModel::from_fe(&spec).unwrap_err().to_string();
        assert!(e.contains("free") && e.contains("rigid-body"), "{e}");
    }
}
