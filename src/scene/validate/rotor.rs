//! Rules of `[rotor]` (Jeffcott and FE) and `[[station]]`.

use super::checks::*;
use crate::error::SceneError;
use crate::scene::*;

pub(super) fn validate_jeffcott(ls: &LoadedScene, j: &JeffcottSpec) -> Result<(), SceneError> {
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
        damping_ratio_bound(ls, "rotor.damping_ratio", z)?;
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
        degrees(ls, &format!("rotor.unbalance.{i}.phase_deg"), u.phase_deg)?;
        if u.node != 0 {
            return Err(ls.invalid(
                &format!("rotor.unbalance.{i}.node"),
                "a Jeffcott rotor has only node 0",
            ));
        }
    }
    Ok(())
}

pub(super) fn validate_stations(ls: &LoadedScene) -> Result<(), SceneError> {
    let s = &ls.scene;
    if s.stations.is_empty() && !s.stators.is_empty() {
        return Err(ls.invalid(
            "station",
            "no [[station]]: every stator faces one (its `station` key)",
        ));
    }
    let mut names = std::collections::HashSet::new();
    for (i, st) in s.stations.iter().enumerate() {
        let k = |f: &str| format!("station.{i}.{f}");
        if st.name.trim().is_empty() {
            return Err(ls.invalid(&k("name"), "empty name: the stators refer to it"));
        }
        positive(ls, &k("radius"), st.radius)?;
        non_negative(ls, &k("friction"), st.friction)?;
        if st.stick && st.friction <= 0.0 {
            return Err(ls.invalid(
                &k("stick"),
                format!("stick needs friction: `station.{i}.friction` is {}, and a pair sticks only inside the cone |t| ≤ μ p (give μ > 0, or leave `stick` out)", st.friction),
            ));
        }
        if !names.insert(st.name.as_str()) {
            return Err(ls.invalid(&k("name"), format!("duplicate station name `{}`", st.name)));
        }
        if matches!(s.rotor, RotorSpec::Jeffcott(_)) && st.node != 0 {
            return Err(ls.invalid(&k("node"), "a Jeffcott rotor has only node 0"));
        }
    }
    Ok(())
}

/// `Err` naming `key` when rotor node `n` is not one of the `nodes` shaft nodes.
pub(super) fn node_ok(
    ls: &LoadedScene,
    key: String,
    n: usize,
    nodes: usize,
) -> Result<(), SceneError> {
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

pub(super) fn validate_fe_rotor(ls: &LoadedScene, f: &FeRotorSpec) -> Result<(), SceneError> {
    let nodes = validate_shaft(ls, f)?;
    dense_ok(ls, f, nodes)?;
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
        degrees(ls, &format!("rotor.unbalance.{i}.phase_deg"), u.phase_deg)?;
    }
    for v in f.rayleigh {
        non_negative(ls, "rotor.rayleigh", v)?;
    }
    if let Some(md) = &f.modal_damping {
        non_negative(ls, "rotor.modal_damping.ratio", md.ratio)?;
        damping_ratio_bound(ls, "rotor.modal_damping.ratio", md.ratio)?;
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

/// The rotor's DOFs (4 a shaft node, 2 a pedestal, 1 a node's axial and torsional DOF each)
/// within what its dense operations may cost ([`dense_rotor_cost`]); the error names the
/// segment with the most elements and every segment's count.
fn dense_ok(ls: &LoadedScene, f: &FeRotorSpec, nodes: usize) -> Result<(), SceneError> {
    let per_node = 4 + usize::from(f.axial) + usize::from(f.torsion);
    let pedestals = f.bearing.iter().filter(|b| b.pedestal.is_some()).count();
    let dofs = nodes.saturating_mul(per_node).saturating_add(2 * pedestals);
    let Some(why) = dense_rotor_cost(dofs).excess() else {
        return Ok(());
    };
    let (most, _) = (f.shaft.iter().enumerate())
        .max_by_key(|(i, s)| (s.elements, std::cmp::Reverse(*i)))
        .unwrap_or((0, &f.shaft[0]));
    let keys: Vec<String> = (f.shaft.iter().enumerate())
        .map(|(i, s)| format!("rotor.shaft.{i}.elements = {}", s.elements))
        .collect();
    Err(ls.invalid(
        &format!("rotor.shaft.{most}.elements"),
        format!(
            "the FE rotor ({}) {why}: use fewer elements",
            keys.join(", ")
        ),
    ))
}

/// Checks the shaft segments; returns the number of shaft nodes.
pub(super) fn validate_shaft(ls: &LoadedScene, f: &FeRotorSpec) -> Result<usize, SceneError> {
    if f.shaft.is_empty() {
        return Err(ls.invalid(
            "rotor.shaft",
            "an FE rotor needs at least one [[rotor.shaft]] segment",
        ));
    }
    let mut nodes: usize = 1;
    for (i, seg) in f.shaft.iter().enumerate() {
        let k = |x: &str| format!("rotor.shaft.{i}.{x}");
        positive(ls, &k("length"), seg.length)?;
        positive(ls, &k("outer_diameter"), seg.outer_diameter)?;
        non_negative(ls, &k("inner_diameter"), seg.inner_diameter)?;
        if seg.inner_diameter >= seg.outer_diameter {
            return Err(ls.invalid(&k("inner_diameter"), "must be smaller than outer_diameter"));
        }
        if let Some(od) = seg.outer_diameter_right {
            positive(ls, &k("outer_diameter_right"), od)?;
        }
        if let Some(id) = seg.inner_diameter_right {
            non_negative(ls, &k("inner_diameter_right"), id)?;
        }
        let (od_r, id_r) = (
            seg.outer_diameter_right.unwrap_or(seg.outer_diameter),
            seg.inner_diameter_right.unwrap_or(seg.inner_diameter),
        );
        if id_r >= od_r {
            let key = if seg.inner_diameter_right.is_some() {
                "inner_diameter_right"
            } else {
                "outer_diameter_right"
            };
            return Err(ls.invalid(
                &k(key),
                format!("the right end needs inner diameter {id_r} < outer diameter {od_r}"),
            ));
        }
        if seg.elements == 0 {
            return Err(ls.invalid(&k("elements"), "must be at least 1"));
        }
        nodes = nodes.saturating_add(seg.elements);
        if nodes > MAX_ROTOR_NODES {
            return Err(ls.invalid(
                &k("elements"),
                format!(
                    "{} elements make a shaft of more than {MAX_ROTOR_NODES} nodes",
                    seg.elements
                ),
            ));
        }
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
            // A massless shaft leaves the nodes without disks massless: M is singular.
            positive(ls, &k("density"), r)?;
        }
        if let Some(nu) = seg.poisson {
            if !(nu > -1.0 && nu < 0.5) {
                return Err(ls.invalid(
                    &k("poisson"),
                    format!("must lie in (−1, 0.5), got {}", show(nu)),
                ));
            }
        }
    }
    Ok(nodes)
}

pub(super) fn validate_disks(
    ls: &LoadedScene,
    f: &FeRotorSpec,
    nodes: usize,
) -> Result<(), SceneError> {
    for (i, d) in f.disk.iter().enumerate() {
        node_ok(ls, format!("rotor.disk.{i}.node"), d.node, nodes)?;
        let inertial = d.mass.is_some();
        let geo = d.outer_diameter.is_some() || d.width.is_some();
        if inertial == geo {
            return Err(ls.invalid(&format!("rotor.disk.{i}"), "give `mass` (+ inertias) or the geometry `outer_diameter`, `width` (+ `bore`, `density`/`material`), not both"));
        }
        for (name, v) in [("outer_diameter", d.outer_diameter), ("width", d.width)] {
            if let Some(v) = v {
                positive(ls, &format!("rotor.disk.{i}.{name}"), v)?;
            }
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
        if let Some(r) = d.density {
            positive(ls, &format!("rotor.disk.{i}.density"), r)?;
        }
        non_negative(ls, &format!("rotor.disk.{i}.bore"), d.bore)?;
        if d.outer_diameter.is_some_and(|od| d.bore >= od) {
            return Err(ls.invalid(
                &format!("rotor.disk.{i}.bore"),
                "must be smaller than outer_diameter",
            ));
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

pub(super) fn validate_bearings(
    ls: &LoadedScene,
    f: &FeRotorSpec,
    nodes: usize,
) -> Result<(), SceneError> {
    if f.bearing.is_empty() {
        return Err(ls.invalid(
            "rotor.bearing",
            "an FE rotor needs at least one [[rotor.bearing]] (a free rotor has no equilibrium)",
        ));
    }
    for (i, b) in f.bearing.iter().enumerate() {
        node_ok(ls, format!("rotor.bearing.{i}.node"), b.node, nodes)?;
        let n = b.speeds.len();
        for (j, w) in b.speeds.iter().enumerate() {
            non_negative(ls, &format!("rotor.bearing.{i}.speeds.{j}"), *w)?;
        }
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
            let key = format!("rotor.bearing.{i}.{name}");
            // Direct stiffness and damping resist motion (≥ 0); cross-coupled ones take any sign.
            let direct = !matches!(name, "kxy" | "kyx" | "cxy" | "cyx");
            let values: &[f64] = match v {
                None => &[],
                Some(ScalarOrTable::Scalar(x)) => std::slice::from_ref(x),
                Some(ScalarOrTable::Table(t)) => {
                    if n == 0 {
                        return Err(ls.invalid(
                            &key,
                            "a table of values needs `speeds` (rad/s), one per value",
                        ));
                    }
                    if t.len() != n {
                        return Err(ls.invalid(
                            &key,
                            format!("table has {} values but `speeds` has {n}", t.len()),
                        ));
                    }
                    t
                }
            };
            for x in values {
                if direct {
                    non_negative(ls, &key, *x)?;
                } else {
                    finite(ls, &key, *x)?;
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

pub(super) fn validate_supports(
    ls: &LoadedScene,
    f: &FeRotorSpec,
    nodes: usize,
) -> Result<(), SceneError> {
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
            // 0 is ROSS's kzz = 0: a damper alone, or nothing; the DOF is then free if no
            // other support holds it (a rigid-body mode, see `FeRotor::free_axial`).
            non_negative(ls, &format!("rotor.{name}.{i}.stiffness"), g.stiffness)?;
            non_negative(ls, &format!("rotor.{name}.{i}.damping"), g.damping)?;
            if !on {
                return Err(ls.invalid(
                    &format!("rotor.{name}.{i}"),
                    format!("needs `{flag} = true` in [rotor] (the rotor has no such DOFs)"),
                ));
            }
        }
        // Without a support of positive stiffness the DOFs are free (a rigid-body mode). A free
        // θ_z under a rub's friction torque would spin down without bound: refused.
        let free = on && !list.iter().any(|g| g.stiffness > 0.0);
        if free && flag == "torsion" {
            if let Some((i, st)) = ls
                .scene
                .stations
                .iter()
                .enumerate()
                .find(|(_, st)| st.friction > 0.0)
            {
                let key = if list.is_empty() {
                    format!("rotor.{name}")
                } else {
                    format!("rotor.{name}.0.stiffness")
                };
                return Err(ls.invalid(
                    &key,
                    format!("the rotor's {mode} DOFs are free (`torsion = true` without a [[rotor.{name}]] of positive stiffness), but station `{}` rubs with friction (`station.{i}.friction`), whose torque they cannot resist: add a drive or coupling stiffness", st.name),
                ));
            }
        }
    }
    Ok(())
}

/// Refuses a damping ratio above [`MAX_DAMPING_RATIO`] at `key` (`xi` is the ratio the key
/// gives, for `rotor.damping` the one it makes with the rotor's mass and stiffness).
pub(crate) fn damping_ratio_bound(ls: &LoadedScene, key: &str, xi: f64) -> Result<(), SceneError> {
    if xi > MAX_DAMPING_RATIO {
        return Err(ls.invalid(
            key,
            format!(
                "a damping ratio of {xi:e} is above {MAX_DAMPING_RATIO} (rotors have a few percent to about 1; at 10 no resonance is left): is it a damping coefficient in N·s/m?"
            ),
        ));
    }
    Ok(())
}
