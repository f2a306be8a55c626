//! Admissibility rules that types cannot express, with errors naming file, key and line.
//!
//! [`validate()`] runs every rule in a fixed order (rotor, stations, stators, run, output) and
//! reports the first one broken. The rules that choose between keys or turn a name into
//! something else ([`one_of`], [`at_most_one`], [`station_index`], [`extra_station_index`],
//! [`mesh_plane`], [`output_component`]) return what they chose, so the resolve stage
//! ([`crate::resolve`]) reads its choices from the same code that checked them.

use super::*;
use crate::element::solid2d::Plane;
use crate::error::SceneError;

/// Which of two alternative keys a scene gives (e.g. `clearance` or `clearance_nd`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OneOf<A, B> {
    /// The first key, with its value.
    First(A),
    /// The second key, with its value.
    Second(B),
}

/// Exactly one of the keys `key_a`, `key_b` (values `a`, `b`); the error names the table `at`.
pub fn one_of<A, B>(
    ls: &LoadedScene,
    (key_a, a): (&str, Option<A>),
    (key_b, b): (&str, Option<B>),
    at: &str,
) -> Result<OneOf<A, B>, SceneError> {
    match (a, b) {
        (Some(a), None) => Ok(OneOf::First(a)),
        (None, Some(b)) => Ok(OneOf::Second(b)),
        (Some(_), Some(_)) => Err(both(ls, key_a, key_b, at)),
        (None, None) => Err(ls.invalid(at, format!("missing: give `{key_a}` or `{key_b}`"))),
    }
}

/// At most one of the keys `key_a`, `key_b` (`None`: neither); the error names the table `at`.
pub fn at_most_one<A, B>(
    ls: &LoadedScene,
    (key_a, a): (&str, Option<A>),
    (key_b, b): (&str, Option<B>),
    at: &str,
) -> Result<Option<OneOf<A, B>>, SceneError> {
    match (a, b) {
        (Some(_), Some(_)) => Err(both(ls, key_a, key_b, at)),
        (Some(a), None) => Ok(Some(OneOf::First(a))),
        (None, Some(b)) => Ok(Some(OneOf::Second(b))),
        (None, None) => Ok(None),
    }
}

fn both(ls: &LoadedScene, key_a: &str, key_b: &str, at: &str) -> SceneError {
    ls.invalid(at, format!("give `{key_a}` or `{key_b}`, not both"))
}

/// Index of the station stator `stator` faces (its `station` key).
pub fn station_index(ls: &LoadedScene, stator: usize, name: &str) -> Result<usize, SceneError> {
    let stations = &ls.scene.stations;
    stations
        .iter()
        .position(|st| st.name == name)
        .ok_or_else(|| {
            let known: Vec<&str> = stations.iter().map(|s| s.name.as_str()).collect();
            ls.invalid(
                &format!("stator.{stator}.station"),
                format!(
                    "no station named `{name}` (stations: {})",
                    if known.is_empty() {
                        "none".to_string()
                    } else {
                        known.join(", ")
                    }
                ),
            )
        })
}

/// Index of entry `j` of a meshed stator's further `stations`.
pub fn extra_station_index(
    ls: &LoadedScene,
    stator: usize,
    j: usize,
    name: &str,
) -> Result<usize, SceneError> {
    let stations = &ls.scene.stations;
    stations
        .iter()
        .position(|st| st.name == name)
        .ok_or_else(|| {
            ls.invalid(
                &format!("stator.{stator}.stations.{j}"),
                format!("no station named `{name}`"),
            )
        })
}

/// The plane of the 2-D meshed stator `stator` (`plane = "stress"` or `"strain"`).
pub fn mesh_plane(
    ls: &LoadedScene,
    stator: usize,
    m: &MeshStatorSpec,
) -> Result<Plane, SceneError> {
    m.plane().ok_or_else(|| {
        ls.invalid(
            &format!("stator.{stator}.plane"),
            "must be \"stress\" or \"strain\"",
        )
    })
}

/// The analysed response component (`output.component = "x"` or `"y"`).
pub fn output_component(ls: &LoadedScene) -> Result<Component, SceneError> {
    Component::from_name(&ls.scene.output.component)
        .ok_or_else(|| ls.invalid("output.component", "must be \"x\" or \"y\""))
}

fn positive(ls: &LoadedScene, key: &str, v: f64) -> Result<(), SceneError> {
    if !(v.is_finite() && v > 0.0) {
        return Err(ls.invalid(key, format!("must be a positive finite number, got {v}")));
    }
    Ok(())
}

fn non_negative(ls: &LoadedScene, key: &str, v: f64) -> Result<(), SceneError> {
    if !(v.is_finite() && v >= 0.0) {
        return Err(ls.invalid(key, format!("must be zero or positive, got {v}")));
    }
    Ok(())
}

fn poisson(ls: &LoadedScene, key: &str, v: f64) -> Result<(), SceneError> {
    if v.is_finite() && v > -1.0 && v < 0.5 {
        Ok(())
    } else {
        Err(ls.invalid(key, format!("must lie in (−1, 0.5), got {v}")))
    }
}

/// Checks every admissibility rule that types cannot express.
pub fn validate(ls: &LoadedScene) -> Result<(), SceneError> {
    let s = &ls.scene;
    match &s.rotor {
        RotorSpec::Jeffcott(j) => validate_jeffcott(ls, j)?,
        RotorSpec::Fe(f) => validate_fe_rotor(ls, f)?,
    }
    validate_stations(ls)?;
    for (i, stator) in s.stators.iter().enumerate() {
        station_index(ls, i, stator.station())?;
        match stator {
            StatorSpec::Rod(r) => validate_rod(ls, i, r)?,
            StatorSpec::Ring(r) => validate_ring(ls, i, r)?,
            StatorSpec::Fe(f) => validate_fe_stator(ls, i, f)?,
            StatorSpec::Mesh(m) => validate_mesh_stator(ls, i, m)?,
        }
    }
    validate_run(ls)?;
    output_component(ls)?;
    validate_series(ls)?;
    Ok(())
}

fn validate_jeffcott(ls: &LoadedScene, j: &JeffcottSpec) -> Result<(), SceneError> {
    one_of(ls, ("mass", j.mass), ("disk", j.disk.as_ref()), "rotor")?;
    one_of(
        ls,
        ("stiffness", j.stiffness),
        ("shaft", j.shaft.as_ref()),
        "rotor",
    )?;
    one_of(
        ls,
        ("damping", j.damping),
        ("damping_ratio", j.damping_ratio),
        "rotor",
    )?;
    if let Some(m) = j.mass {
        positive(ls, "rotor.mass", m)?;
    }
    if let Some(n) = ls.scene.output.node.filter(|n| *n != 0) {
        return Err(ls.invalid(
            "output.node",
            format!("node {n} does not exist (a Jeffcott rotor has node 0 only)"),
        ));
    }
    if let Some(k) = j.stiffness {
        positive(ls, "rotor.stiffness", k)?;
    }
    if let Some(c) = j.damping {
        non_negative(ls, "rotor.damping", c)?;
    }
    if let Some(z) = j.damping_ratio {
        non_negative(ls, "rotor.damping_ratio", z)?;
    }
    if let Some(d) = &j.disk {
        positive(ls, "rotor.disk.diameter", d.diameter)?;
        positive(ls, "rotor.disk.thickness", d.thickness)?;
        positive(ls, "rotor.disk.density", d.density)?;
    }
    if let Some(sh) = &j.shaft {
        positive(ls, "rotor.shaft.youngs_modulus", sh.youngs_modulus)?;
        positive(ls, "rotor.shaft.diameter", sh.diameter)?;
        positive(ls, "rotor.shaft.length", sh.length)?;
    }
    for (i, u) in j.unbalance.iter().enumerate() {
        non_negative(ls, &format!("rotor.unbalance.{i}.mass"), u.mass)?;
        non_negative(ls, &format!("rotor.unbalance.{i}.radius"), u.radius)?;
        if u.node != 0 {
            return Err(ls.invalid(
                &format!("rotor.unbalance.{i}.node"),
                "a Jeffcott rotor has only node 0",
            ));
        }
    }
    Ok(())
}

fn validate_stations(ls: &LoadedScene) -> Result<(), SceneError> {
    let s = &ls.scene;
    let mut names = std::collections::HashSet::new();
    for (i, st) in s.stations.iter().enumerate() {
        let k = |f: &str| format!("station.{i}.{f}");
        positive(ls, &k("radius"), st.radius)?;
        non_negative(ls, &k("friction"), st.friction)?;
        if !names.insert(st.name.as_str()) {
            return Err(ls.invalid(&k("name"), format!("duplicate station name `{}`", st.name)));
        }
        if matches!(s.rotor, RotorSpec::Jeffcott(_)) && st.node != 0 {
            return Err(ls.invalid(&k("node"), "a Jeffcott rotor has only node 0"));
        }
    }
    Ok(())
}

fn validate_rod(ls: &LoadedScene, i: usize, r: &RodSpec) -> Result<(), SceneError> {
    let k = |f: &str| format!("stator.{i}.{f}");
    validate_clearance(ls, i, r.clearance, r.clearance_nd)?;
    positive(ls, &k("length"), r.length)?;
    positive(ls, &k("area"), r.area)?;
    one_of(
        ls,
        ("youngs_modulus", r.youngs_modulus),
        ("stiffness_ratio", r.stiffness_ratio),
        &format!("stator.{i}"),
    )?;
    if let Some(e) = r.youngs_modulus {
        positive(ls, &k("youngs_modulus"), e)?;
    }
    if let Some(e) = r.stiffness_ratio {
        positive(ls, &k("stiffness_ratio"), e)?;
    }
    non_negative(ls, &k("density"), r.density)?;
    if r.elements == 0 {
        return Err(ls.invalid(&k("elements"), "must be at least 1"));
    }
    for v in r.rayleigh {
        non_negative(ls, &k("rayleigh"), v)?;
    }
    Ok(())
}

fn validate_ring(ls: &LoadedScene, i: usize, r: &RingSpec) -> Result<(), SceneError> {
    let k = |f: &str| format!("stator.{i}.{f}");
    validate_clearance(ls, i, r.clearance, r.clearance_nd)?;
    one_of(
        ls,
        ("stiffness", r.stiffness),
        ("stiffness_ratio", r.stiffness_ratio),
        &format!("stator.{i}"),
    )?;
    if let Some(v) = r.stiffness {
        positive(ls, &k("stiffness"), v)?;
    }
    if let Some(v) = r.stiffness_ratio {
        positive(ls, &k("stiffness_ratio"), v)?;
    }
    non_negative(ls, &k("mass"), r.mass)?;
    non_negative(ls, &k("damping"), r.damping)?;
    Ok(())
}

fn validate_fe_stator(ls: &LoadedScene, i: usize, f: &FeStatorSpec) -> Result<(), SceneError> {
    let k = |x: &str| format!("stator.{i}.{x}");
    let nn = f.nodes.len();
    if nn == 0 {
        return Err(ls.invalid(&k("nodes"), "a stator needs at least one node"));
    }
    let missing = |key: String, n: usize| {
        ls.invalid(
            &key,
            format!("node {n} does not exist (stator has {nn} nodes)"),
        )
    };
    for (e, el) in f.elements.iter().enumerate() {
        let ek = |x: &str| format!("stator.{i}.elements.{e}.{x}");
        match el {
            FeElementSpec::Bar {
                nodes,
                youngs_modulus,
                area,
                density,
            } => {
                if let Some(n) = nodes.iter().find(|n| **n >= nn) {
                    return Err(missing(ek("nodes"), *n));
                }
                let a = f.nodes[nodes[0]];
                let b = f.nodes[nodes[1]];
                if (a[0] - b[0]).hypot(a[1] - b[1]) <= 0.0 {
                    return Err(ls.invalid(&ek("nodes"), "zero-length bar"));
                }
                positive(ls, &ek("youngs_modulus"), *youngs_modulus)?;
                positive(ls, &ek("area"), *area)?;
                non_negative(ls, &ek("density"), *density)?;
            }
            FeElementSpec::Spring {
                node, stiffness, ..
            } => {
                if *node >= nn {
                    return Err(missing(ek("node"), *node));
                }
                positive(ls, &ek("stiffness"), *stiffness)?;
            }
        }
    }
    for fx in &f.fixed {
        if fx[0] >= nn || fx[1] > 1 {
            return Err(ls.invalid(
                &k("fixed"),
                format!(
                    "[{}, {}] is not a valid [node, component] (component 0 = x, 1 = y)",
                    fx[0], fx[1]
                ),
            ));
        }
    }
    if f.contact_nodes.is_empty() {
        return Err(ls.invalid(&k("contact_nodes"), "no contact nodes given"));
    }
    if let Some(c) = f.contact_nodes.iter().find(|c| **c >= nn) {
        return Err(missing(k("contact_nodes"), *c));
    }
    for (n, m) in &f.point_masses {
        if *n >= nn {
            return Err(ls.invalid(&k("point_masses"), format!("node {n} does not exist")));
        }
        non_negative(ls, &k("point_masses"), *m)?;
    }
    for v in f.rayleigh {
        non_negative(ls, &k("rayleigh"), v)?;
    }
    Ok(())
}

fn validate_run(ls: &LoadedScene) -> Result<(), SceneError> {
    let r = &ls.scene.run;
    let n_speed = [
        r.speed_ratio.is_some(),
        r.speed.is_some(),
        r.sweep.is_some(),
    ]
    .iter()
    .filter(|b| **b)
    .count();
    if n_speed != 1 {
        return Err(ls.invalid(
            "run",
            "give exactly one of `speed_ratio`, `speed` or `[run.sweep]`",
        ));
    }
    if let Some(v) = r.speed_ratio {
        positive(ls, "run.speed_ratio", v)?;
    }
    if let Some(v) = r.speed {
        positive(ls, "run.speed", v)?;
    }
    if let Some(sw) = &r.sweep {
        positive(ls, "run.sweep.from", sw.from)?;
        positive(ls, "run.sweep.to", sw.to)?;
        positive(ls, "run.sweep.step", sw.step)?;
        if sw.to < sw.from {
            return Err(ls.invalid("run.sweep.to", "must not be below `from`"));
        }
        if let Some(v) = &sw.vary {
            if v.values.is_empty() {
                return Err(ls.invalid("run.sweep.vary.values", "no values"));
            }
        }
    }
    if r.revolutions <= r.transient_revolutions {
        return Err(ls.invalid(
            "run.revolutions",
            format!(
                "must exceed transient_revolutions ({}), got {}",
                r.transient_revolutions, r.revolutions
            ),
        ));
    }
    if let Some(dt) = r.dt {
        positive(ls, "run.dt", dt)?;
    }
    positive(ls, "run.harmonics", r.harmonics)?;
    if r.samples_per_rev < 8 {
        return Err(ls.invalid("run.samples_per_rev", "must be at least 8"));
    }
    Ok(())
}

/// `Err` naming `key` when rotor node `n` is not one of the `nodes` shaft nodes.
fn node_ok(ls: &LoadedScene, key: String, n: usize, nodes: usize) -> Result<(), SceneError> {
    if n >= nodes {
        Err(ls.invalid(
            &key,
            format!(
                "node {n} does not exist (the shaft has nodes 0..={})",
                nodes - 1
            ),
        ))
    } else {
        Ok(())
    }
}

fn validate_fe_rotor(ls: &LoadedScene, f: &FeRotorSpec) -> Result<(), SceneError> {
    let nodes = validate_shaft(ls, f)?;
    validate_disks(ls, f, nodes)?;
    validate_bearings(ls, f, nodes)?;
    validate_supports(ls, f, nodes)?;
    for (i, p) in f.point_mass.iter().enumerate() {
        node_ok(ls, format!("rotor.point_mass.{i}.node"), p.node, nodes)?;
        non_negative(ls, &format!("rotor.point_mass.{i}.mass"), p.mass)?;
    }
    for (i, u) in f.unbalance.iter().enumerate() {
        node_ok(ls, format!("rotor.unbalance.{i}.node"), u.node, nodes)?;
        non_negative(ls, &format!("rotor.unbalance.{i}.mass"), u.mass)?;
        non_negative(ls, &format!("rotor.unbalance.{i}.radius"), u.radius)?;
    }
    for v in f.rayleigh {
        non_negative(ls, "rotor.rayleigh", v)?;
    }
    if let Some(md) = &f.modal_damping {
        non_negative(ls, "rotor.modal_damping.ratio", md.ratio)?;
        if let Some(w) = md.max_frequency {
            positive(ls, "rotor.modal_damping.max_frequency", w)?;
        }
        if md.modes == Some(0) {
            return Err(ls.invalid("rotor.modal_damping.modes", "must be at least 1"));
        }
    }
    for (i, st) in ls.scene.stations.iter().enumerate() {
        node_ok(ls, format!("station.{i}.node"), st.node, nodes)?;
    }
    if let Some(n) = ls.scene.output.node {
        node_ok(ls, "output.node".into(), n, nodes)?;
    }
    Ok(())
}

/// Checks the shaft segments; returns the number of shaft nodes.
fn validate_shaft(ls: &LoadedScene, f: &FeRotorSpec) -> Result<usize, SceneError> {
    if f.shaft.is_empty() {
        return Err(ls.invalid(
            "rotor.shaft",
            "an FE rotor needs at least one [[rotor.shaft]] segment",
        ));
    }
    let mut nodes = 1;
    for (i, seg) in f.shaft.iter().enumerate() {
        let k = |x: &str| format!("rotor.shaft.{i}.{x}");
        positive(ls, &k("length"), seg.length)?;
        positive(ls, &k("outer_diameter"), seg.outer_diameter)?;
        non_negative(ls, &k("inner_diameter"), seg.inner_diameter)?;
        if seg.inner_diameter >= seg.outer_diameter {
            return Err(ls.invalid(&k("inner_diameter"), "must be smaller than outer_diameter"));
        }
        if seg.elements == 0 {
            return Err(ls.invalid(&k("elements"), "must be at least 1"));
        }
        nodes += seg.elements;
        let named = match &seg.material {
            Some(m) => Some(material(m).ok_or_else(|| {
                ls.invalid(&k("material"), format!("unknown material `{m}` (known: steel, aluminium, titanium; or give youngs_modulus, poisson, density)"))
            })?),
            None => None,
        };
        if named.is_none() && (seg.youngs_modulus.is_none() || seg.density.is_none()) {
            return Err(ls.invalid(
                &format!("rotor.shaft.{i}"),
                "give `material` or `youngs_modulus` and `density`",
            ));
        }
        if let Some(e) = seg.youngs_modulus {
            positive(ls, &k("youngs_modulus"), e)?;
        }
        if let Some(r) = seg.density {
            non_negative(ls, &k("density"), r)?;
        }
        if let Some(nu) = seg.poisson {
            if !(nu > -1.0 && nu < 0.5) {
                return Err(ls.invalid(&k("poisson"), format!("must lie in (−1, 0.5), got {nu}")));
            }
        }
    }
    Ok(nodes)
}

fn validate_disks(ls: &LoadedScene, f: &FeRotorSpec, nodes: usize) -> Result<(), SceneError> {
    for (i, d) in f.disk.iter().enumerate() {
        node_ok(ls, format!("rotor.disk.{i}.node"), d.node, nodes)?;
        let inertial = d.mass.is_some();
        let geo = d.outer_diameter.is_some() || d.width.is_some();
        if inertial == geo {
            return Err(ls.invalid(&format!("rotor.disk.{i}"), "give `mass` (+ inertias) or the geometry `outer_diameter`, `width` (+ `bore`, `density`/`material`), not both"));
        }
        if geo
            && (d.outer_diameter.is_none()
                || d.width.is_none()
                || (d.density.is_none() && d.material.is_none()))
        {
            return Err(ls.invalid(
                &format!("rotor.disk.{i}"),
                "geometry needs `outer_diameter`, `width` and `density` or `material`",
            ));
        }
        for (name, v) in [
            ("mass", d.mass),
            ("polar_inertia", d.polar_inertia),
            ("diametral_inertia", d.diametral_inertia),
            ("outer_diameter", d.outer_diameter),
            ("width", d.width),
        ] {
            if let Some(v) = v {
                non_negative(ls, &format!("rotor.disk.{i}.{name}"), v)?;
            }
        }
        if let Some(m) = &d.material {
            if material(m).is_none() {
                return Err(ls.invalid(
                    &format!("rotor.disk.{i}.material"),
                    format!("unknown material `{m}`"),
                ));
            }
        }
    }
    Ok(())
}

fn validate_bearings(ls: &LoadedScene, f: &FeRotorSpec, nodes: usize) -> Result<(), SceneError> {
    if f.bearing.is_empty() {
        return Err(ls.invalid(
            "rotor",
            "an FE rotor needs at least one [[rotor.bearing]] (a free rotor has no equilibrium)",
        ));
    }
    for (i, b) in f.bearing.iter().enumerate() {
        node_ok(ls, format!("rotor.bearing.{i}.node"), b.node, nodes)?;
        let n = b.speeds.len();
        if b.speeds.windows(2).any(|w| w[1] <= w[0]) {
            return Err(ls.invalid(
                &format!("rotor.bearing.{i}.speeds"),
                "must be strictly ascending",
            ));
        }
        let all = [
            ("stiffness", &b.stiffness),
            ("damping", &b.damping),
            ("kxx", &b.kxx),
            ("kxy", &b.kxy),
            ("kyx", &b.kyx),
            ("kyy", &b.kyy),
            ("cxx", &b.cxx),
            ("cxy", &b.cxy),
            ("cyx", &b.cyx),
            ("cyy", &b.cyy),
        ];
        for (name, v) in all {
            if let Some(ScalarOrTable::Table(t)) = v {
                if n == 0 {
                    return Err(ls.invalid(
                        &format!("rotor.bearing.{i}.{name}"),
                        "a table of values needs `speeds` (one value per speed); give a number for a coefficient that does not vary",
                    ));
                }
                if t.len() != n {
                    return Err(ls.invalid(
                        &format!("rotor.bearing.{i}.{name}"),
                        format!("table has {} values but `speeds` has {n}", t.len()),
                    ));
                }
            }
        }
        if b.stiffness.is_some() && (b.kxx.is_some() || b.kyy.is_some()) {
            return Err(ls.invalid(
                &format!("rotor.bearing.{i}"),
                "give `stiffness` or `kxx`/`kyy`, not both",
            ));
        }
        if b.stiffness.is_none() && b.kxx.is_none() && b.kyy.is_none() {
            return Err(ls.invalid(
                &format!("rotor.bearing.{i}"),
                "missing stiffness (`stiffness` or `kxx`, `kyy`)",
            ));
        }
        if let Some(p) = &b.pedestal {
            let k = |x: &str| format!("rotor.bearing.{i}.pedestal.{x}");
            positive(ls, &k("mass"), p.mass)?;
            positive(ls, &k("stiffness"), p.stiffness)?;
            non_negative(ls, &k("damping"), p.damping)?;
        }
    }
    Ok(())
}

fn validate_supports(ls: &LoadedScene, f: &FeRotorSpec, nodes: usize) -> Result<(), SceneError> {
    for (name, on, flag, mode, list) in [
        ("axial_support", f.axial, "axial", "axial", &f.axial_support),
        (
            "torsional_support",
            f.torsion,
            "torsion",
            "torsional",
            &f.torsional_support,
        ),
    ] {
        for (i, g) in list.iter().enumerate() {
            node_ok(ls, format!("rotor.{name}.{i}.node"), g.node, nodes)?;
            positive(ls, &format!("rotor.{name}.{i}.stiffness"), g.stiffness)?;
            non_negative(ls, &format!("rotor.{name}.{i}.damping"), g.damping)?;
            if !on {
                return Err(ls.invalid(
                    &format!("rotor.{name}.{i}"),
                    format!("needs `{flag} = true` in [rotor] (the rotor has no such DOFs)"),
                ));
            }
        }
        if on && list.is_empty() {
            return Err(ls.invalid(
                &format!("rotor.{flag}"),
                format!("`{flag} = true` needs at least one [[rotor.{name}]] (without one the rotor has a free rigid-body {mode} mode and no equilibrium)"),
            ));
        }
    }
    Ok(())
}

/// Checks `output.vtk`, `output.hdf5` and `output.per_speed`.
fn validate_series(ls: &LoadedScene) -> Result<(), SceneError> {
    let o = &ls.scene.output;
    let revs = ls.scene.run.revolutions as f64;
    for (name, spec) in [("vtk", &o.vtk), ("hdf5", &o.hdf5)] {
        let Some(sp) = spec else { continue };
        let k = |f: &str| format!("output.{name}.{f}");
        if sp.every == Some(0) {
            return Err(ls.invalid(&k("every"), "must be at least 1 (steps between frames)"));
        }
        if sp.fields.is_empty() {
            return Err(ls.invalid(&k("fields"), "no fields: leave the key out to write all"));
        }
        non_negative(ls, &k("from_revolution"), sp.from_revolution)?;
        let to = sp.to_revolution.unwrap_or(revs);
        if !(to.is_finite() && to >= sp.from_revolution && sp.from_revolution <= revs) {
            return Err(ls.invalid(
                &k("to_revolution"),
                format!(
                    "the window [{}, {to}] revolutions must be ordered and overlap the run (0 to {revs})",
                    sp.from_revolution
                ),
            ));
        }
    }
    if o.per_speed != PerSpeed::All(false) && o.vtk.is_none() && o.hdf5.is_none() {
        return Err(ls.invalid(
            "output.per_speed",
            "asks for per-speed time series, but neither `output.vtk` nor `output.hdf5` is given",
        ));
    }
    if let PerSpeed::Speeds(v) = &o.per_speed {
        for x in v {
            positive(ls, "output.per_speed", *x)?;
        }
    }
    Ok(())
}

/// Admissibility of a meshed stator's values (what the mesh needs is checked when it is read).
fn validate_mesh_stator(ls: &LoadedScene, i: usize, m: &MeshStatorSpec) -> Result<(), SceneError> {
    let k = |f: &str| format!("stator.{i}.{f}");
    if m.geometry.trim().is_empty() {
        return Err(ls.invalid(&k("geometry"), "empty path"));
    }
    for (name, v) in &m.parameters {
        if !v.is_finite() {
            return Err(ls.invalid(&k(&format!("parameters.{name}")), "must be finite"));
        }
    }
    if !(m.order == 1 || m.order == 2) {
        return Err(ls.invalid(&k("order"), format!("must be 1 or 2, got {}", m.order)));
    }
    positive(ls, &k("size_factor"), m.size_factor)?;
    mesh_plane(ls, i, m)?;
    if let Some(t) = m.thickness {
        positive(ls, &k("thickness"), t)?;
    }
    positive(ls, &k("youngs_modulus"), m.youngs_modulus)?;
    poisson(ls, &k("poisson_ratio"), m.poisson_ratio)?;
    non_negative(ls, &k("density"), m.density)?;
    for (r, reg) in m.regions.iter().enumerate() {
        let rk = |f: &str| format!("stator.{i}.regions.{r}.{f}");
        if let Some(v) = reg.youngs_modulus {
            positive(ls, &rk("youngs_modulus"), v)?;
        }
        if let Some(v) = reg.poisson_ratio {
            poisson(ls, &rk("poisson_ratio"), v)?;
        }
        if let Some(v) = reg.density {
            non_negative(ls, &rk("density"), v)?;
        }
        if let Some(v) = reg.thickness {
            positive(ls, &rk("thickness"), v)?;
        }
    }
    for (r, sp) in m.springs.iter().enumerate() {
        for v in sp.stiffness {
            non_negative(ls, &format!("stator.{i}.springs.{r}.stiffness"), v)?;
        }
    }
    for (r, fr) in m.frames.iter().enumerate() {
        validate_frame(ls, &format!("stator.{i}.frames.{r}"), fr)?;
    }
    at_most_one(
        ls,
        ("clearance", m.clearance),
        ("clearance_nd", m.clearance_nd),
        &format!("stator.{i}"),
    )?;
    if let Some(v) = m.clearance {
        positive(ls, &k("clearance"), v)?;
    }
    if let Some(v) = m.clearance_nd {
        positive(ls, &k("clearance_nd"), v)?;
    }
    for v in m.rayleigh {
        non_negative(ls, &k("rayleigh"), v)?;
    }
    for (j, name) in m.stations.iter().enumerate() {
        extra_station_index(ls, i, j, name)?;
    }
    if !m.axial_origin.is_finite() {
        return Err(ls.invalid(&k("axial_origin"), "must be finite"));
    }
    if m.fixed.is_empty() && m.fixed_x.is_empty() && m.fixed_y.is_empty() && m.springs.is_empty() {
        return Err(ls.invalid(
            &k("fixed"),
            "the stator has no supports: name a fixed group or springs",
        ));
    }
    Ok(())
}

/// A meshed stator's `[[stator.frames]]` entry at dotted key `at`.
fn validate_frame(ls: &LoadedScene, at: &str, fr: &FrameSpec) -> Result<(), SceneError> {
    let fk = |f: &str| format!("{at}.{f}");
    positive(ls, &fk("youngs_modulus"), fr.youngs_modulus)?;
    positive(ls, &fk("area"), fr.area)?;
    if let Some(v) = fr.inertia {
        positive(ls, &fk("inertia"), v)?;
    }
    if let Some(v) = fr.shear_factor {
        positive(ls, &fk("shear_factor"), v)?;
        if fr.inertia.is_none() {
            return Err(ls.invalid(
                &fk("shear_factor"),
                "a shear factor needs `inertia` (bars carry no shear)",
            ));
        }
    }
    poisson(ls, &fk("poisson_ratio"), fr.poisson_ratio)?;
    non_negative(ls, &fk("density"), fr.density)?;
    Ok(())
}

fn validate_clearance(
    ls: &LoadedScene,
    i: usize,
    c: Option<f64>,
    c_nd: Option<f64>,
) -> Result<(), SceneError> {
    one_of(
        ls,
        ("clearance", c),
        ("clearance_nd", c_nd),
        &format!("stator.{i}"),
    )?;
    if let Some(v) = c {
        positive(ls, &format!("stator.{i}.clearance"), v)?;
    }
    if let Some(v) = c_nd {
        positive(ls, &format!("stator.{i}.clearance_nd"), v)?;
    }
    Ok(())
}
