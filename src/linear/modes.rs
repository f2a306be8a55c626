//! The damped modes of the rotor alone at one spin speed (the Campbell diagram built on them is
//! [`mod@super::campbell`], the forced response [`super::response`]).
//!
//! The rotor obeys `M q̈ + (C + Ω G) q̇ + K q = f` with the matrices of
//! [`crate::model::Rotor::matrices`]. Modes come from the first-order form
//! `ż = A z`, `A = [[0, I], [−M⁻¹K, −M⁻¹(C + ΩG)]]`, eigenvalues `λ = σ ± i ω_d` (dense,
//! `faer`): damping ratio `ζ = −σ/|λ|`, logarithmic decrement `δ = −2πσ/ω_d`. A mode with
//! eigenvector `φ` whirls **forward** (with the spin, counter-clockwise seen from +z for
//! Ω > 0) at a node when `Im(φ_x φ̄_y) > 0` for `ω_d > 0`.
//!
//! FE rotors with axial (`u_z`) or torsional (`θ_z`) DOFs have modes of those kinds too. M has
//! no entries between lateral, axial and torsional DOFs, so the kinetic energy `φᴴ M φ` of a
//! mode splits exactly into the three groups; a mode is labelled ([`ModeKind`]) by the group
//! holding the largest share, and only lateral modes get a whirl direction. Axial and torsional
//! frequencies do not depend on the spin (G acts on the bending rotations only): their
//! Campbell lines are flat.

use crate::error::ModelError;
use crate::linalg::Csc;
use crate::model::fe_rotor::dense;
use crate::model::Rotor;
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;
use serde::Serialize;

/// Whirl direction of a mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Whirl {
    /// With the spin.
    Forward,
    /// Against the spin.
    Backward,
    /// Nodes disagree (or planar motion).
    Mixed,
    /// No lateral motion to whirl: axial and torsional modes.
    NoWhirl,
}

impl Whirl {
    /// Short label.
    pub fn label(self) -> &'static str {
        match self {
            Whirl::Forward => "FW",
            Whirl::Backward => "BW",
            Whirl::Mixed => "mixed",
            Whirl::NoWhirl => "-",
        }
    }
}

/// Which DOFs a mode moves: the group with the largest share of its kinetic energy `φᴴ M φ`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ModeKind {
    /// Bending (`u_x, u_y, θ_x, θ_y`, pedestals).
    Lateral,
    /// Axial `u_z`.
    Axial,
    /// Torsional `θ_z`.
    Torsional,
}

impl ModeKind {
    /// Label: "lateral", "axial", "torsional".
    pub fn label(self) -> &'static str {
        match self {
            ModeKind::Lateral => "lateral",
            ModeKind::Axial => "axial",
            ModeKind::Torsional => "torsional",
        }
    }
}

/// Short label of a mode: the whirl ("FW", "BW", "mixed") of a lateral mode, else the kind
/// ("axial", "torsional").
pub fn mode_label(kind: ModeKind, whirl: Whirl) -> &'static str {
    match kind {
        ModeKind::Lateral => whirl.label(),
        _ => kind.label(),
    }
}

/// One damped mode.
#[derive(Debug, Clone, Serialize)]
pub struct Mode {
    /// Damped natural frequency ω_d (rad/s).
    pub omega_d: f64,
    /// ω_d/(2π) (Hz).
    pub freq_hz: f64,
    /// Real part σ of the eigenvalue (1/s); negative is stable.
    pub sigma: f64,
    /// Damping ratio ζ = −σ/|λ|.
    pub damping_ratio: f64,
    /// Logarithmic decrement −2πσ/ω_d.
    pub log_dec: f64,
    /// Whirl direction ([`Whirl::NoWhirl`] for axial and torsional modes).
    pub whirl: Whirl,
    /// Lateral, axial or torsional.
    pub kind: ModeKind,
    /// Shares of the kinetic energy `φᴴ M φ` in the lateral, axial and torsional DOFs (sum 1).
    pub energy: [f64; 3],
    /// The orbit of every node as ROSS's κ: `(R_f − R_b)/(R_f + R_b)` with the forward and
    /// backward circle radii `R_f = |φ_x + iφ_y|/2`, `R_b = |φ_x − iφ_y|/2` — ± minor/major
    /// semi-axis, positive for a forward orbit (sign of `Im(φ_x φ̄_y)`), 0 for a straight line or
    /// a node at rest. ROSS calls a mode forward (backward) when every node's κ is > 0 (≤ 0),
    /// else mixed; [`Mode::whirl`] weighs the nodes by their motion instead.
    pub kappa: Vec<f64>,
    /// Normalised displacement shape `[φ_x, φ_y]` per node (largest component of the mode,
    /// lateral, axial or torsional, is 1).
    #[serde(skip)]
    pub shape: Vec<[Complex64; 2]>,
    /// Axial shape `φ_z` per node, same scale (empty without axial DOFs).
    #[serde(skip)]
    pub shape_axial: Vec<Complex64>,
    /// Torsional shape `φ_θz` per node, same scale (empty without torsional DOFs).
    #[serde(skip)]
    pub shape_torsion: Vec<Complex64>,
    /// Rotations `[φ_θx, φ_θy]` per node, same scale (empty for a Jeffcott rotor): with the
    /// displacements they make the full shape that Campbell tracking compares.
    #[serde(skip)]
    pub shape_tilt: Vec<[Complex64; 2]>,
}

impl Mode {
    /// Short label (see [`mode_label`]).
    pub fn label(&self) -> &'static str {
        mode_label(self.kind, self.whirl)
    }
}

/// `u_z` and `θ_z` DOF per node (empty for a Jeffcott rotor or when off).
fn scalar_dofs(rotor: &Rotor) -> (Vec<usize>, Vec<usize>) {
    match rotor {
        Rotor::Fe(f) => (
            f.rotor.node_axial.iter().flatten().copied().collect(),
            f.rotor.node_torsion.iter().flatten().copied().collect(),
        ),
        Rotor::Jeffcott(_) => (Vec::new(), Vec::new()),
    }
}

/// Results of a modal analysis at one speed.
#[derive(Debug, Clone, Serialize)]
pub struct ModalResults {
    /// Spin speed Ω (rad/s).
    pub speed: f64,
    /// Rigid-body modes (ω = 0) of free axial or torsional DOFs, by kind: not in `modes`.
    pub rigid_body: Vec<ModeKind>,
    /// Modes sorted by ω_d (positive-frequency members of the conjugate pairs).
    pub modes: Vec<Mode>,
}

/// [`Mode::kappa`] of each node of `shape`.
fn orbit_kappa(shape: &[[Complex64; 2]]) -> Vec<f64> {
    let i = Complex64::new(0.0, 1.0);
    shape
        .iter()
        .map(|[x, y]| {
            let (f, b) = ((x + i * y).norm(), (x - i * y).norm());
            if f + b > 0.0 {
                (f - b) / (f + b)
            } else {
                0.0
            }
        })
        .collect()
}

fn whirl_of(shape: &[[Complex64; 2]]) -> Whirl {
    let (mut fwd, mut bwd) = (0.0, 0.0);
    for [x, y] in shape {
        let w = (x * y.conj()).im;
        if w > 0.0 {
            fwd += w;
        } else {
            bwd -= w;
        }
    }
    let tot = fwd + bwd;
    if tot <= 1e-12 {
        Whirl::Mixed
    } else if bwd < 0.05 * tot {
        Whirl::Forward
    } else if fwd < 0.05 * tot {
        Whirl::Backward
    } else {
        Whirl::Mixed
    }
}

pub use crate::model::fe_rotor::undamped_modes;

/// Shares of the kinetic energy `φᴴ M φ` of a mode `q` in its lateral, axial and torsional
/// DOFs (`group`: 0, 1, 2 per DOF; M has no entries between groups); all lateral when the
/// total is not positive.
fn energy_shares(m: &Csc, group: &[usize], q: &[Complex64]) -> [f64; 3] {
    let mut e = [0.0; 3];
    for (r, c, v) in m.triplets() {
        if group[r] == group[c] {
            e[group[r]] += (q[r].conj() * v * q[c]).re;
        }
    }
    let tot: f64 = e.iter().sum();
    if tot > 0.0 {
        [e[0] / tot, e[1] / tot, e[2] / tot]
    } else {
        [1.0, 0.0, 0.0]
    }
}

/// The kind of a mode: the DOF group holding the largest share of its energy (lateral on a
/// tie with it).
fn kind_of(energy: [f64; 3]) -> ModeKind {
    if energy[1] > energy[0] && energy[1] >= energy[2] {
        ModeKind::Axial
    } else if energy[2] > energy[0] && energy[2] > energy[1] {
        ModeKind::Torsional
    } else {
        ModeKind::Lateral
    }
}

/// Scales a mode shape so that its entry of largest modulus is 1; returns the divisor (1 for
/// a zero shape).
fn normalise(
    shape: &mut [[Complex64; 2]],
    shape_axial: &mut [Complex64],
    shape_torsion: &mut [Complex64],
) -> Complex64 {
    let big = shape
        .iter()
        .flat_map(|p| p.iter())
        .chain(shape_axial.iter())
        .chain(shape_torsion.iter())
        .fold(Complex64::new(0.0, 0.0), |b, v| {
            if v.norm() > b.norm() {
                *v
            } else {
                b
            }
        });
    if big.norm() > 0.0 {
        for p in shape.iter_mut() {
            p[0] /= big;
            p[1] /= big;
        }
        for v in shape_axial.iter_mut().chain(shape_torsion.iter_mut()) {
            *v /= big;
        }
        big
    } else {
        Complex64::new(1.0, 0.0)
    }
}

/// The undamped modes `(ω², Φ)` without the rigid-body modes of free axial and torsional DOFs,
/// and the kinds of those removed. Each rigid-body mode `r` is the column of largest
/// `|φᵀ M r|² / (rᵀ M r)` (1 for it, 0 for every other mode of a mass-normalised basis).
#[allow(clippy::type_complexity)]
fn elastic_modes(
    rotor: &Rotor,
    m: &Csc,
    k: &Csc,
) -> Result<(Vec<f64>, DMatrix<f64>, Vec<ModeKind>), ModelError> {
    let (lam, phi) = undamped_modes(m, k)?;
    let md = dense(m);
    let mut drop = Vec::new();
    let mut kinds = Vec::new();
    for (r, kind) in rotor
        .rigid_body_modes()
        .into_iter()
        .zip([ModeKind::Axial, ModeKind::Torsional])
    {
        let Some(r) = r else { continue };
        let mr = &md * DVector::from_vec(r);
        let best = (0..phi.ncols())
            .map(|j| (j, phi.column(j).dot(&mr).powi(2)))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        if let Some((j, _)) = best {
            drop.push(j);
            kinds.push(kind);
        }
    }
    let keep: Vec<usize> = (0..lam.len()).filter(|j| !drop.contains(j)).collect();
    let phi = DMatrix::from_fn(phi.nrows(), keep.len(), |r, c| phi[(r, keep[c])]);
    Ok((keep.iter().map(|&j| lam[j]).collect(), phi, kinds))
}

/// Rotors with at most this many (elastic) DOFs are solved on the full modal basis: exact, and
/// cheap at that size (the reduction's truncation error grows with Ω² and with damping that
/// couples the modes: 4e-7 of ω_d at 1000 rad/s on ROSS's `rotor_example` with 34 of its 40
/// modes, 1.6e-5 at 3000 rad/s on ROSS's `rotor_example_with_damping`, 202 elastic DOFs, with
/// 34).
pub const FULL_BASIS: usize = 256;

/// Damped modes at spin speed `omega` (rad/s): at most `nmodes`, lowest ω_d first.
///
/// Solved in the basis of the undamped modes (of the symmetric part of K; a skew part
/// (K − Kᵀ)/2 from cross-coupled bearing or seal stiffness, kxy ≠ kyx, enters the first-order
/// matrix projected on that basis): all of them up to [`FULL_BASIS`] DOFs, else the
/// lowest `max(2·nmodes + 10, 20)` (pseudo-modal reduction): the first-order matrix then spans only the
/// frequencies of interest and stays well conditioned even with very stiff supports. The
/// rigid-body modes of free axial or torsional DOFs are left out of the basis and listed in
/// [`ModalResults::rigid_body`] (exact when the damping does not couple them to the elastic
/// modes: Rayleigh damping of the assembly; ROSS's shaft-only α with disks does, weakly).
pub fn modal(rotor: &Rotor, omega: f64, nmodes: usize) -> Result<ModalResults, ModelError> {
    modal_in(rotor, omega, nmodes, &ModalBasis::new(rotor, omega)?)
}

/// The undamped modes a modal solve works in: the elastic modes `(ω², Φ)` of `K(Ω) φ = ω² M φ`
/// (mass-normalised, ascending) without the rigid-body modes of free axial and torsional DOFs,
/// and the kinds of those. It depends on Ω only through bearings tabulated over speed
/// ([`Rotor::speed_tabulated`]); otherwise one basis serves every speed
/// ([`ModalBasis::reusable`]), which is what makes a Campbell diagram of a large rotor cheap
/// (one dense symmetric eigenproblem instead of one per speed).
#[derive(Debug, Clone)]
pub struct ModalBasis {
    lam: Vec<f64>,
    phi: DMatrix<f64>,
    rigid_body: Vec<ModeKind>,
}

impl ModalBasis {
    /// The basis at spin speed `omega` (rad/s).
    ///
    /// # Errors
    /// [`ModelError::Singular`] when M is not positive definite.
    pub fn new(rotor: &Rotor, omega: f64) -> Result<Self, ModelError> {
        let (m, k, _, _) = rotor.matrices(omega)?;
        let (lam, phi, rigid_body) = elastic_modes(rotor, &m, &k)?;
        Ok(Self {
            lam,
            phi,
            rigid_body,
        })
    }

    /// True when the basis of one speed is the basis of every speed: K does not depend on Ω.
    pub fn reusable(rotor: &Rotor) -> bool {
        !rotor.speed_tabulated()
    }
}

/// [`modal`] in a given basis (built by [`ModalBasis::new`] at `omega`, or at any speed when
/// [`ModalBasis::reusable`]).
pub fn modal_in(
    rotor: &Rotor,
    omega: f64,
    nmodes: usize,
    basis: &ModalBasis,
) -> Result<ModalResults, ModelError> {
    let (m, k, c, g) = rotor.matrices(omega)?;
    let lam = &basis.lam;
    let nr = if lam.len() <= FULL_BASIS {
        lam.len()
    } else {
        lam.len().min((2 * nmodes + 10).max(20))
    };
    let phi = basis.phi.columns(0, nr).into_owned();
    let (a, scale) = first_order(lam, &phi, &dense(&Csc::lin_comb(1.0, &c, omega, &g)), &k);
    let evd = faer::linalg::solvers::Eigen::new_from_real(a.as_ref()).map_err(|e| {
        ModelError::Singular {
            what: "rotor eigenproblem".into(),
            detail: format!("{e:?}"),
        }
    })?;
    let s = evd.S();
    let u = evd.U();
    let groups = DofGroups::of(rotor, m.nrows());
    let n = nr;
    let mut modes = Vec::new();
    for j in 0..2 * n {
        let lam: Complex64 = s.column_vector()[j];
        if lam.im <= 1e-8 * (1.0 + lam.norm()) {
            continue;
        }
        let full = |dof: usize| -> Complex64 {
            (0..n).map(|r| u[(r, j)] / scale[r] * phi[(dof, r)]).sum()
        };
        modes.push(mode_of(rotor, &m, &groups, lam, full));
    }
    modes.sort_by(|a, b| a.omega_d.total_cmp(&b.omega_d));
    split_degenerate_pairs(&mut modes);
    modes.truncate(nmodes);
    Ok(ModalResults {
        speed: omega,
        rigid_body: basis.rigid_body.clone(),
        modes,
    })
}

/// The first-order matrix of the modal solve in the basis `phi` (the first `n` columns of the
/// undamped modes, `lam` their ω²) and the scale `s_r` of its state, for the damping and
/// gyroscopic matrix `ctot = C + ΩG` and the stiffness `k`.
///
/// State `[s_r η_r; η̇_r]` with `s_r = ω_r = √λ_r` (1 for a mode at zero frequency): the matrix
/// `[0, diag(s); −diag(λ/s), −Φᵀ(C + ΩG)Φ]` has entries of the order of ω rather than ω², so
/// its eigenvalues keep their relative accuracy next to very stiff modes (in the plain form
/// `[0, I; −Λ, −D]` the low damped modes of ROSS's `rotor_example_with_damping`,
/// ω²_max ~ 1e13, lost 2e-7 of ω_d and 2e-6 of ζ). The basis diagonalises the symmetric part
/// of K; the skew part `(K − Kᵀ)/2` — bearings and seals with kxy ≠ kyx — enters as
/// `Φᵀ K_a Φ` (zero, and skipped, for a symmetric K), divided by `s` like `λ`.
fn first_order(
    lam: &[f64],
    phi: &DMatrix<f64>,
    ctot: &DMatrix<f64>,
    k: &Csc,
) -> (faer::Mat<f64>, Vec<f64>) {
    let cr = phi.transpose() * ctot * phi;
    let kd = dense(k);
    let ka = (&kd - kd.transpose()) * 0.5;
    let kar = if ka.iter().any(|v| *v != 0.0) {
        Some(phi.transpose() * ka * phi)
    } else {
        None
    };
    let n = phi.ncols();
    let scale: Vec<f64> = lam
        .iter()
        .take(n)
        .map(|&l| if l > 0.0 { l.sqrt() } else { 1.0 })
        .collect();
    let a = faer::Mat::<f64>::from_fn(2 * n, 2 * n, |i, j| {
        if i < n {
            if j == i + n {
                scale[i]
            } else {
                0.0
            }
        } else if j < n {
            let skew = kar.as_ref().map_or(0.0, |ka| ka[(i - n, j)]);
            if i - n == j {
                -(lam[j] + skew) / scale[j]
            } else {
                -skew / scale[j]
            }
        } else {
            -cr[(i - n, j - n)]
        }
    });
    (a, scale)
}

/// The rotor's DOFs by group: the axial and torsional DOFs, and each DOF's group (0 lateral,
/// 1 axial, 2 torsional).
struct DofGroups {
    axial: Vec<usize>,
    torsion: Vec<usize>,
    group: Vec<usize>,
}

impl DofGroups {
    fn of(rotor: &Rotor, ndofs: usize) -> Self {
        let (axial, torsion) = scalar_dofs(rotor);
        let mut group = vec![0usize; ndofs];
        for &d in &axial {
            group[d] = 1;
        }
        for &d in &torsion {
            group[d] = 2;
        }
        Self {
            axial,
            torsion,
            group,
        }
    }
}

/// The mode of eigenvalue `lam = σ + iω_d` whose full eigenvector (displacement part, in the
/// rotor's DOFs) is `full(dof)`: its shapes by node and group, normalised to a largest entry
/// of 1, its kind by kinetic energy shares over the mass matrix `m`, its whirl.
fn mode_of(
    rotor: &Rotor,
    m: &Csc,
    groups: &DofGroups,
    lam: Complex64,
    full: impl Fn(usize) -> Complex64,
) -> Mode {
    let nodes = rotor.node_count();
    let (axial, torsion) = (&groups.axial, &groups.torsion);
    let mut shape: Vec<[Complex64; 2]> = (0..nodes)
        .map(|i| {
            let d = rotor.node_dofs(i);
            [full(d[0]), full(d[1])]
        })
        .collect();
    let mut shape_axial: Vec<Complex64> = axial.iter().map(|&d| full(d)).collect();
    let mut shape_torsion: Vec<Complex64> = torsion.iter().map(|&d| full(d)).collect();
    let mut shape_tilt: Vec<[Complex64; 2]> = match rotor {
        Rotor::Fe(_) => (0..nodes)
            .map(|i| [full(4 * i + 2), full(4 * i + 3)])
            .collect(),
        Rotor::Jeffcott(_) => Vec::new(),
    };
    let energy = if axial.is_empty() && torsion.is_empty() {
        [1.0, 0.0, 0.0]
    } else {
        let q: Vec<Complex64> = (0..m.nrows()).map(full).collect();
        energy_shares(m, &groups.group, &q)
    };
    let kind = kind_of(energy);
    let scale = normalise(&mut shape, &mut shape_axial, &mut shape_torsion);
    for t in shape_tilt.iter_mut().flatten() {
        *t /= scale;
    }
    let whirl = if kind == ModeKind::Lateral {
        whirl_of(&shape)
    } else {
        Whirl::NoWhirl
    };
    Mode {
        omega_d: lam.im,
        freq_hz: lam.im / (2.0 * std::f64::consts::PI),
        sigma: lam.re,
        damping_ratio: -lam.re / lam.norm(),
        log_dec: -2.0 * std::f64::consts::PI * lam.re / lam.im,
        whirl,
        kind,
        energy,
        kappa: orbit_kappa(&shape),
        shape,
        shape_axial,
        shape_torsion,
        shape_tilt,
    }
}

/// An isotropic rotor without gyroscopic split (at rest, or a mode without disk tilt) has
/// double eigenvalues; the solver returns an arbitrary basis of each pair. Rotate every such
/// pair into the two circular (forward and backward) combinations that extremise the whirl
/// form `W(ψ) = Σ_nodes Im(ψ_x ψ̄_y)`, a 2×2 Hermitian eigenproblem. Only lateral modes pair
/// (consecutive lateral modes in frequency order; axial and torsional ones in between are
/// skipped).
fn split_degenerate_pairs(modes: &mut [Mode]) {
    let lateral: Vec<usize> = (0..modes.len())
        .filter(|&i| modes[i].kind == ModeKind::Lateral)
        .collect();
    let mut k = 0;
    while k + 1 < lateral.len() {
        let (i, i2) = (lateral[k], lateral[k + 1]);
        let (a, b) = (&modes[i], &modes[i2]);
        let close = (a.omega_d - b.omega_d).abs() <= 1e-4 * a.omega_d.max(1e-12)
            && (a.sigma - b.sigma).abs() <= 1e-4 * a.omega_d.max(1e-12);
        if !close {
            k += 1;
            continue;
        }
        let (p, q) = (&a.shape, &b.shape);
        let two_i = Complex64::new(0.0, 2.0);
        let g = |u: &[[Complex64; 2]], v: &[[Complex64; 2]]| -> Complex64 {
            u.iter()
                .zip(v)
                .map(|(s, t)| (s[0] * t[1].conj() - t[0].conj() * s[1]) / two_i)
                .sum()
        };
        // H = Gᵀ with G_ij = Σ (φ_ix φ̄_jy − φ̄_jx φ_iy)/(2i).
        let h11 = g(p, p).re;
        let h22 = g(q, q).re;
        let h12 = g(q, p); // H_12 = G_21
        let mid = 0.5 * (h11 + h22);
        let rad = (0.25 * (h11 - h22).powi(2) + h12.norm_sqr()).sqrt();
        let vec_for = |lam: f64| -> [Complex64; 2] {
            let v = if h12.norm() > 1e-300 {
                [h12, Complex64::new(lam - h11, 0.0)]
            } else if (lam - h11).abs() <= (lam - h22).abs() {
                [Complex64::new(1.0, 0.0), Complex64::new(0.0, 0.0)]
            } else {
                [Complex64::new(0.0, 0.0), Complex64::new(1.0, 0.0)]
            };
            let n = (v[0].norm_sqr() + v[1].norm_sqr()).sqrt();
            [v[0] / n, v[1] / n]
        };
        let combine = |c: [Complex64; 2]| -> Vec<[Complex64; 2]> {
            p.iter()
                .zip(q)
                .map(|(s, t)| [c[0] * s[0] + c[1] * t[0], c[0] * s[1] + c[1] * t[1]])
                .collect()
        };
        let combine1 = |c: [Complex64; 2], s: &[Complex64], t: &[Complex64]| -> Vec<Complex64> {
            s.iter().zip(t).map(|(s, t)| c[0] * s + c[1] * t).collect()
        };
        let (cf, cb) = (vec_for(mid + rad), vec_for(mid - rad));
        let fw = combine(cf);
        let bw = combine(cb);
        let combine_tilt = |c: [Complex64; 2]| -> Vec<[Complex64; 2]> {
            a.shape_tilt
                .iter()
                .zip(&b.shape_tilt)
                .map(|(s, t)| [c[0] * s[0] + c[1] * t[0], c[0] * s[1] + c[1] * t[1]])
                .collect()
        };
        let (ti_fw, ti_bw) = (combine_tilt(cf), combine_tilt(cb));
        let (ax_fw, ax_bw) = (
            combine1(cf, &a.shape_axial, &b.shape_axial),
            combine1(cb, &a.shape_axial, &b.shape_axial),
        );
        let (to_fw, to_bw) = (
            combine1(cf, &a.shape_torsion, &b.shape_torsion),
            combine1(cb, &a.shape_torsion, &b.shape_torsion),
        );
        // Both members are lateral; the pair's energy shares apply to each combination.
        let energy = [0, 1, 2].map(|g| 0.5 * (a.energy[g] + b.energy[g]));
        let reshare = a.energy != b.energy;
        modes[i].shape = bw;
        modes[i].shape_axial = ax_bw;
        modes[i].shape_torsion = to_bw;
        modes[i].shape_tilt = ti_bw;
        modes[i].whirl = whirl_of(&modes[i].shape);
        modes[i].kappa = orbit_kappa(&modes[i].shape);
        modes[i2].shape = fw;
        modes[i2].shape_axial = ax_fw;
        modes[i2].shape_torsion = to_fw;
        modes[i2].shape_tilt = ti_fw;
        modes[i2].whirl = whirl_of(&modes[i2].shape);
        modes[i2].kappa = orbit_kappa(&modes[i2].shape);
        if reshare {
            modes[i].energy = energy;
            modes[i2].energy = energy;
        }
        // The combinations are unit combinations of normalised shapes: scale them back so that
        // their largest entry is 1, as every other mode's.
        for j in [i, i2] {
            let md = &mut modes[j];
            let scale = normalise(&mut md.shape, &mut md.shape_axial, &mut md.shape_torsion);
            for t in md.shape_tilt.iter_mut().flatten() {
                *t /= scale;
            }
        }
        k += 2;
    }
}

/// Modal assurance criterion of two complex shapes (1 = same shape).
pub fn mac(a: &[[Complex64; 2]], b: &[[Complex64; 2]]) -> f64 {
    let mut ab = Complex64::new(0.0, 0.0);
    let (mut aa, mut bb) = (0.0, 0.0);
    for (p, q) in a.iter().zip(b) {
        for c in 0..2 {
            ab += p[c].conj() * q[c];
            aa += p[c].norm_sqr();
            bb += q[c].norm_sqr();
        }
    }
    if aa == 0.0 || bb == 0.0 {
        0.0
    } else {
        ab.norm_sqr() / (aa * bb)
    }
}

/// MAC of two modes over their full shapes — displacements, rotations, axial and torsional
/// DOFs; modes of different groups have a MAC of 0 (the groups are uncoupled).
pub fn mode_mac(a: &Mode, b: &Mode) -> f64 {
    let mut ab = Complex64::new(0.0, 0.0);
    let (mut aa, mut bb) = (0.0, 0.0);
    let pairs = a
        .shape
        .iter()
        .flatten()
        .zip(b.shape.iter().flatten())
        .chain(
            a.shape_tilt
                .iter()
                .flatten()
                .zip(b.shape_tilt.iter().flatten()),
        )
        .chain(a.shape_axial.iter().zip(&b.shape_axial))
        .chain(a.shape_torsion.iter().zip(&b.shape_torsion));
    for (p, q) in pairs {
        ab += p.conj() * q;
        aa += p.norm_sqr();
        bb += q.norm_sqr();
    }
    if aa == 0.0 || bb == 0.0 {
        0.0
    } else {
        ab.norm_sqr() / (aa * bb)
    }
}
