"""Stick and roll against an independent integration (issue 28, docs/STICK.md §3.4).

The lightly damped whip of the rig (a Jeffcott rotor in a ring with mass, μ 0.3, Ω = 4 rad/s)
is not the circular whip of the closed form: stick and slip alternate and the whirl's radius
and force are modulated. rubsim's generalised-α run (Coulomb friction with stick, Lagrange
multipliers) is compared with scipy's LSODA on the same equations with a penalty contact of
stiffness k_c and a regularised friction μ p tanh(v_slip/ε), over the same 40 s from the same
start: the whirl frequency, the largest rotor radius and the largest normal force. The
regularised model converges to the nonsmooth one as k_c → ∞ and ε → 0; at k_c = 10⁶ N/m and
ε = 10⁻⁴ m/s its figures are within 2e-3 of those at 10⁷ and 10⁻⁵ (the test prints both
settings' figures in the docs; only the first is run here, ≈ 15 s).
"""

import pathlib

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import rubsim

ROOT = pathlib.Path(__file__).resolve().parents[2]

M, K, C = 1.0, 1.0, 0.1
MS, KS, CS = 0.1, 100.0, 0.5
DELTA, R, MU = 0.01, 0.05, 0.3
OMEGA, T, DT = 4.0, 40.0, 1e-3

SCENE = f"""
[rotor]
kind = "jeffcott"
mass = {M}
stiffness = {K}
damping = {C}
[[station]]
name = "s"
radius = {R}
friction = {MU}
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
speed = {OMEGA}
integrator = "generalized_alpha"
dt = {DT}
duration = {T}
check_coexistence = false
error_estimate = false
initial_displacement = [{1.05 * DELTA}, 0.0]
initial_velocity = [0.0, {-R * OMEGA / DELTA * 1.05 * DELTA}]
"""


def regularised(kc, eps):
    """Whirl frequency (rad/s), largest rotor radius (m) and largest normal force (N) over
    the second half of the 40 s, scipy LSODA on the penalty–regularised model."""

    def rhs(t, y):
        x, yy, xs, ys, vx, vy, vxs, vys = y
        dx, dy = x - xs, yy - ys
        r = np.hypot(dx, dy)
        fx = fy = 0.0
        if r > DELTA:
            n = np.array([dx, dy]) / r
            a = np.array([-n[1], n[0]])
            p = kc * (r - DELTA)
            vs = a @ np.array([vx - vxs, vy - vys]) + R * OMEGA
            f = -(n * p + a * MU * p * np.tanh(vs / eps))
            fx, fy = f
        return [vx, vy, vxs, vys,
                (-K * x - C * vx + fx) / M, (-K * yy - C * vy + fy) / M,
                (-KS * xs - CS * vxs - fx) / MS, (-KS * ys - CS * vys - fy) / MS]

    r0 = 1.05 * DELTA
    y0 = [r0, 0.0, 0.0, 0.0, 0.0, -R * OMEGA / DELTA * r0, 0.0, 0.0]
    ts = np.linspace(T / 2, T, 20001)
    sol = solve_ivp(rhs, (0.0, T), y0, method="LSODA", rtol=1e-9, atol=1e-12,
                    t_eval=ts, max_step=1e-3)
    x, yy, xs, ys = sol.y[:4]
    angle = np.unwrap(np.arctan2(yy, x))
    p = kc * np.maximum(np.hypot(x - xs, yy - ys) - DELTA, 0.0)
    return (angle[-1] - angle[0]) / (ts[-1] - ts[0]), np.hypot(x, yy).max(), p.max()


@pytest.mark.slow
def test_modulated_whip_matches_a_regularised_integration():
    w_ref, zr_ref, p_ref = regularised(1e6, 1e-4)
    # A modulated whip is not a steady window: the run says so (a RuntimeWarning).
    with pytest.warns(RuntimeWarning, match="not steady"):
        run = rubsim.Scene.from_toml(SCENE).run()
    res = run.result
    assert res["dry_rub"] == "whip"
    w = res["whirl"]["dominant_order"] * OMEGA
    # No unbalance: the non-dimensional outputs are in metres and newtons (scales of 1).
    zr = np.hypot(run.orbit[:, 0], run.orbit[:, 1]).max() * (res["z0"] or 1.0)
    # The largest contact force slips (|t| = μ p): |F| = p √(1 + μ²).
    p = res["contact_force_max_nd"] * (res["unbalance_force"] or 1.0) / np.hypot(1.0, MU)
    print(f"rubsim: ω {w:.5f} rad/s, |z_r| ≤ {zr:.6f} m, p ≤ {p:.5f} N, "
          f"stick {res['stick_fraction']:.3f}; scipy: ω {w_ref:.5f}, |z_r| ≤ {zr_ref:.6f}, "
          f"p ≤ {p_ref:.5f}")
    assert abs(w / w_ref - 1) < 2e-3
    assert abs(zr / zr_ref - 1) < 3e-3
    assert abs(p / p_ref - 1) < 5e-3
    # Stick and slip alternate: neither is the whole window.
    assert 0.0 < res["stick_fraction"] < 0.5


def test_a_run_down_tells_its_windows_of_whip_and_whirl():
    # scenes/stick/whirl_rundown.toml from Python: the windows' classes as the command's
    # full_waterfall.csv has them — dry whip above ≈ 2 ωn, dry whirl below (every contact
    # sample in stick once the roll has settled, below 1.8 ωn).
    t = rubsim.Scene(ROOT / "scenes" / "stick" / "whirl_rundown.toml").transient()
    w = t.windows
    nu = w["omega"] / t.omega_n
    classes = w["dry_rub"]
    assert len(classes) == len(nu) > 10
    assert all(c == "whip" for c, v in zip(classes[2:], nu[2:]) if v > 2.1)
    assert all(c == "whirl" for c, v in zip(classes, nu) if v < 1.8)
    assert np.all(w["stick_fraction"][nu < 1.8] == 1.0)
    assert np.allclose(w["frequency"][nu < 1.8] / w["omega"][nu < 1.8], -0.05 / 0.0115, atol=5e-3)
