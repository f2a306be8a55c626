//! The rotor's response to what drives it, in the frequency domain: the steady unbalance
//! response over speed and the static deflection under gravity, with the speed lists and node
//! choices of `rubsim unbalance` and `rubsim modal`.
//!
//! Sign and phase: a DOF's steady response is `Re(q e^{iΩt})`, so `x = |X| cos(Ωt + φ_x)`
//! with `X = q_x` from [`Rotor::unbalance_response`]; the orbit's major semi-axis is
//! [`ellipse_major`] of `(X, Y)`.

use crate::error::ModelError;
use crate::model::fe_rotor::{dense, ellipse_major};
use crate::model::Rotor;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// Unbalance response at one speed and node.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct ResponsePoint {
    /// Spin speed (rad/s).
    pub speed: f64,
    /// Node.
    pub node: usize,
    /// x amplitude (m) and phase (deg) of `x = |X| cos(Ωt + φ_x)`.
    pub x_amp: f64,
    /// Phase of x (deg).
    pub x_phase_deg: f64,
    /// y amplitude (m).
    pub y_amp: f64,
    /// Phase of y (deg).
    pub y_phase_deg: f64,
    /// Major semi-axis of the orbit (m).
    pub major: f64,
    /// Complex x response (m), for polar plots.
    pub x_re: f64,
    /// Imaginary part of x (m).
    pub x_im: f64,
}

/// Steady unbalance response over `speeds` (rad/s) at `nodes`.
pub fn unbalance_response(
    rotor: &Rotor,
    speeds: &[f64],
    nodes: &[usize],
) -> Result<Vec<ResponsePoint>, ModelError> {
    let mut out = Vec::new();
    for &w in speeds {
        let q = rotor.unbalance_response(w)?;
        for &n in nodes {
            let d = rotor.node_dofs(n);
            let (x, y) = (q[d[0]], q[d[1]]);
            out.push(ResponsePoint {
                speed: w,
                node: n,
                x_amp: x.norm(),
                x_phase_deg: x.arg().to_degrees(),
                y_amp: y.norm(),
                y_phase_deg: y.arg().to_degrees(),
                major: ellipse_major(x, y),
                x_re: x.re,
                x_im: x.im,
            });
        }
    }
    Ok(out)
}

/// Static deflection under gravity g (m/s², along −y): `K q = −g M e_y` (m, rad per DOF).
/// Gravity is lateral, so only the lateral block is solved and the axial and torsional entries
/// are zero (uncoupled DOFs, which may be free).
pub fn static_deflection(rotor: &Rotor, g: f64) -> Result<Vec<f64>, ModelError> {
    let (m, k, _, _) = rotor.matrices(0.0)?;
    let (n, nl) = (m.nrows(), rotor.lateral_dofs());
    let mut ey = DVector::zeros(n);
    for i in 0..rotor.node_count() {
        ey[rotor.node_dofs(i)[1]] = 1.0;
    }
    let f = (-g * (dense(&m) * ey)).rows(0, nl).into_owned();
    let kd: DMatrix<f64> = dense(&k).view((0, 0), (nl, nl)).into_owned();
    let mut q: Vec<f64> = kd
        .lu()
        .solve(&f)
        .map(|v| v.iter().copied().collect())
        .ok_or_else(|| ModelError::Singular {
            what: "rotor stiffness".into(),
            detail: "singular: the rotor is not held by its bearings".into(),
        })?;
    q.resize(n, 0.0);
    Ok(q)
}

/// `points` speeds (at least 2) spread evenly from `from` to `to`, both included.
pub fn speed_list(from: f64, to: f64, points: usize) -> Vec<f64> {
    let n = points.max(2);
    (0..n)
        .map(|i| from + (to - from) * i as f64 / (n - 1) as f64)
        .collect()
}

/// The nodes an unbalance response reports by default: every station's rotor node, node 0
/// when there is no station.
pub fn default_response_nodes(model: &crate::model::Model) -> Vec<usize> {
    let v: Vec<usize> = model.stations.iter().map(|s| s.node).collect();
    if v.is_empty() {
        vec![0]
    } else {
        v
    }
}

/// The lateral displacement `[u_x, u_y]` of every rotor node from a DOF vector `q` (e.g. the
/// [`static_deflection`]), in node order.
pub fn lateral_at_nodes(rotor: &Rotor, q: &[f64]) -> Vec<[f64; 2]> {
    (0..rotor.node_count())
        .map(|i| {
            let d = rotor.node_dofs(i);
            [q[d[0]], q[d[1]]]
        })
        .collect()
}

/// The largest major semi-axis of the response at `node` and its speed, `(speed, amplitude)`
/// (`(0, 0)` when the node has no point).
pub fn peak_response(res: &[ResponsePoint], node: usize) -> (f64, f64) {
    res.iter()
        .filter(|r| r.node == node)
        .map(|r| (r.speed, r.major))
        .fold((0.0, 0.0), |b, x| if x.1 > b.1 { x } else { b })
}
