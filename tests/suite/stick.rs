//! Coulomb friction with stick (`station.N.stick`, issue 28; docs/STICK.md): a Jeffcott rotor
//! in a ring on springs with mass rolls on it — dry whirl at `ω = −RΩ/δ` — while the rolling
//! speed is below the coupled natural frequency, and whips — slips, its whirl locked near that
//! frequency whatever the speed — above. Both steady whirls have closed forms in the frame
//! whirling with them (docs/STICK.md §3), which the runs match: frequency, radius, normal
//! force, the friction the roll needs (inside the cone) and the whip's (on it), first-order
//! convergence of the whip in Δt, and no chattering between stick and slip.

use crate::common;

use common::complex::{abs, add, div, mul, C};

use common::{case_and_plan, scene_model};
use rubsim::analysis::dry::DryRub;
use rubsim::math::loglog_slope;
use rubsim::time::{integrate, Initial, Record, RunStats, Scheme};

/// The rig: rotor m = 1 kg, k = 1 N/m, c = 0.1 N·s/m (ξ 0.05, ω_n = 1 rad/s), no unbalance;
/// section R = 0.05 m; ring m_s = 0.1 kg, k_s = 100 N/m, c_s = 0.5 N·s/m at δ = 0.01 m, so the
/// roll runs at 5 Ω and exists for 0.2 < Ω < 1.92 rad/s (the coupled frequency
/// √((k + k_s)/(m + m_s)) = 9.58 rad/s over R/δ).
const M: f64 = 1.0;
const K: f64 = 1.0;
const CR: f64 = 0.1;
const MS: f64 = 0.1;
const KS: f64 = 100.0;
const CS: f64 = 0.5;
const DELTA: f64 = 0.01;
const R: f64 = 0.05;

/// The rotor's and the ring's dynamic stiffness at whirl frequency `w` (rad/s),
/// `k − m ω² + i c ω`, with a ring of mass `ms` and damping `cs`, the rotor's damping `cr`.
fn stiffness_with(w: f64, ms: f64, cs: f64, cr: f64) -> (C, C) {
    ((K - M * w * w, cr * w), (KS - ms * w * w, cs * w))
}

/// The rolling whirl (docs/STICK.md §3.1) at spin `omega`: its frequency `ω = −RΩ/δ`, the
/// rotor's and the ring's whirl radii (m), the normal force `p` (N) and the friction it needs
/// over the normal force `t/p`.
fn rolling(omega: f64) -> (f64, f64, f64, f64, f64) {
    rolling_with(omega, MS, CS)
}

/// [`rolling`] in a ring of mass `ms` and damping `cs`.
fn rolling_with(omega: f64, ms: f64, cs: f64) -> (f64, f64, f64, f64, f64) {
    rolling_damped(omega, ms, cs, CR)
}

/// [`rolling_with`] with the rotor's damping `cr`.
fn rolling_damped(omega: f64, ms: f64, cs: f64, cr: f64) -> (f64, f64, f64, f64, f64) {
    let w = -R * omega / DELTA;
    let (dr, ds) = stiffness_with(w, ms, cs, cr);
    // z_r − z_s = δ with D_r z_r = −f, D_s z_s = f: f = −δ D_r D_s/(D_r + D_s).
    let f = mul((-DELTA, 0.0), div(mul(dr, ds), add(dr, ds)));
    let (zr, zs) = (abs(div(f, dr)), abs(div(f, ds)));
    (w, zr, zs, f.0, f.1 / f.0)
}

/// The whip (docs/STICK.md §3.2) with the ring's damping `cs`: the slipping backward whirl,
/// `f = p(1 + iμ)`, at the root of `Im[(1 + iμ)(D_r + D_s)/(D_r D_s)] = 0` near the coupled
/// frequency; its frequency, the rotor's and the ring's radii and `p`.
fn whip(mu: f64, cs: f64) -> (f64, f64, f64, f64) {
    let g = |w: f64| {
        let (dr, ds) = stiffness_with(w, MS, cs, CR);
        mul((1.0, mu), div(add(dr, ds), mul(dr, ds)))
    };
    let (mut a, mut b) = (-6.0, -9.5);
    assert!(g(a).1.signum() != g(b).1.signum(), "no root bracketed");
    for _ in 0..200 {
        let mid = 0.5 * (a + b);
        if g(mid).1.signum() == g(a).1.signum() {
            a = mid;
        } else {
            b = mid;
        }
    }
    let p = -DELTA / g(a).0;
    let (dr, ds) = stiffness_with(a, MS, cs, CR);
    let f = (p, p * mu);
    (a, abs(div(f, dr)), abs(div(f, ds)), p)
}

fn scene(mu: f64) -> String {
    format!(
        r#"
[rotor]
kind = "jeffcott"
mass = {M}
stiffness = {K}
damping = {CR}
[[station]]
name = "s"
radius = {R}
friction = {mu}
stick = true
[[stator]]
kind = "ring"
name = "ring"
station = "s"
clearance = {DELTA}
stiffness = {KS}
mass = {MS}
damping = {CS}
[run]
speed = 1.0
revolutions = 40
transient_revolutions = 20
error_estimate = false
check_coexistence = false
"#
    )
}

/// The run at spin `omega` (rad/s) with `kind` at step `dt`, started touching the ring and
/// whirling backward at the rolling speed.
fn whirl_run(mu: f64, omega: f64, kind: Scheme, dt: f64, revs: usize) -> (Record, RunStats) {
    whirl_run_with(mu, omega, kind, dt, revs, &[])
}

/// [`whirl_run`] with more overrides.
fn whirl_run_with(
    mu: f64,
    omega: f64,
    kind: Scheme,
    dt: f64,
    revs: usize,
    more: &[&str],
) -> (Record, RunStats) {
    let mut sets = vec![
        format!("run.dt={dt}"),
        format!("run.revolutions={revs}"),
        format!("run.transient_revolutions={}", revs / 2),
    ];
    sets.extend(more.iter().map(|s| s.to_string()));
    let (ls, model) = scene_model(&scene(mu), &sets);
    let (case, plan) = case_and_plan(&ls, &model, omega, kind);
    let r0 = 1.05 * DELTA;
    let init = Initial {
        u: [r0, 0.0],
        v: [0.0, -R * omega / DELTA * r0],
    };
    integrate(&case, kind, &plan, init).unwrap()
}

/// Over the recorded samples from `from` on: the whirl frequency (rad/s, from the unwrapped
/// angle of the rotor's position) and the ranges of the rotor's radius (m), the normal force
/// (N), the ring centre's radius (m: `x_C − δ n`, `n` from the normal force) and `|t|/p`.
struct Whirl {
    freq: f64,
    radius: [f64; 2],
    normal: [f64; 2],
    ring: [f64; 2],
    friction: [f64; 2],
    /// The recorded friction power's range (W).
    power: [f64; 2],
}

fn whirl_of(rec: &Record, from: usize) -> Whirl {
    let last = rec.len() - 1;
    let (mut angle, mut prev) = (0.0, None::<f64>);
    let span = [f64::INFINITY, 0.0];
    let mut w = Whirl {
        freq: 0.0,
        radius: span,
        normal: span,
        ring: span,
        friction: span,
        power: [f64::INFINITY, f64::NEG_INFINITY],
    };
    let range = |r: &mut [f64; 2], v: f64| {
        r[0] = r[0].min(v);
        r[1] = r[1].max(v);
    };
    for i in from..=last {
        let u = rec.disp_at(i, 0);
        let th = u[1].atan2(u[0]);
        if let Some(p) = prev {
            let mut d = th - p;
            d -= (d / std::f64::consts::TAU).round() * std::f64::consts::TAU;
            angle += d;
        }
        prev = Some(th);
        range(&mut w.radius, u[0].hypot(u[1]));
        // The force on the rotor is −n p − a t.
        let (f, fnorm) = (rec.force_at(i, 0), rec.force_normal[i]);
        let p = fnorm[0].hypot(fnorm[1]);
        let t = (f[0] - fnorm[0]).hypot(f[1] - fnorm[1]);
        range(&mut w.normal, p);
        range(&mut w.friction, t / p);
        let n = [-fnorm[0] / p, -fnorm[1] / p];
        range(
            &mut w.ring,
            (u[0] - DELTA * n[0]).hypot(u[1] - DELTA * n[1]),
        );
        range(&mut w.power, rec.friction_power_at(i, 0));
    }
    w.freq = angle / (rec.t[last] - rec.t[from]);
    w
}

/// The samples of the second half of a record.
fn second_half(rec: &Record) -> usize {
    rec.len() / 2
}

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

/// Checks a rolling run against the closed form `want = (ω, z_r, z_s, p, t/p)`: the whirl to
/// `tol[0]`, the radii and the normal force to `tol[1]`, the friction to `tol[2]` (relative),
/// every instant of the steady window in stick (no chattering into slip), no penetration.
fn assert_rolls(
    tag: &str,
    rec: &Record,
    stats: &RunStats,
    want: (f64, f64, f64, f64, f64),
    tol: [f64; 3],
) {
    let got = whirl_of(rec, second_half(rec));
    let (w, zr, zs, p, need) = want;
    assert!(
        rel(got.freq, w) < tol[0],
        "{tag}: whirl {} vs {w} rad/s",
        got.freq
    );
    assert_eq!(
        stats.steady.contact_instants, stats.steady.instants,
        "{tag}"
    );
    assert_eq!(stats.steady.stick_instants, stats.steady.instants, "{tag}");
    for (name, r, want, tol) in [
        ("rotor radius", got.radius, zr, tol[1]),
        ("ring radius", got.ring, zs, tol[1]),
        ("normal force", got.normal, p, tol[1]),
        ("friction t/p", got.friction, need, tol[2]),
    ] {
        assert!(
            rel(r[0], want) < tol && rel(r[1], want) < tol,
            "{tag}: {name} {:.6e}..{:.6e}, closed form {want:.6e}",
            r[0],
            r[1]
        );
    }
    assert!(
        stats.min_gap > -1e-6 * DELTA,
        "{tag}: penetration {:.3e}",
        -stats.min_gap
    );
}

#[test]
fn rolling_whirl_matches_its_closed_form_in_every_scheme() {
    let omega = 0.6;
    let want = rolling(omega);
    assert!(
        want.4.abs() < 0.3 && want.3 > 0.0,
        "the roll exists at μ = 0.3"
    );
    // Generalised-α (the implicit scheme a stator with mass takes): second order, the force
    // imposed at tₙ₊₁.
    let ga = Scheme::GeneralizedAlpha {
        rho_inf: rubsim::time::STATOR_WITH_MASS_RHO_INF,
    };
    let (rec, stats) = whirl_run(0.3, omega, ga, 2e-3, 30);
    assert_rolls("generalised-α", &rec, &stats, want, [2e-5, 1e-4, 1e-4]);
    // Forward increment: the whirl, radii and force to second order, but the friction the roll
    // needs to first order — the multipliers of step n act along the normal frozen at tₙ₊₁, a
    // lag of ω Δt that tilts the force by p ω Δt: t/p is 14 % high at Δt = 2 ms. Its errors
    // halve with Δt and their Richardson extrapolation meets the closed form.
    let mut ratios = Vec::new();
    for dt in [1e-3, 5e-4] {
        let (rec, stats) = whirl_run(0.3, omega, Scheme::ForwardIncrement, dt, 30);
        assert_rolls("forward increment", &rec, &stats, want, [2e-5, 2e-4, 0.08]);
        ratios.push(whirl_of(&rec, second_half(&rec)).friction[1]);
    }
    let extrapolated = 2.0 * ratios[1] - ratios[0];
    assert!(
        rel(extrapolated, want.4) < 2e-3,
        "t/p {ratios:?} → {extrapolated} vs {}",
        want.4
    );
    let (e1, e2) = (ratios[0] - want.4, ratios[1] - want.4);
    assert!(
        (e1 / e2 - 2.0).abs() < 0.1,
        "first order: errors {e1:.3e}, {e2:.3e}"
    );
    // A massless ring in the collocated scheme: the static solve at tₙ with the rotor held, the
    // ring alone following the section's surface while it sticks.
    let want = rolling_with(omega, 0.0, 0.0);
    let massless = ["stator.0.mass=0.0", "stator.0.damping=0.0"];
    let (rec, stats) = whirl_run_with(0.3, omega, Scheme::Collocated, 1e-3, 30, &massless);
    assert_rolls(
        "collocated, massless ring",
        &rec,
        &stats,
        want,
        [2e-5, 2e-4, 6e-3],
    );
}

#[test]
fn the_roll_ends_where_the_friction_it_needs_reaches_the_cone() {
    // With μ = 0.1 the roll's friction t/p (rising with the speed toward the coupled
    // frequency) reaches the cone at Ω_c = 1.5369 rad/s, before its normal force vanishes:
    // just below, every instant sticks and the friction sits just inside the cone; just above,
    // the pair slips at the cone and the rotor whips.
    let mu = 0.1;
    let (mut lo, mut hi) = (1.0, 1.7);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if rolling(mid).4 < mu {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    assert!(
        (lo - 1.5369).abs() < 1e-4 && rolling(lo).3 > 0.0,
        "Ω_c = {lo}"
    );
    let ga = Scheme::GeneralizedAlpha {
        rho_inf: rubsim::time::STATOR_WITH_MASS_RHO_INF,
    };
    // (Near the coupled frequency the radii are ten times as sensitive to the scheme's
    // (ωΔt)²/6 in the whirl: Δt = 0.5 ms.)
    let below = 0.98 * lo;
    let (rec, stats) = whirl_run(mu, below, ga, 5e-4, 40);
    assert_rolls(
        "just below the cone",
        &rec,
        &stats,
        rolling(below),
        [2e-5, 1e-4, 1e-4],
    );
    assert!(whirl_of(&rec, second_half(&rec)).friction[1] < mu);
    let (rec, stats) = whirl_run(mu, 1.02 * lo, ga, 1e-3, 40);
    let got = whirl_of(&rec, second_half(&rec));
    assert!(
        stats.steady.stick_fraction() < 0.5 && rel(got.friction[1], mu) < 1e-9,
        "just above the cone: stick {}, t/p up to {}",
        stats.steady.stick_fraction(),
        got.friction[1]
    );
    assert!(
        got.freq > -5.0 * 1.02 * lo,
        "slipping backward: whirl {}",
        got.freq
    );
}

#[test]
fn a_driven_rotor_settles_where_its_drive_balances_the_roll() {
    // A driven rotor (its spin a DOF, J = 1e-3 kg·m²) with a constant drive T_d and a viscous
    // drag c_d Ω, rolling in the massless ring: the friction the roll needs brakes the spin by
    // R t(Ω) (rising with Ω), so the speed settles where T_d = c_d Ω + R t(Ω) — here at
    // Ω* = 0.6 rad/s, from a roll started at 0.5 rad/s — and the rotor rolls there as the
    // roll's closed form at that speed says. Collocated scheme (explicit, as a driven spin
    // needs; second order with a massless ring).
    let (omega, cd, j) = (0.6, 1e-4, 1e-3);
    let want = rolling_with(omega, 0.0, 0.0);
    let td = cd * omega + R * want.3 * want.4;
    let start = 0.5;
    let r0 = 1.05 * DELTA;
    let text = scene(0.3).replace("speed = 1.0\n", "").replace(
        "[run]\n",
        &format!(
            "[run.speed_profile]\nkind = \"driven\"\nunit = \"rad_per_s\"\nspeed = {start}\nduration = 150.0\n\
             drive_torque = {td}\ndrag_coefficient = {cd}\npolar_inertia = {j}\n\n[run]\n"
        ),
    );
    let sets = [
        "stator.0.mass=0.0".to_string(),
        "stator.0.damping=0.0".to_string(),
        "run.integrator=\"collocated\"".to_string(),
        "run.dt=1e-3".to_string(),
        format!("run.initial_displacement=[{r0}, 0.0]"),
        format!("run.initial_velocity=[0.0, {}]", -R * start / DELTA * r0),
    ];
    let (ls, model) = scene_model(&text, &sets);
    let spec = ls.scene.run.speed_profile.as_ref().unwrap();
    let r = rubsim::analysis::prepare_transient(&model, &common::settings(&ls), spec)
        .unwrap()
        .run(&mut [])
        .unwrap();
    // The last fifth of the run: the speed settled, every contact sample in stick, the whirl at
    // −RΩ*/δ, the rotor's radius the closed form's.
    let from = 4 * r.spin.len() / 5;
    let last = &r.spin[from..];
    let (lo, hi) = last.iter().fold((f64::INFINITY, 0.0_f64), |(a, b), s| {
        (a.min(s[1]), b.max(s[1]))
    });
    assert!(
        rel(lo, omega) < 2e-4 && rel(hi, omega) < 2e-4,
        "Ω {lo} … {hi}, balance at {omega}"
    );
    assert!(r.contact_state[from..].iter().all(|c| c[0] > 0 && c[1] > 0));
    let radius = r.response[from..]
        .iter()
        .map(|u| u[0].hypot(u[1]))
        .fold((f64::INFINITY, 0.0_f64), |(a, b), v| (a.min(v), b.max(v)));
    assert!(
        rel(radius.0, want.1) < 1e-4 && rel(radius.1, want.1) < 1e-4,
        "radius {radius:?} vs {}",
        want.1
    );
    // The drive's power goes into the rotor's damper, c ω² |z_r|², none into heat.
    let heat = r.contact[from..]
        .iter()
        .map(|c| c[1].abs())
        .fold(0.0, f64::max);
    assert!(heat < 1e-6 * td * omega, "friction power {heat:e} W");
}

#[test]
fn a_ring_rolls_again_above_its_own_natural_frequency() {
    // p = Re f > 0 in two windows of the whirl frequency (docs/STICK.md §3.1): between the
    // rotor's natural frequency and the coupled one (the ring stiffness-controlled), and above
    // the ring's own √(k_s/m_s) (both bodies mass-controlled: they orbit their common centre of
    // mass, the contact force the centripetal force, the rotor's radius → δ m_s/(m + m_s)).
    // A ring of the rotor's mass: windows 1 < |ω| < 7.11 and |ω| > 10 rad/s, a whip between.
    // Damped more (rotor 0.2, ring 1 N·s/m) than the rig, so that the start's transient dies
    // out in the first half of the run.
    let (ms, cs, cr) = (1.0, 1.0, 0.2);
    let p_at = |omega: f64| rolling_damped(omega, ms, cs, cr).3;
    assert!(p_at(0.6) > 0.0 && p_at(1.6) < 0.0 && p_at(4.0) > 0.0);
    let ga = Scheme::GeneralizedAlpha {
        rho_inf: rubsim::time::STATOR_WITH_MASS_RHO_INF,
    };
    let heavy = [
        "stator.0.mass=1.0",
        "stator.0.damping=1.0",
        "rotor.damping=0.2",
    ];
    // Above the ring's frequency: ω = −20 rad/s, the rotor at 4.30 mm, the ring at 5.70 mm
    // (δ = 10 mm apart, on either side of their centre of mass), p = 1.71 N, t/p = 0.047.
    let want = rolling_damped(4.0, ms, cs, cr);
    assert!(want.1 < 0.5 * DELTA && want.4.abs() < 0.3);
    // (The scheme's rolling error is (ωΔt)²/6 in the whirl: 2e-5 at Δt = 0.5 ms.)
    let (rec, stats) = whirl_run_with(0.3, 4.0, ga, 5e-4, 80, &heavy);
    // The force ∝ ω² carries the scheme's error twice: 1.4e-4 at this step.
    assert_rolls(
        "above the ring's frequency",
        &rec,
        &stats,
        want,
        [2e-5, 2e-4, 2e-4],
    );
    // And in the lower window, as the light ring's.
    let (rec, stats) = whirl_run_with(0.3, 0.6, ga, 2e-3, 30, &heavy);
    let want = rolling_damped(0.6, ms, cs, cr);
    assert_rolls(
        "below the coupled frequency",
        &rec,
        &stats,
        want,
        [2e-5, 1e-4, 1e-4],
    );
    // Between the windows no roll: the same start slips.
    let (_, stats) = whirl_run_with(0.3, 1.6, ga, 1e-3, 40, &heavy);
    assert!(
        stats.steady.stick_fraction() < 0.5,
        "stick {} in the gap",
        stats.steady.stick_fraction()
    );
}

/// The rolling whirl in a ring whose springs and dashpots differ along x and y (`k_x`, `k_y`,
/// `c_x`, `c_y`; docs/STICK.md §3.3) at spin `omega`: the normal turns uniformly, `n = e^{iωt}`
/// with `ω = −RΩ/δ` exactly — rolling fixes the relative position's angle, whatever the ring
/// does —, so the rotor's and the ring's motions are the steady responses of linear equations
/// to that prescribed relative motion, each component apart: `(D_r + D_s,x) X = δ D_s,x`,
/// `(D_r + D_s,y) Y = −iδ D_s,y`, `x_r = Re(X e^{iωt})`, `y_r = Re(Y e^{iωt})`, the force on
/// the ring `f = −D_r (X, Y)`. The normal force `p = f·n` and the friction `t = f·a` are then
/// a mean and a line at 2ω each. Returns ω, the rotor's and the ring's x and y amplitudes (m),
/// `[mean, 2ω amplitude]` of `p` and of `t` (N), and the range of `t/p` over a whirl.
fn rolling_anisotropic(omega: f64, k: [f64; 2], c: [f64; 2]) -> AnisotropicRoll {
    let w = -R * omega / DELTA;
    let (dr, _) = stiffness_with(w, MS, CS, CR);
    let ds = |i: usize| (k[i] - MS * w * w, c[i] * w);
    let x = div(mul((DELTA, 0.0), ds(0)), add(dr, ds(0)));
    let y = div(mul((0.0, -DELTA), ds(1)), add(dr, ds(1)));
    let (fx, fy) = (mul((-1.0, 0.0), mul(dr, x)), mul((-1.0, 0.0), mul(dr, y)));
    // The ring's amplitudes: z_s = z_r − δ n, n = (cos ωt, sin ωt) = Re((1, −i) e^{iωt}).
    let (sx, sy) = (add(x, (-DELTA, 0.0)), add(y, (0.0, DELTA)));
    // Over one whirl: the means and 2ω lines of p and t by their sums, the range of t/p.
    let n = 3600;
    let (mut sums, mut tp) = ([(0.0, 0.0); 4], [f64::INFINITY, f64::NEG_INFINITY]);
    for j in 0..n {
        let th = std::f64::consts::TAU * j as f64 / n as f64;
        let e = (th.cos(), th.sin());
        let f = [mul(fx, e).0, mul(fy, e).0];
        let pn = f[0] * th.cos() + f[1] * th.sin();
        let t = -f[0] * th.sin() + f[1] * th.cos();
        let e2 = ((2.0 * th).cos(), -(2.0 * th).sin());
        for (k, v) in [pn, t].iter().enumerate() {
            sums[2 * k] = add(sums[2 * k], (*v, 0.0));
            sums[2 * k + 1] = add(sums[2 * k + 1], mul((*v, 0.0), e2));
        }
        tp = [tp[0].min(t / pn), tp[1].max(t / pn)];
    }
    let nf = n as f64;
    AnisotropicRoll {
        w,
        amp: [abs(x), abs(y), abs(sx), abs(sy)],
        p: [sums[0].0 / nf, 2.0 * abs(sums[1]) / nf],
        t: [sums[2].0 / nf, 2.0 * abs(sums[3]) / nf],
        tp,
    }
}

/// [`rolling_anisotropic`]'s closed form.
struct AnisotropicRoll {
    w: f64,
    amp: [f64; 4],
    p: [f64; 2],
    t: [f64; 2],
    tp: [f64; 2],
}

/// The least-squares fit `v ≈ m + a cos ωt + b sin ωt` over the samples `(t, v)`: `[m, |(a, b)|]`.
fn line_fit(t: &[f64], v: &[f64], w: f64) -> [f64; 2] {
    // Normal equations of the three columns 1, cos, sin (row-major).
    let (mut a, mut x, mut piv) = ([0.0; 9], [0.0; 3], [0; 3]);
    for (ti, vi) in t.iter().zip(v) {
        let col = [1.0, (w * ti).cos(), (w * ti).sin()];
        for i in 0..3 {
            x[i] += col[i] * vi;
            for j in 0..3 {
                a[3 * i + j] += col[i] * col[j];
            }
        }
    }
    assert!(rubsim::math::lu_in_place(&mut a, 3, &mut piv, 1e-14));
    rubsim::math::lu_solve(&a, 3, &piv, &mut x);
    [x[0], x[1].hypot(x[2])]
}

#[test]
fn an_anisotropic_ring_rolls_as_its_closed_form() {
    // k_y = 0.6 k_x, c_y = 2 c_x: the orbit is an ellipse, the normal force swings by a quarter
    // and the friction the roll needs changes sign over each whirl (−0.06 … +0.20 of p), inside
    // the cone μ = 0.3 throughout.
    let (omega, k, c) = (1.0, [KS, 60.0], [CS, 1.0]);
    let want = rolling_anisotropic(omega, k, c);
    assert!(want.p[0] > want.p[1] && want.tp[0] > -0.3 && want.tp[1] < 0.3);
    assert!(want.tp[0] < -0.05 && want.tp[1] > 0.15, "{:?}", want.tp);
    let aniso = ["stator.0.stiffness_y=60.0", "stator.0.damping_y=1.0"];
    let ga = Scheme::GeneralizedAlpha {
        rho_inf: rubsim::time::STATOR_WITH_MASS_RHO_INF,
    };
    let (rec, stats) = whirl_run_with(0.3, omega, ga, 1e-3, 40, &aniso);
    assert_eq!(stats.steady.stick_instants, stats.steady.instants);
    let from = second_half(&rec);
    let got = whirl_of(&rec, from);
    let w = want.w;
    assert!(rel(got.freq, w) < 2e-5, "whirl {} vs {w} rad/s", got.freq);
    // Per sample: the rotor's and the ring's x and y, the normal force and the signed friction.
    let mut cols = vec![Vec::new(); 6];
    for i in from..rec.len() {
        let (u, f, fnorm) = (rec.disp_at(i, 0), rec.force_at(i, 0), rec.force_normal[i]);
        let pn = fnorm[0].hypot(fnorm[1]);
        // The force on the rotor is −(n p + a t), a = ẑ × n.
        let n = [-fnorm[0] / pn, -fnorm[1] / pn];
        let t = -((f[0] - fnorm[0]) * -n[1] + (f[1] - fnorm[1]) * n[0]);
        let ring = [u[0] - DELTA * n[0], u[1] - DELTA * n[1]];
        for (c, v) in cols.iter_mut().zip([u[0], u[1], ring[0], ring[1], pn, t]) {
            c.push(v);
        }
    }
    let ts = &rec.t[from..];
    for (j, name) in ["rotor x", "rotor y", "ring x", "ring y"]
        .iter()
        .enumerate()
    {
        let fit = line_fit(ts, &cols[j], w);
        assert!(
            rel(fit[1], want.amp[j]) < 1e-4,
            "{name}: {:.6e} vs closed form {:.6e}",
            fit[1],
            want.amp[j]
        );
    }
    for (j, name, want) in [(4, "p", want.p), (5, "t", want.t)] {
        let fit = line_fit(ts, &cols[j], 2.0 * w);
        for (part, g, v) in [("mean", fit[0], want[0]), ("2ω line", fit[1], want[1])] {
            assert!(
                (g - v).abs() < 2e-4 * want[0].abs().max(want[1]),
                "{name} {part}: {g:.6e} vs closed form {v:.6e}"
            );
        }
    }
}

/// The ring's damping of the whip tests (N·s/m): the circular whip is then the attractor; at
/// the rig's 0.5 N·s/m it is modulated, stick and slip alternating (docs/STICK.md §3.3).
const CS_WHIP: f64 = 2.0;

#[test]
fn whip_locks_near_the_coupled_frequency_whatever_the_speed() {
    let mu = 0.3;
    let (w, zr, zs, p) = whip(mu, CS_WHIP);
    let damped = ["stator.0.damping=2.0"];
    let ga = Scheme::GeneralizedAlpha {
        rho_inf: rubsim::time::STATOR_WITH_MASS_RHO_INF,
    };
    for omega in [2.5, 4.0] {
        let (rec, stats) = whirl_run_with(mu, omega, ga, 1e-3, 60, &damped);
        let got = whirl_of(&rec, second_half(&rec));
        // Slipping: the friction on the cone, no instant in stick, and the whirl the closed
        // form's whatever the speed (locked).
        let tag = format!("Ω = {omega}");
        assert_eq!(stats.steady.stick_instants, 0, "{tag}");
        assert!(rel(got.friction[0], mu) < 1e-9 && rel(got.friction[1], mu) < 1e-9);
        assert!(rel(got.freq, w) < 1e-4, "{tag}: whirl {} vs {w}", got.freq);
        for (name, r, want) in [
            ("rotor radius", got.radius, zr),
            ("ring radius", got.ring, zs),
            ("normal force", got.normal, p),
        ] {
            assert!(
                rel(r[0], want) < 1e-3 && rel(r[1], want) < 1e-3,
                "{tag}: {name} {r:?} vs {want}"
            );
        }
    }
    // Forward increment: first order in Δt (fitted slope).
    let dts = [2e-3, 1e-3, 5e-4];
    let mut errs = Vec::new();
    for dt in dts {
        let (rec, _) = whirl_run_with(mu, 4.0, Scheme::ForwardIncrement, dt, 60, &damped);
        let got = whirl_of(&rec, second_half(&rec));
        errs.push(rel(got.freq, w).max(rel(0.5 * (got.radius[0] + got.radius[1]), zr)));
    }
    let slope = loglog_slope(&dts, &errs);
    assert!(
        (slope - 1.0).abs() < 0.15,
        "order {slope:.3} (errors {errs:?})"
    );
}

#[test]
fn runs_tell_dry_whirl_from_dry_whip() {
    let text = scene(0.3);
    let start = |omega: f64| {
        let r0 = 1.05 * DELTA;
        vec![
            format!("run.speed={omega}"),
            "run.dt=2e-3".to_string(),
            format!("run.initial_displacement=[{r0}, 0.0]"),
            format!("run.initial_velocity=[0.0, {}]", -R * omega / DELTA * r0),
        ]
    };
    let (ls, model) = scene_model(&text, &start(0.6));
    let settings = common::settings(&ls);
    let req = settings.request(0.6);
    let r = rubsim::analysis::run_speed(&model, &req, Default::default()).unwrap();
    assert_eq!(r.dry_rub, Some(DryRub::Whirl), "Ω = 0.6");
    assert_eq!(r.stick_fraction, Some(1.0));
    // R/δ = 5 is a whole number: the roll repeats every revolution in theory, but the scheme's
    // phase error turns its Poincaré points; judged by its extents, it is steady at once.
    assert!(
        r.steady && r.transient_revolutions < 50 && r.stationarity.attractor.is_some(),
        "steady {} after {} revolutions",
        r.steady,
        r.transient_revolutions
    );
    assert_eq!(rubsim::analysis::regime_label(&r), "dry whirl");
    let (ls, model) = scene_model(&text, &start(4.0));
    let req = common::settings(&ls).request(4.0);
    let r = rubsim::analysis::run_speed(&model, &req, Default::default()).unwrap();
    assert_eq!(r.dry_rub, Some(DryRub::Whip), "Ω = 4");
    assert_eq!(r.stick_fraction, Some(0.0));
    assert_eq!(rubsim::analysis::regime_label(&r), "dry whip");
    // Permanent slip cannot roll: the same start at Ω = 0.6 leaves no dry whirl behind.
    let (ls, model) = scene_model(
        &text,
        &[start(0.6), vec!["station.0.stick=false".into()]].concat(),
    );
    let req = common::settings(&ls).request(0.6);
    let r = rubsim::analysis::run_speed(&model, &req, Default::default()).unwrap();
    assert_eq!((r.dry_rub, r.stick_fraction), (None, None));
}

#[test]
fn stick_without_friction_or_with_a_dashpot_and_a_bad_ring_are_refused_by_key() {
    let text = scene(0.3);
    let err = |sets: &[&str]| -> String {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let ls = rubsim::scene::parse("stick.toml".as_ref(), &text, &sets);
        match ls {
            Err(e) => e.to_string(),
            Ok(_) => panic!("{sets:?} accepted"),
        }
    };
    let e = err(&["station.0.friction=0.0"]);
    assert!(
        e.contains("station.0.stick") && e.contains("friction"),
        "{e}"
    );
    let e = err(&["stator.0.contact_damping=1.0"]);
    assert!(
        e.contains("stator.0.contact_damping") && e.contains("stick"),
        "{e}"
    );
    // A section that cannot roll: no radius.
    let e = err(&["station.0.radius=0.0"]);
    assert!(e.contains("station.0.radius"), "{e}");
    // An anisotropic ring's keys: a support stiffness that is not positive, damping without
    // mass, and the radially elastic law, which is isotropic.
    let e = err(&["stator.0.stiffness_y=-5.0"]);
    assert!(e.contains("stator.0.stiffness_y"), "{e}");
    let e = err(&[
        "stator.0.mass=0.0",
        "stator.0.damping=0.0",
        "stator.0.damping_y=1.0",
    ]);
    assert!(
        e.contains("stator.0.damping_y") && e.contains("mass"),
        "{e}"
    );
    let e = err(&[
        "stator.0.mass=0.0",
        "stator.0.damping=0.0",
        "stator.0.kinematics=\"radial\"",
        "stator.0.stiffness_y=50.0",
    ]);
    assert!(
        e.contains("stator.0.stiffness_y") && e.contains("radial"),
        "{e}"
    );
}

#[test]
fn friction_dissipates_only_in_slip_and_balances_the_spin_s_work() {
    // Rolling: the section's surface moves with the ring, no slip, no friction power, though
    // the friction force is 4 % of the normal force.
    let omega = 0.6;
    let ga = Scheme::GeneralizedAlpha {
        rho_inf: rubsim::time::STATOR_WITH_MASS_RHO_INF,
    };
    let (rec, _) = whirl_run(0.3, omega, ga, 2e-3, 30);
    let got = whirl_of(&rec, second_half(&rec));
    let scale = got.normal[1] * got.friction[1] * R * omega;
    assert!(
        got.power[0].abs().max(got.power[1].abs()) < 1e-9 * scale,
        "rolling dissipates {:?} W (scale {scale:.3e} W)",
        got.power
    );
    // The whip: the spin's work through the friction torque, R μ p Ω, goes into the two
    // dampers, c ω² |z_r|² + c_s ω² |z_s|², and into heat at the slip, μ p (RΩ + ωδ) — in
    // the closed form and in the run (its own radii, force and whirl).
    let (mu, omega) = (0.3, 4.0);
    let (w, zr, zs, p) = whip(mu, CS_WHIP);
    let heat = mu * p * (R * omega + w * DELTA);
    let damping = w * w * (CR * zr * zr + CS_WHIP * zs * zs);
    assert!(
        rel(R * mu * p * omega, damping + heat) < 1e-9,
        "closed form balance"
    );
    let (rec, _) = whirl_run_with(mu, omega, ga, 1e-3, 60, &["stator.0.damping=2.0"]);
    let got = whirl_of(&rec, second_half(&rec));
    assert!(
        rel(got.power[0], heat) < 1e-3 && rel(got.power[1], heat) < 1e-3,
        "heat {:?} W, closed form {heat:.5e} W",
        got.power
    );
    let mean = |r: [f64; 2]| 0.5 * (r[0] + r[1]);
    let (p_run, zr_run, zs_run) = (mean(got.normal), mean(got.radius), mean(got.ring));
    let damping_run = got.freq * got.freq * (CR * zr_run * zr_run + CS_WHIP * zs_run * zs_run);
    let input = R * mu * p_run * omega;
    let heat_run = mean(got.power);
    assert!(
        rel(input, damping_run + heat_run) < 1e-3,
        "spin's work {input:.5e} W against dampers {damping_run:.5e} W + heat {heat_run:.5e} W"
    );
}

#[test]
fn the_scene_s_sweep_crosses_from_dry_whirl_into_dry_whip() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("sweep");
    let scene = common::repo("scenes/stick/dry_whirl.toml");
    let stdout = common::cli::ok(
        tmp.path(),
        &[
            "sweep",
            scene.to_str().unwrap(),
            "--set",
            "run.sweep.from=1.0",
            "--set",
            "run.sweep.to=2.5",
            "--set",
            "run.sweep.step=1.5",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(
        stdout.contains("dry whirl  ω/ωn 1.00") && stdout.contains("dry whip  ω/ωn 2.50"),
        "{stdout}"
    );
    let text = common::read(&out.join("sweep.csv"));
    let mut lines = text.lines();
    let cols: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = |name: &str| cols.iter().position(|c| *c == name).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 2);
    assert_eq!(
        (rows[0][at("dry_rub")], rows[0][at("stick_fraction")]),
        ("whirl", "1.0000")
    );
    assert_eq!(rows[1][at("dry_rub")], "whip");
    let stick: f64 = rows[1][at("stick_fraction")].parse().unwrap();
    assert!(stick < 0.5, "the whip slips: {stick}");
    // The roll's whirl follows −RΩ/δ = −4.35 Ω; the whip's is locked near the coupled
    // frequency, 9.58 rad/s undamped.
    let order: f64 = rows[0][at("whirl_order")].parse().unwrap();
    assert!((order + 0.05 / 0.0115).abs() < 1e-3, "roll order {order}");
    let order: f64 = rows[1][at("whirl_order")].parse().unwrap();
    assert!(
        (order * 2.5 + 8.8).abs() < 0.2,
        "whip at {} rad/s",
        order * 2.5
    );
    assert!(out.join("dry_whirl.png").exists());
}

#[test]
fn a_rub_that_never_sticks_is_the_permanent_slip_run_bit_for_bit() {
    // A forward whirl in full contact slips forward at every instant: the law with stick gives
    // the force n + μa of permanent slip, so the same run to the last bit.
    let run = |stick: &str| {
        let (ls, model) = scene_model(&scene(0.3), &["run.dt=1e-3", stick]);
        let (case, plan) = case_and_plan(&ls, &model, 4.0, Scheme::ForwardIncrement);
        let r0 = 1.05 * DELTA;
        let init = Initial {
            u: [r0, 0.0],
            v: [0.0, 4.0 * r0],
        };
        integrate(&case, Scheme::ForwardIncrement, &plan, init).unwrap()
    };
    let (a, sa) = run("station.0.stick=true");
    let (b, sb) = run("station.0.stick=false");
    assert_eq!(sa.whole.stick_instants, 0);
    assert!(sa.contact_steps > 0);
    assert_eq!(a.disp, b.disp);
    assert_eq!(a.force, b.force);
    assert_eq!((sa.steps, sa.pivots), (sb.steps, sb.pivots));
}

/// One window of a transient's `full_waterfall.csv`: its time, Ω/ω_n, the strongest line's
/// frequency / ω_n, the contact and stick fractions and the class (`whirl`, `whip` or empty).
struct WindowRow {
    t: f64,
    nu: f64,
    freq: f64,
    contact: f64,
    stick: f64,
    class: String,
}

/// The windows of a transient run of `scene` (its strongest line each), with the command's
/// standard output and the run's summary.json.
fn transient_windows(scene: &str) -> (Vec<WindowRow>, String, serde_json::Value) {
    let (_tmp, out, stdout) = common::cli::run_scene(scene);
    let (cols, table) = common::cli::csv_table(&out.join("full_waterfall.csv"));
    let at = |name: &str| cols.iter().position(|c| c == name).unwrap();
    let rows = table
        .iter()
        .filter(|r| r[at("rank")] == "1")
        .map(|r| WindowRow {
            t: r[at("t_s")].parse().unwrap(),
            nu: r[at("speed_ratio")].parse().unwrap(),
            freq: r[at("freq_nd")].parse().unwrap(),
            contact: r[at("contact_fraction")].parse().unwrap(),
            stick: r[at("stick_fraction")].parse().unwrap(),
            class: r[at("dry_rub")].to_string(),
        })
        .collect();
    for png in ["full_waterfall.png", "dry_whirl.png"] {
        assert!(out.join(png).exists(), "{png}");
    }
    let summary = serde_json::from_str(&common::read(&out.join("summary.json"))).unwrap();
    (rows, stdout, summary)
}

/// The spans of summary.json's `full_waterfall.dry_rub`: (class, first and last Ω/ω_n).
fn spans(summary: &serde_json::Value) -> Vec<(String, f64, f64)> {
    summary["full_waterfall"]["dry_rub"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            let nu = &s["speed_ratio"];
            (
                s["regime"].as_str().unwrap().to_string(),
                nu[0].as_f64().unwrap(),
                nu[1].as_f64().unwrap(),
            )
        })
        .collect()
}

/// Checks the windows of a run-up or run-down across the roll's end: below `lo` the windows
/// roll (dry whirl, every contact sample in stick, the backward line at −RΩ/δ), above `hi` they
/// whip (dry whip, the line locked near the coupled frequency −8.8 ω_n); returns the windows of
/// each. The first `settle` windows, which hold the start's settling, are not checked.
fn assert_whirl_below_whip_above(
    rows: &[WindowRow],
    (lo, hi): (f64, f64),
    settle: usize,
) -> (usize, usize) {
    let rolling = -0.05 / 0.0115;
    let (mut rolled, mut whipped) = (0, 0);
    for w in rows.iter().skip(settle) {
        if w.nu < lo {
            assert!(
                (w.freq / w.nu - rolling).abs() < 5e-3,
                "Ω/ωn {}: {} ωn",
                w.nu,
                w.freq
            );
            assert_eq!(
                (w.class.as_str(), w.contact, w.stick),
                ("whirl", 1.0, 1.0),
                "Ω/ωn {}",
                w.nu
            );
            rolled += 1;
        } else if w.nu > hi {
            assert!((w.freq + 8.8).abs() < 0.15, "Ω/ωn {}: {} ωn", w.nu, w.freq);
            assert_eq!(
                (w.class.as_str(), w.contact),
                ("whip", 1.0),
                "Ω/ωn {}",
                w.nu
            );
            assert!(w.stick < 0.5, "Ω/ωn {}: stick {}", w.nu, w.stick);
            whipped += 1;
        }
    }
    (rolled, whipped)
}

#[test]
fn a_run_up_leaves_dry_whirl_for_a_whip_locked_near_the_coupled_frequency() {
    let (rows, stdout, summary) = transient_windows("scenes/stick/whirl_runup.toml");
    let (rolled, whipped) = assert_whirl_below_whip_above(&rows, (1.9, 2.3), 1);
    assert!(
        rolled >= 2 && whipped >= 2,
        "{rolled} rolled, {whipped} whipped"
    );
    // One span of each, whirl first, told on the console too.
    let s = spans(&summary);
    assert_eq!(
        s.iter().map(|s| s.0.as_str()).collect::<Vec<_>>(),
        ["whirl", "whip"],
        "{s:?}"
    );
    assert!(s[0].2 < 2.2 && s[1].1 > 1.9, "{s:?}");
    assert!(
        stdout.contains("dry whirl: t ") && stdout.contains("dry whip: t "),
        "{stdout}"
    );
}

#[test]
fn a_run_down_drops_from_dry_whip_into_dry_whirl() {
    // The mirror of the run-up: started slipping in a backward whirl at 3 ωn and run down to
    // 0.5 ωn, the rotor whips — its whirl locked near the coupled frequency — until the rolling
    // speed 4.35 Ω falls below it near 2 ωn, and rolls below, windows of 2 revolutions each.
    // The first two (9 s) hold the whip's settling from its start touching the ring.
    let (rows, _, summary) = transient_windows("scenes/stick/whirl_rundown.toml");
    let (rolled, whipped) = assert_whirl_below_whip_above(&rows, (1.8, 2.1), 2);
    assert!(
        rolled >= 5 && whipped >= 5,
        "{rolled} rolled, {whipped} whipped"
    );
    let s = spans(&summary);
    assert_eq!(
        s.iter().map(|s| s.0.as_str()).collect::<Vec<_>>(),
        ["whip", "whirl"],
        "{s:?}"
    );
    // The whip ends and the roll starts between the windows either side of 8.8/4.35 = 2.02 ωn.
    assert!(
        s[0].2 > 2.02 && s[0].2 < 2.2 && s[1].1 < 2.02 && s[1].1 > 1.85,
        "{s:?}"
    );
}

#[test]
fn an_fe_rotor_drops_into_dry_whirl_after_a_blade_off() {
    // The FE paper rotor at 3 ωn in a casing ring with mass (R/δ = 20): before the blade leaves
    // at 0.05 s nothing touches; after it the rub slips, then sticks for good, and from 0.19 s
    // on every window rolls at −RΩ/δ = −20 Ω (the whirl above the ring's own frequency).
    let (rows, stdout, summary) = transient_windows("scenes/stick/fe_blade_off_whirl.toml");
    let before: Vec<&WindowRow> = rows.iter().filter(|w| w.t < 0.04).collect();
    assert!(
        !before.is_empty()
            && before
                .iter()
                .all(|w| w.contact == 0.0 && w.class.is_empty())
    );
    let rolling: Vec<&WindowRow> = rows.iter().filter(|w| w.t > 0.19).collect();
    assert!(
        rolling.len() >= 10,
        "{} windows after 0.19 s",
        rolling.len()
    );
    for w in rolling {
        assert!(
            (w.freq / w.nu + 20.0).abs() < 0.05
                && (w.class.as_str(), w.contact, w.stick) == ("whirl", 1.0, 1.0),
            "t {}: {} ωn, {} (contact {}, stick {})",
            w.t,
            w.freq,
            w.class,
            w.contact,
            w.stick
        );
    }
    let s = spans(&summary);
    assert_eq!(s.len(), 1, "{s:?}");
    assert_eq!(s[0].0, "whirl");
    assert!(stdout.contains("dry whirl: t 0."), "{stdout}");
}

#[test]
fn a_roll_the_step_or_the_record_does_not_resolve_is_told() {
    // The blade-off scene at 5e-5 s and 32 samples a revolution: its roll at −20 Ω (9.8e3
    // rad/s) is taken in 12.8 steps a whirl and lies beyond the ±16 orders of its samples. The
    // run says both, naming the keys; at the scene's own step and record it says neither.
    let tmp = tempfile::tempdir().unwrap();
    let scene = common::repo("scenes/stick/fe_blade_off_whirl.toml");
    let run = |sets: &[&str]| {
        let mut args = vec!["run", scene.to_str().unwrap()];
        for s in sets {
            args.extend(["--set", s]);
        }
        let out = tmp.path().join("run");
        args.extend(["--out", out.to_str().unwrap(), "--force"]);
        let o = common::cli::rubsim(tmp.path(), &args);
        assert!(o.status.success(), "{}", common::cli::text(&o.stderr));
        common::cli::text(&o.stderr)
    };
    let err = run(&["run.dt=5e-5", "run.samples_per_rev=32"]);
    assert!(
        err.contains("station `disk` rolls on stator `casing`")
            && err.contains("steps a period")
            && err.contains("`run.dt` ≤")
            && err.contains("`run.samples_per_rev` ≥ 41"),
        "{err}"
    );
    let err = run(&[]);
    assert!(!err.contains("rolls on stator"), "{err}");
}

#[test]
fn a_meshed_annulus_with_mass_on_springs_rolls_as_the_ring_of_its_mass() {
    // The rig's ring as a gmsh annulus: Q4 plane stress, 128 nodes around its inner circle
    // (r = R + δ), 10 mm thick, ρ 2450 kg/m³ so that its mass is the ring's 0.1 kg, stiff
    // (E = 1 GPa: its own deformation under the roll's force is below 1e-4 δ), held only by
    // springs of 100 N/m in all on its outer circle, Rayleigh α = 5 (c_s = α m_s = 0.5 N·s/m).
    // Node-to-nodes contact with stick: the section rolls over the nodes, several at once at
    // the start, where the active set on the friction states cycles and the Gauss–Seidel
    // sweeps solve the step. It rolls as the rigid ring of §3.1 does.
    let geo = common::repo("geometry/annulus.geo");
    let text = scene(0.3).replace(
        &format!(
            "kind = \"ring\"\nname = \"ring\"\nstation = \"s\"\nclearance = {DELTA}\nstiffness = {KS}\nmass = {MS}\ndamping = {CS}\n"
        ),
        &format!(
            "kind = \"mesh\"\nname = \"annulus\"\nstation = \"s\"\ngeometry = \"{}\"\n\
             parameters = {{ ri = {}, ro = 0.07, h = 0.004, n = 128 }}\norder = 1\nquads = true\n\
             plane = \"stress\"\nthickness = 0.01\nyoungs_modulus = 1e9\npoisson_ratio = 0.3\n\
             density = 2450.0\nfixed = []\nrayleigh = [5.0, 0.0]\n\
             [[stator.springs]]\ngroup = \"stator_fixed\"\nstiffness = [{KS}, {KS}]\n",
            geo.display(),
            R + DELTA
        ),
    );
    assert!(text.contains("kind = \"mesh\""));
    let omega = 0.6;
    let ga = Scheme::GeneralizedAlpha {
        rho_inf: rubsim::time::STATOR_WITH_MASS_RHO_INF,
    };
    // 67 samples a revolution: not commensurate with the 640 node passages of a revolution
    // (5 whirls of 128 nodes), so the sampled force is not read at the same place between
    // two nodes every time.
    let sets = [
        "run.dt=2e-3",
        "run.revolutions=12",
        "run.transient_revolutions=6",
        "run.samples_per_rev=67",
    ];
    let (ls, model) = scene_model(&text, &sets);
    let (case, plan) = case_and_plan(&ls, &model, omega, ga);
    let r0 = 1.05 * DELTA;
    let init = Initial {
        u: [r0, 0.0],
        v: [0.0, -R * omega / DELTA * r0],
    };
    let (rec, stats) = integrate(&case, ga, &plan, init).unwrap();
    assert!(
        stats.friction_sweep_solves > 0,
        "the fallback was not needed"
    );
    assert_eq!(stats.steady.contact_instants, stats.steady.instants);
    assert_eq!(stats.steady.stick_instants, stats.steady.instants);
    let from = second_half(&rec);
    let got = whirl_of(&rec, from);
    let want = rolling(omega);
    assert!(
        rel(got.freq, want.0) < 5e-4,
        "whirl {} vs {}",
        got.freq,
        want.0
    );
    assert!(
        rel(got.radius[0], want.1) < 5e-4 && rel(got.radius[1], want.1) < 5e-4,
        "radius {:?} vs {}",
        got.radius,
        want.1
    );
    // The force pulses as the contact passes from node to node; its mean is the ring's.
    let n = (rec.len() - from) as f64;
    let mean = (from..rec.len())
        .map(|i| {
            let f = rec.force_at(i, 0);
            f[0].hypot(f[1])
        })
        .sum::<f64>()
        / n;
    let ring = want.3 * (1.0 + want.4 * want.4).sqrt();
    assert!(
        rel(mean, ring) < 2e-3,
        "mean |F| {mean} vs the ring's {ring} N"
    );
}
