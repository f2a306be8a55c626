//! Mode shapes as people look at them: the complex shape of a mode per rotor node, its whirl
//! ellipses, the shaft line at a phase, and the line sampled between the nodes.
//!
//! A mode `q(t) = Re(φ e^{iω_d t})` (no decay: the shape at constant amplitude) moves node `i`
//! on the ellipse `x(t) + i y(t) = F e^{iτ} + B e^{−iτ}`, `τ = ω_d t`, with the forward and
//! backward circular parts `F = (φ_x + i φ_y)/2`, `B = (φ̄_x + i φ̄_y)/2`: major semi-axis
//! `|F| + |B|`, minor `||F| − |B||`, whirling forward (counter-clockwise seen from +z, with the
//! spin) when `|F| > |B|`. Shapes are those of [`Mode`]: scaled so that the largest entry is 1,
//! rotations on the same scale (rad per unit of that entry).
//!
//! Between two FE nodes the displacement is the shaft element's cubic (Hermite) interpolation
//! of the end values and slopes — `u_x` with `θ_y = ∂u_x/∂z`, `u_y` with `θ_x = −∂u_y/∂z` —
//! applied to the complex shape, so the drawn line is the element's own deflection.

use super::modes::Mode;
use crate::model::Rotor;
use num_complex::Complex64;

/// Where things sit along the rotor axis.
#[derive(Debug, Clone, PartialEq)]
pub struct RotorLine {
    /// Axial position of each node (m); `[0]` for a Jeffcott rotor.
    pub z: Vec<f64>,
    /// Nodes carrying a disk.
    pub disk_nodes: Vec<usize>,
    /// Nodes carrying a bearing.
    pub bearing_nodes: Vec<usize>,
    /// True when the nodes have rotations (FE rotor): the line between them is cubic.
    pub has_rotations: bool,
}

/// The rotor's nodes, disks and bearings along its axis.
pub fn rotor_line(rotor: &Rotor) -> RotorLine {
    match rotor {
        Rotor::Jeffcott(_) => RotorLine {
            z: vec![0.0],
            disk_nodes: vec![0],
            bearing_nodes: Vec::new(),
            has_rotations: false,
        },
        Rotor::Fe(f) => RotorLine {
            z: f.rotor.z.clone(),
            disk_nodes: f.rotor.disks.iter().map(|d| d.node).collect(),
            bearing_nodes: f.rotor.bearings.iter().map(|b| b.node).collect(),
            has_rotations: true,
        },
    }
}

/// The complex shape `[φ_x, φ_y, φ_θx, φ_θy]` of every node (rotations 0 when the rotor has
/// none).
pub fn node_shape(mode: &Mode) -> Vec<[Complex64; 4]> {
    let zero = Complex64::new(0.0, 0.0);
    mode.shape
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let t = mode.shape_tilt.get(i).copied().unwrap_or([zero; 2]);
            [p[0], p[1], t[0], t[1]]
        })
        .collect()
}

/// The real shape at phase `alpha` (rad): `Re(φ e^{iα})` of every node and component.
pub fn at_phase(shape: &[[Complex64; 4]], alpha: f64) -> Vec<[f64; 4]> {
    let e = Complex64::from_polar(1.0, alpha);
    shape.iter().map(|p| p.map(|v| (v * e).re)).collect()
}

/// The phase at which the translations are largest: `α* = −arg(Σ φ²)/2` maximises
/// `Σ |Re(φ e^{iα})|² = ½ Σ |φ|² + ½ Re(e^{2iα} Σ φ²)` over the `u_x`, `u_y` of every node.
pub fn peak_phase(shape: &[[Complex64; 4]]) -> f64 {
    let s: Complex64 = shape.iter().map(|p| p[0] * p[0] + p[1] * p[1]).sum();
    if s.norm() == 0.0 {
        0.0
    } else {
        -0.5 * s.arg()
    }
}

/// The whirl ellipse of one point moving as `Re([x, y] e^{iτ})`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ellipse {
    /// Major semi-axis (same unit as the shape).
    pub major: f64,
    /// Minor semi-axis, positive for forward whirl, negative for backward.
    pub minor: f64,
    /// Angle of the major axis from +x, counter-clockwise (rad).
    pub angle: f64,
}

/// The ellipse traced by `Re([x, y] e^{iτ})` over one period (module docs).
pub fn ellipse(x: Complex64, y: Complex64) -> Ellipse {
    let i = Complex64::new(0.0, 1.0);
    let f = 0.5 * (x + i * y);
    let b = 0.5 * (x.conj() + i * y.conj());
    let minor = f.norm() - b.norm();
    Ellipse {
        major: f.norm() + b.norm(),
        minor,
        angle: 0.5 * (f.arg() + b.arg()),
    }
}

/// The ellipse of every node.
pub fn ellipses(shape: &[[Complex64; 4]]) -> Vec<Ellipse> {
    shape.iter().map(|p| ellipse(p[0], p[1])).collect()
}

/// The complex `[φ_x, φ_y]` along the axis at `per_element` points per element (both ends
/// included once): the shaft element's cubic interpolation (module docs), linear when the rotor
/// has no rotations. Returns `(z, [φ_x, φ_y])` per point.
pub fn sample_line(
    line: &RotorLine,
    shape: &[[Complex64; 4]],
    per_element: usize,
) -> Vec<(f64, [Complex64; 2])> {
    let n = line.z.len().min(shape.len());
    let mut out = Vec::with_capacity(n.saturating_sub(1) * per_element.max(1) + 1);
    for e in 0..n.saturating_sub(1) {
        let (z0, z1) = (line.z[e], line.z[e + 1]);
        let h = z1 - z0;
        let (a, b) = (shape[e], shape[e + 1]);
        // Slopes: ∂u_x/∂z = θ_y, ∂u_y/∂z = −θ_x.
        let (sa, sb) = if line.has_rotations {
            ([a[3], -a[2]], [b[3], -b[2]])
        } else {
            let d = [(b[0] - a[0]) / h, (b[1] - a[1]) / h];
            (d, d)
        };
        for k in 0..per_element.max(1) {
            let s = k as f64 / per_element.max(1) as f64;
            let h00 = 2.0 * s.powi(3) - 3.0 * s * s + 1.0;
            let h10 = s.powi(3) - 2.0 * s * s + s;
            let h01 = -2.0 * s.powi(3) + 3.0 * s * s;
            let h11 = s.powi(3) - s * s;
            let v = |c: usize| a[c] * h00 + sa[c] * (h10 * h) + b[c] * h01 + sb[c] * (h11 * h);
            out.push((z0 + s * h, [v(0), v(1)]));
        }
    }
    if n > 0 {
        out.push((line.z[n - 1], [shape[n - 1][0], shape[n - 1][1]]));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(re: f64, im: f64) -> Complex64 {
        Complex64::new(re, im)
    }

    #[test]
    fn forward_circle_has_positive_minor_axis_and_backward_negative() {
        // x = cos τ, y = sin τ: φ = (1, −i), counter-clockwise.
        let fw = ellipse(c(1.0, 0.0), c(0.0, -1.0));
        assert!((fw.major - 1.0).abs() < 1e-15 && (fw.minor - 1.0).abs() < 1e-15);
        let bw = ellipse(c(1.0, 0.0), c(0.0, 1.0));
        assert!((bw.major - 1.0).abs() < 1e-15 && (bw.minor + 1.0).abs() < 1e-15);
        // A line at 30°: major 2, minor 0, angle 30° (mod π).
        let (ca, sa) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        let l = ellipse(c(2.0 * ca, 0.0), c(2.0 * sa, 0.0));
        assert!((l.major - 2.0).abs() < 1e-14 && l.minor.abs() < 1e-14);
        let d = (l.angle - 30f64.to_radians()).rem_euclid(std::f64::consts::PI);
        assert!(
            d < 1e-12 || (std::f64::consts::PI - d) < 1e-12,
            "{}",
            l.angle
        );
    }

    #[test]
    fn peak_phase_maximises_the_translations() {
        let shape = vec![[c(0.3, 0.8), c(-0.2, 0.5), c(0.0, 0.0), c(0.0, 0.0)]];
        let a = peak_phase(&shape);
        let energy = |al: f64| -> f64 {
            at_phase(&shape, al)
                .iter()
                .map(|p| p[0] * p[0] + p[1] * p[1])
                .sum()
        };
        for k in 0..360 {
            assert!(energy(a) >= energy(f64::from(k).to_radians()) - 1e-12);
        }
    }

    #[test]
    fn hermite_line_reproduces_a_cubic_from_end_values_and_slopes() {
        // u_x = z³ on [0, 2]: θ_y = 3z²; u_y = z² with θ_x = −2z.
        let line = RotorLine {
            z: vec![0.0, 2.0],
            disk_nodes: vec![],
            bearing_nodes: vec![],
            has_rotations: true,
        };
        let node = |z: f64| {
            [
                c(z.powi(3), 0.0),
                c(z * z, 0.0),
                c(-2.0 * z, 0.0),
                c(3.0 * z * z, 0.0),
            ]
        };
        let pts = sample_line(&line, &[node(0.0), node(2.0)], 8);
        assert_eq!(pts.len(), 9);
        for (z, p) in pts {
            assert!((p[0].re - z.powi(3)).abs() < 1e-12, "{z}");
            assert!((p[1].re - z * z).abs() < 1e-12, "{z}");
        }
    }
}
