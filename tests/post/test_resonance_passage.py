"""Passage through resonance at constant angular acceleration: rubsim's transient run of a
Jeffcott rotor without stator against an independent integration of the same equations by
scipy (DOP853, rtol 1e-10), and against the leading-order asymptotic solution of the passage
(the slowly varying envelope; Fresnel integrals when undamped).

The equations (docs/VALIDATION.md §11, `RotorBody::add_unbalance_spin`), m_u e = U, φ(t) the
spin angle of the ramp Ω(t) = Ω₀ + α t:

    m ẍ + c ẋ + k x = U (Ω² cos φ + α sin φ)
    m ÿ + c ẏ + k y = U (Ω² sin φ − α cos φ)

Non-dimensional: ν = Ω/ω_n, η = α/ω_n² (the acceleration), ξ = c/(2√(km)), ε = U/m.

The asymptotic solution. With z = x + i y = A(τ) e^{iφ}, τ = ω_n t, and s = τ − τ_c measured
from the moment ν = 1, keeping the leading terms near resonance (ν² ≈ 1 in the force,
1 − ν² ≈ −2σηs, σ = ±1 run-up/coast-down, Ä and the α term dropped):

    A′ + (ξ + iσηs) A = −iε/2,   so   |A| = ε/(2√η) |∫_{-∞}^{S} e^{−D(S−v) + iσv²/2} dv|,

S = s√η, D = ξ/√η. The peak is A_max = ε G(D)/√η at ν_peak = 1 + σ H(D) √η, the same for the
run-up and the coast-down (σ only conjugates the integral); G(0) = √π/2 · max|½ + C(x) +
i(½ + S(x))| = 1.4672 and H(0) = 2.1574 (the Fresnel integrals C, S; the maximum of the Cornu
spiral's distance from its end). Its error is O(√η) relative, odd in σ, so the mean of a
run-up and a coast-down meets it to O(η). This is the classical result for a linear oscillator
accelerated through its critical speed (F. M. Lewis 1932 solved the problem analytically; the
peak's reduction ∝ η^{-1/2} and its shift ∝ η^{1/2}).

Run with the project's venv after a release build:

    .venv/bin/python -m pytest tests/post/test_resonance_passage.py

The rubsim binary is $RUBSIM_BIN, else target/release/rubsim.
"""
import json
import math
import os
import subprocess

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.special import fresnel

# Slow tier (scripts/test-slow.sh): verification runs of slow passages against scipy and the
# asymptotic solutions (minutes of CPU in all), not read-back of the outputs.
pytestmark = pytest.mark.slow

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BIN = os.environ.get("RUBSIM_BIN", os.path.join(ROOT, "target", "release", "rubsim"))

# The rotor: m = 1 kg, k = 10⁴ N/m (ω_n = 100 rad/s), U = 1e-5 kg·m (ε = 10 µm).
MASS, STIFF, UNB_MASS, UNB_RADIUS = 1.0, 1.0e4, 1.0e-3, 1.0e-2
WN = math.sqrt(STIFF / MASS)
EPS = UNB_MASS * UNB_RADIUS / MASS
NU_LOW, NU_HIGH = 0.5, 1.5  # the ramp's ends (ω/ω_n)
XI = 0.01  # damping ratio of the cases checked against scipy
ETAS = [1e-4, 3e-4, 1e-3, 3e-3, 1e-2]
UNDAMPED_ETAS = [1e-4, 1e-3, 1e-2]


def rubsim(*args):
    assert os.path.exists(BIN), f"{BIN} missing: build with `cargo build --release` (or set RUBSIM_BIN)"
    r = subprocess.run([BIN, *args], capture_output=True, text=True)
    assert r.returncode == 0, f"rubsim {args} failed:\n{r.stderr}"
    return r.stdout


def steady(nu, xi):
    """Steady forward whirl z = ε ν²/(1 − ν² + 2iξν) at φ = 0 and its velocity iνω_n z."""
    z = EPS * nu * nu / (1.0 - nu * nu + 2j * xi * nu)
    return z, 1j * nu * WN * z


def sigma(up):
    return 1.0 if up else -1.0


def scene_text(eta, xi, up, dt=None):
    """A Jeffcott rotor without stator ramped at α = σ η ω_n² through ω_n, started on the
    steady whirl of its first speed (so no start transient rings through the passage)."""
    nu0, nu1 = (NU_LOW, NU_HIGH) if up else (NU_HIGH, NU_LOW)
    z, v = steady(nu0, xi)
    acc = sigma(up) * eta * WN  # ω/ω_n per second: α/ω_n
    lines = [
        'title = "passage through resonance"',
        "[rotor]",
        'kind = "jeffcott"',
        f"mass = {MASS!r}",
        f"stiffness = {STIFF!r}",
        f"damping_ratio = {xi!r}",
        "[[rotor.unbalance]]",
        f"mass = {UNB_MASS!r}",
        f"radius = {UNB_RADIUS!r}",
        "phase_deg = 0.0",
        "[run]",
        "samples_per_rev = 64",
        "error_estimate = false",  # compared with scipy, not with a companion
        f"initial_displacement = [{z.real!r}, {z.imag!r}]",
        f"initial_velocity = [{v.real!r}, {v.imag!r}]",
    ]
    if dt is not None:
        lines.append(f"dt = {dt!r}")
    lines += [
        "[run.speed_profile]",
        'kind = "ramp"',
        'unit = "speed_ratio"',
        f"from = {nu0!r}",
        f"to = {nu1!r}",
        f"acceleration = {acc!r}",
        "[output]",
        "png = false",
    ]
    return "\n".join(lines) + "\n"


def run_rubsim(tmp, eta, xi, up, dt=None):
    """rubsim's sampled response: (t, x, y) from response.csv and the step Δt of its plan."""
    name = f"eta{eta:g}_xi{xi:g}_{'up' if up else 'down'}" + (f"_dt{dt:g}" if dt else "")
    d = tmp / name
    d.mkdir()
    (d / "scene.toml").write_text(scene_text(eta, xi, up, dt))
    rubsim("run", str(d / "scene.toml"), "--out", str(d / "out"))
    a = np.genfromtxt(d / "out" / "response.csv", delimiter=",", names=True)
    with open(d / "out" / "summary.json") as f:
        step = json.load(f)["transient"]["plan"]["dt"]
    return a["t_s"], a["x_m"], a["y_m"], step


def run_scipy(eta, xi, up, t):
    """The same equations by DOP853 (rtol 1e-10), from the same initial state, at rubsim's
    sample times."""
    nu0 = NU_LOW if up else NU_HIGH
    al = sigma(up) * eta * WN * WN
    w0 = nu0 * WN
    z, v = steady(nu0, xi)

    def f(tt, s):
        x, y, vx, vy = s
        ph = w0 * tt + 0.5 * al * tt * tt
        w = w0 + al * tt
        c, sn = math.cos(ph), math.sin(ph)
        fx = EPS * (w * w * c + al * sn)
        fy = EPS * (w * w * sn - al * c)
        return [vx, vy, fx - 2 * xi * WN * vx - WN * WN * x, fy - 2 * xi * WN * vy - WN * WN * y]

    sol = solve_ivp(f, (0.0, t[-1]), [z.real, z.imag, v.real, v.imag], method="DOP853",
                    rtol=1e-10, atol=1e-10 * EPS, t_eval=t)
    assert sol.success, sol.message
    return sol.y[0], sol.y[1]


def peak(t, r):
    """The peak of a sampled r: a cubic fitted by least squares to the samples around the
    largest within 1e-3 of it (many samples: the rounding of response.csv's 7 digits averages
    out), its maximum: (value, time)."""
    i = int(np.argmax(r))
    assert 0 < i < len(r) - 1, "the peak lies at an end of the run"
    lo, hi = i, i
    while lo > 0 and r[lo - 1] >= (1 - 1e-3) * r[i]:
        lo -= 1
    while hi < len(r) - 1 and r[hi + 1] >= (1 - 1e-3) * r[i]:
        hi += 1
    lo, hi = min(lo, i - 3), max(hi, i + 3)
    assert lo >= 0 and hi < len(r), "the peak lies at an end of the run"
    h = t[hi] - t[lo]
    u = (t[lo:hi + 1] - t[i]) / h
    c = np.polyfit(u, r[lo:hi + 1], 3)
    roots = np.roots(np.polyder(c))
    roots = roots[np.isreal(roots)].real
    roots = roots[(roots >= u[0]) & (roots <= u[-1])]
    assert len(roots), "no maximum inside the fitted window"
    v = np.polyval(c, roots)
    k = int(np.argmax(v))
    return v[k], t[i] + roots[k] * h


def speed_at(t, eta, up):
    """ν(t) of the ramp."""
    return (NU_LOW if up else NU_HIGH) + sigma(up) * eta * WN * t


def envelope(D):
    """The asymptotic passage (module doc): G(D) = max_S |A|√η/ε and H(D) = its S, from
    A′ + (D + iS) A = −i/2 integrated by DOP853 from S = −200, started on its quasi-static
    expansion A ≈ −i/(2q)(1 + i/q²), q = D + iS."""
    def f(s, y):
        a = y[0] + 1j * y[1]
        d = -0.5j - (D + 1j * s) * a
        return [d.real, d.imag]

    s0 = -200.0
    q = D + 1j * s0
    a0 = -0.5j / q * (1 + 1j / q ** 2)
    sol = solve_ivp(f, (s0, 12.0), [a0.real, a0.imag], method="DOP853", rtol=1e-12,
                    atol=1e-14, dense_output=True)
    s = np.linspace(-5.0, 12.0, 170001)
    y = sol.sol(s)
    amp = np.hypot(y[0], y[1])
    g, h = peak(s, amp)
    return g, h


@pytest.fixture(scope="module")
def damped(tmp_path_factory):
    """rubsim and scipy for ξ = 0.01 at each η, run-up and coast-down."""
    tmp = tmp_path_factory.mktemp("passage")
    out = {}
    for eta in ETAS:
        for up in (True, False):
            t, x, y, step = run_rubsim(tmp, eta, XI, up)
            xr, yr = run_scipy(eta, XI, up, t)
            out[(eta, up)] = (t, x, y, xr, yr, step)
    return out


def test_envelope_is_the_fresnel_solution_when_undamped():
    # The asymptotic integrator against the closed form of the undamped case.
    x = np.linspace(0.0, 4.0, 400001)
    s, c = fresnel(x)
    amp = math.sqrt(math.pi) / 2 * np.hypot(0.5 + c, 0.5 + s)
    g0, x0 = peak(x, amp)
    g, h = envelope(0.0)
    assert abs(g / g0 - 1) < 1e-7
    assert abs(h - x0 * math.sqrt(math.pi)) < 1e-4
    assert abs(g - 1.46720) < 1e-5 and abs(h - 2.1574) < 1e-4


def test_rubsim_matches_scipy_through_resonance(damped):
    """Peak amplitude and speed at the peak against scipy. The explicit central difference
    errs in frequency by (ω_nΔt)²/24 (4.5e-5 at the plan's Δt, 128 steps per revolution at
    1.5 ω_n): the peak's speed moves by that much relative, and the peak amplitude by a few
    times it (the scheme's amplitude error near resonance, O(Δt²) too). Bounds: speed 2×,
    amplitude 8× that figure."""
    rows = []
    for (eta, up), (t, x, y, xr, yr, step) in sorted(damped.items()):
        e2 = (WN * step) ** 2 / 24
        a, tp = peak(t, np.hypot(x, y))
        ar, tpr = peak(t, np.hypot(xr, yr))
        nu, nur = speed_at(tp, eta, up), speed_at(tpr, eta, up)
        rows.append((eta, up, a / EPS, ar / EPS, a / ar - 1, nu, nur, nu / nur - 1, e2))
        assert abs(a / ar - 1) < 8 * e2, (eta, up, a / ar - 1, e2)
        assert abs(nu / nur - 1) < 2 * e2, (eta, up, nu / nur - 1, e2)
    for r in rows:
        print("η %.0e %-4s peak/ε %.5f scipy %.5f rel %+.2e | ν_peak %.5f scipy %.5f rel %+.2e "
              "| (ω_nΔt)²/24 %.1e" % (r[0], "up" if r[1] else "down", *r[2:]))


def test_scheme_error_against_scipy_falls_as_dt_squared(tmp_path):
    """η = 1e-3 run-up at Δt, Δt/2, Δt/4: the peak's speed and amplitude errors against scipy
    fall with a fitted slope of 2 (the scheme's order)."""
    eta, up = 1e-3, True
    t, x, y, step = run_rubsim(tmp_path, eta, XI, up)
    xr, yr = run_scipy(eta, XI, up, t)
    ar, tpr = peak(t, np.hypot(xr, yr))
    errs_a, errs_nu, dts = [], [], []
    for k in range(3):
        dt = step / 2 ** k
        if k:
            t, x, y, _ = run_rubsim(tmp_path, eta, XI, up, dt)
            xr, yr = run_scipy(eta, XI, up, t)
            ar, tpr = peak(t, np.hypot(xr, yr))
        a, tp = peak(t, np.hypot(x, y))
        errs_a.append(abs(a / ar - 1))
        errs_nu.append(abs(speed_at(tp, eta, up) / speed_at(tpr, eta, up) - 1))
        dts.append(dt)
    slope_a = np.polyfit(np.log(dts), np.log(errs_a), 1)[0]
    slope_nu = np.polyfit(np.log(dts), np.log(errs_nu), 1)[0]
    print("Δt", dts, "peak errors", errs_a, "slope %.3f" % slope_a)
    print("ν_peak errors", errs_nu, "slope %.3f" % slope_nu)
    assert abs(slope_a - 2) < 0.15, slope_a
    assert abs(slope_nu - 2) < 0.15, slope_nu


def test_damped_passage_meets_the_asymptotic_envelope(damped):
    """ξ = 0.01, D = ξ/√η from 1 to 0.1: the peak √η/ε and the shift (ν_peak − 1)/(σ√η)
    against G(D), H(D). Each direction differs by O(√η); the mean of the run-up and the
    coast-down by O(η) (plus the scheme's own error, 8 (ω_nΔt)²/24, the bound of
    `test_rubsim_matches_scipy_through_resonance`)."""
    fails = []
    for eta in ETAS:
        g, h = envelope(XI / math.sqrt(eta))
        got = {}
        for up in (True, False):
            t, x, y, _, _, step = damped[(eta, up)]
            a, tp = peak(t, np.hypot(x, y))
            pk = a * math.sqrt(eta) / EPS
            sh = (speed_at(tp, eta, up) - 1) / (sigma(up) * math.sqrt(eta))
            got[up] = (pk, sh)
            print("η %.0e D %.3f %-4s peak√η/ε %.5f G %.5f rel %+.3e | shift/√η %.4f H %.4f "
                  "rel %+.3e" % (eta, XI / math.sqrt(eta), "up" if up else "down", pk, g,
                                 pk / g - 1, sh, h, sh / h - 1))
            if abs(pk / g - 1) > 1.0 * math.sqrt(eta) or abs(sh / h - 1) > 3 * math.sqrt(eta):
                fails.append((eta, up, pk / g - 1, sh / h - 1))
        e2 = (WN * step) ** 2 / 24
        pk_mean = 0.5 * (got[True][0] + got[False][0])
        sh_mean = 0.5 * (got[True][1] + got[False][1])
        print("   mean: peak rel %+.3e, shift rel %+.3e" % (pk_mean / g - 1, sh_mean / h - 1))
        if abs(pk_mean / g - 1) > 3 * eta + 8 * e2 or abs(sh_mean / h - 1) > 3 * eta + 8 * e2:
            fails.append((eta, "mean", pk_mean / g - 1, sh_mean / h - 1))
    assert not fails, fails


def test_undamped_passage_scales_as_lewis(tmp_path):
    """ξ = 0: the peak falls as η^(-1/2) and the shift grows as η^(1/2) (fitted slopes of the
    mean of run-up and coast-down over η = 1e-4 … 1e-2), with the constants of the Fresnel
    solution, G(0) = 1.4672 and H(0) = 2.1574."""
    g, h = envelope(0.0)
    pks, shs = [], []
    for eta in UNDAMPED_ETAS:
        got = []
        for up in (True, False):
            t, x, y, _ = run_rubsim(tmp_path, eta, 0.0, up)
            a, tp = peak(t, np.hypot(x, y))
            got.append((a / EPS, sigma(up) * (speed_at(tp, eta, up) - 1)))
            print("η %.0e %-4s peak/ε %.4f (Fresnel %.4f) shift %.5f (Fresnel %.5f)"
                  % (eta, "up" if up else "down", a / EPS, g / math.sqrt(eta),
                     got[-1][1], h * math.sqrt(eta)))
        pks.append(0.5 * (got[0][0] + got[1][0]))
        shs.append(0.5 * (got[0][1] + got[1][1]))
    le = np.log(UNDAMPED_ETAS)
    sp, cp = np.polyfit(le, np.log(pks), 1)
    ss, cs = np.polyfit(le, np.log(shs), 1)
    print("peak ∝ η^%.4f, coefficient %.4f; shift ∝ η^%.4f, coefficient %.4f"
          % (sp, math.exp(cp), ss, math.exp(cs)))
    assert abs(sp + 0.5) < 0.01, sp
    assert abs(ss - 0.5) < 0.01, ss
    for eta, p, s in zip(UNDAMPED_ETAS, pks, shs):
        assert abs(p * math.sqrt(eta) / g - 1) < 3 * eta, (eta, p)
        assert abs(s / (h * math.sqrt(eta)) - 1) < 3 * eta, (eta, s)
