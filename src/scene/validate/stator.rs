//! Rules of `[[stator]]`: rods, rings, FE and meshed stators.

use super::checks::*;
use crate::error::SceneError;
use crate::scene::*;

pub(super) fn validate_rod(ls: &LoadedScene, i: usize, r: &RodSpec) -> Result<(), SceneError> {
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
    if !(1..=MAX_ROD_ELEMENTS).contains(&r.elements) {
        return Err(ls.invalid(
            &k("elements"),
            format!("must lie in 1 ..= {MAX_ROD_ELEMENTS}, got {}", r.elements),
        ));
    }
    degrees(ls, &k("angle_deg"), r.angle_deg)?;
    for v in r.rayleigh {
        non_negative(ls, &k("rayleigh"), v)?;
    }
    if r.density == 0.0 && r.rayleigh != [0.0; 2] {
        return Err(ls.invalid(
            &k("rayleigh"),
            "a massless rod (density = 0) enters the time loop as its static compliance and has no velocity to damp (for damping at the contact use `contact_damping`, N·s/m): give `density` or leave `rayleigh` out",
        ));
    }
    Ok(())
}

pub(super) fn validate_ring(ls: &LoadedScene, i: usize, r: &RingSpec) -> Result<(), SceneError> {
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
    if let Some(v) = r.stiffness_y {
        positive(ls, &k("stiffness_y"), v)?;
    }
    non_negative(ls, &k("mass"), r.mass)?;
    non_negative(ls, &k("damping"), r.damping)?;
    if let Some(v) = r.damping_y {
        non_negative(ls, &k("damping_y"), v)?;
        if r.mass == 0.0 {
            return Err(ls.invalid(
                &k("damping_y"),
                format!("a massless ring (`{}` = 0) has no support to damp: give the ring `mass` for support damping", k("mass")),
            ));
        }
    }
    if r.kinematics == "radial" && r.stiffness_y.is_some() {
        return Err(ls.invalid(
            &k("stiffness_y"),
            "`radial` kinematics is the isotropic radially elastic stator (force k_s(R − δ) along the rotor's radius): an anisotropic ring needs `kinematics = \"exact\"`",
        ));
    }
    match r.kinematics.as_str() {
        "exact" => {}
        "radial" if r.mass > 0.0 => {
            return Err(ls.invalid(
                &k("kinematics"),
                "`radial` kinematics (the ring's centre moves only along the contact normal) is a massless stator's contact law: give mass = 0 or use `exact`",
            ))
        }
        "radial" => {}
        other => {
            return Err(ls.invalid(
                &k("kinematics"),
                format!("unknown ring kinematics `{other}`: `exact` (the ring takes the whole contact force, default) or `radial` (force along the rotor's radius, friction to ground)"),
            ))
        }
    }
    if r.mass == 0.0 && r.damping > 0.0 {
        return Err(ls.invalid(
            &k("damping"),
            format!("a massless ring (`{}` = 0) has no support to damp: for a dashpot that acts while the rotor touches the ring (ROSS's contact damping) use `contact_damping` (N·s/m); for support damping give the ring `mass`", k("mass")),
        ));
    }
    Ok(())
}

pub(super) fn validate_fe_stator(
    ls: &LoadedScene,
    i: usize,
    f: &FeStatorSpec,
) -> Result<(), SceneError> {
    let k = |x: &str| format!("stator.{i}.{x}");
    let nn = f.nodes.len();
    if nn == 0 {
        return Err(ls.invalid(&k("nodes"), "a stator needs at least one node"));
    }
    for (n, xy) in f.nodes.iter().enumerate() {
        for x in xy {
            finite(ls, &k(&format!("nodes.{n}")), *x)?;
        }
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
                node,
                stiffness,
                angle_deg,
            } => {
                if *node >= nn {
                    return Err(missing(ek("node"), *node));
                }
                positive(ls, &ek("stiffness"), *stiffness)?;
                degrees(ls, &ek("angle_deg"), *angle_deg)?;
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

/// Admissibility of a meshed stator's values (what the mesh needs is checked when it is read).
pub(super) fn validate_mesh_stator(
    ls: &LoadedScene,
    i: usize,
    m: &MeshStatorSpec,
) -> Result<(), SceneError> {
    let k = |f: &str| format!("stator.{i}.{f}");
    mesh_names_ok(ls, i, m)?;
    for (name, v) in &m.parameters {
        finite(ls, &k(&format!("parameters.{name}")), *v)?;
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
    mesh_parts_ok(ls, i, m)?;
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
    degrees(ls, &k("approach_deg"), m.approach_deg)?;
    if !m.axial_origin.is_finite() {
        return Err(ls.invalid(&k("axial_origin"), "must be finite"));
    }
    if m.fixed.is_empty() && m.fixed_x.is_empty() && m.fixed_y.is_empty() && m.springs.is_empty() {
        return Err(ls.invalid(
            &k("fixed"),
            format!("the stator has no supports: name a fixed group (`stator.{i}.fixed`, `fixed_x`, `fixed_y`) or springs (`stator.{i}.springs`)"),
        ));
    }
    Ok(())
}

/// A meshed stator's names: a geometry path, and no empty group name among its supports,
/// contact group, regions, springs and frames.
fn mesh_names_ok(ls: &LoadedScene, i: usize, m: &MeshStatorSpec) -> Result<(), SceneError> {
    let k = |f: &str| format!("stator.{i}.{f}");
    if m.geometry.trim().is_empty() {
        return Err(ls.invalid(&k("geometry"), "empty path"));
    }
    let groups = [
        ("fixed", &m.fixed),
        ("fixed_x", &m.fixed_x),
        ("fixed_y", &m.fixed_y),
        ("fixed_z", &m.fixed_z),
    ];
    for (name, list) in groups {
        if let Some(j) = list.iter().position(|g| g.trim().is_empty()) {
            return Err(ls.invalid(&k(&format!("{name}.{j}")), "empty group name"));
        }
    }
    let named = [("contact_group", m.contact_group.as_str())]
        .into_iter()
        .chain(m.regions.iter().map(|r| ("regions", r.group.as_str())))
        .chain(m.springs.iter().map(|r| ("springs", r.group.as_str())))
        .chain(m.frames.iter().map(|r| ("frames", r.group.as_str())));
    let mut seen = std::collections::HashMap::new();
    for (name, g) in named {
        let j = seen.entry(name).or_insert(0usize);
        if g.trim().is_empty() {
            let key = if name == "contact_group" {
                k(name)
            } else {
                k(&format!("{name}.{j}.group"))
            };
            return Err(ls.invalid(&key, "empty group name"));
        }
        *j += 1;
    }
    Ok(())
}

/// A meshed stator's regions (their material overrides), springs (stiffness ≥ 0) and frames.
fn mesh_parts_ok(ls: &LoadedScene, i: usize, m: &MeshStatorSpec) -> Result<(), SceneError> {
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
    Ok(())
}

/// A meshed stator's `[[stator.frames]]` entry at dotted key `at`.
pub(super) fn validate_frame(ls: &LoadedScene, at: &str, fr: &FrameSpec) -> Result<(), SceneError> {
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

pub(super) fn validate_clearance(
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

/// The contact dashpot of any stator kind: `contact_damping` ≥ 0 (N·s/m) and
/// `contact_damping_mode` one of `"normal"`, `"full"` (a mode with `contact_damping = 0` does
/// nothing: a study may vary the coefficient down to 0). Whether the stator is massless is checked when it is built.
pub(super) fn validate_contact_damping(
    ls: &LoadedScene,
    i: usize,
    s: &StatorSpec,
) -> Result<(), SceneError> {
    let (c, mode) = s.contact_damping();
    let key = format!("stator.{i}.contact_damping");
    non_negative(ls, &key, c)?;
    let stick = ls
        .scene
        .stations
        .iter()
        .position(|st| st.name == s.station() && st.stick);
    if let (true, Some(j)) = (c > 0.0, stick) {
        return Err(ls.invalid(
            &key,
            format!("a contact dashpot cannot act on a station with stick (`station.{j}.stick = true`): the dashpot's force enters the normal problem only; leave one of them out"),
        ));
    }
    let mode_key = format!("{key}_mode");
    if !matches!(mode, "normal" | "full") {
        return Err(ls.invalid(
            &mode_key,
            format!("must be \"normal\" or \"full\", got {mode:?}"),
        ));
    }
    Ok(())
}
