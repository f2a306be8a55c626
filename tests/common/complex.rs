//! Complex numbers as `(re, im)` pairs, for the closed forms of whirling rotors (the ring's
//! exact kinematics, rolling whirl and whip).

/// A complex number `(re, im)`.
pub type C = (f64, f64);

/// `a b`.
pub fn mul(a: C, b: C) -> C {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}

/// `a / b`.
pub fn div(a: C, b: C) -> C {
    let d = b.0 * b.0 + b.1 * b.1;
    ((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
}

/// `a + b`.
pub fn add(a: C, b: C) -> C {
    (a.0 + b.0, a.1 + b.1)
}

/// `s a` for real `s`.
pub fn scale(a: C, s: f64) -> C {
    (a.0 * s, a.1 * s)
}

/// `|a|`.
pub fn abs(a: C) -> f64 {
    a.0.hypot(a.1)
}
