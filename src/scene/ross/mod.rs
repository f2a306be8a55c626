//! A rotor saved by ROSS (`Rotor.save`, TOML or JSON; checked with ROSS 2.3.0 and 3.0.0) as a
//! rubsim scene (`rubsim import-ross FILE`).
//!
//! ROSS writes one table per element, named `"<Class>_<tag>"`: `ShaftElement_…` (`L`, `idl`,
//! `odl`, `idr`, `odr`, `n`, `shear_effects`, `rotary_inertia`, `gyroscopic`, `alpha`, `beta`,
//! and a `material` sub-table with `rho`, `E`, `G_s`), `DiskElement_…` (`n`, `m`, `Id`, `Ip`),
//! `BearingElement_…` (`n`, coefficient lists `kxx … kzz`, `cxx … czz`, `mxx … mzz`, and
//! `frequency` when they are tabulated; `CylindricalBearing` names it `speed`, and so does
//! ROSS 3 for a table over rotor speed), `PointMass_…` (`n`, `m` or `mx`, `my`; ROSS 3 `mz`
//! too), and a `[parameters]` table: empty in ROSS 2, the rotor's damping in ROSS 3 (`alpha`,
//! `beta`, `default_damping_ratio`, `modal_damping_ratio`). They map to
//! `[[rotor.shaft]]` segments of one element each (ν = E/(2G) − 1; a tapered element, `idl ≠ idr`
//! or `odl ≠ odr`, with `outer_diameter_right`, `inner_diameter_right`), `[[rotor.disk]]` by
//! inertias, `[[rotor.bearing]]` with `kxx … cyy` (tables over `speeds` when ROSS gives a
//! `frequency`), `[[rotor.point_mass]]`. ROSS's rotor is 6-DOF: the scene has `axial = true`,
//! `torsion = true`; a bearing's `kzz`, `czz` becomes an `[[rotor.axial_support]]` (kzz = 0
//! everywhere leaves u_z free), θ_z is always free.
//!
//! **Versions and damping** (`damping`): the file's format is told by its keys — ROSS 3's
//! `[parameters]` damping keys, its bearings' `interpolation`, a `ross_version` ≥ 3 — and
//! named, with the damping, in the scene's header. ROSS 2's Rayleigh factors are the shaft
//! elements' (`rayleigh_on = "shaft"`: Σ_e α M_e + β K_e); ROSS 3's are the rotor's,
//! `C = α (M_shaft + M_disks + M_point_masses) + β K_shaft` (`rayleigh_on = "rotor"`), the
//! elements' then ignored as ROSS 3 ignores them; either way each bearing's own C is kept.
//! ROSS 3's modal damping is refused. **Bearing tables** are interpolated by a smoothing
//! spline in ROSS 2 and by PCHIP (or linearly, `interpolation = "linear"`) with linear
//! extrapolation in ROSS 3; the scene notes the difference above each table; ROSS 3's tables
//! over both speed and whirl frequency are refused.
//!
//! **Seals and the other bearing classes.** Every bearing class of ROSS 2.3.0 — `SealElement`,
//! `BallBearingElement`, `RollerBearingElement`, the fluid-film models (`CylindricalBearing`,
//! `BearingFluidFlow`, `PlainJournal`, `TiltingPad`, `SqueezeFilmDamper`, `ThrustPad`) and the
//! seal models (`LabyrinthSeal`, `HolePatternSeal`, `HybridSeal`) — inherits `M`, `K`, `C` of
//! `BearingElement` unchanged: the saved coefficient lists over `frequency`, from the node to
//! ground, enter ROSS's assembled M, K(Ω), C(Ω) exactly as a bearing's do. They are read by the
//! bearing rule above. What else they save does not enter ROSS's matrices and is not read: a
//! seal's `seal_leakage` (reported only), a ball or roller bearing's `n_balls`, `d_balls`,
//! `n_rollers`, `l_rollers`, `fs`, `alpha` (used once, to compute the saved `kxx`, `kyy`, `cxx`,
//! `cyy`), the fluid-film and seal models' geometry and fluid data (read back by ROSS as the
//! saved coefficients, without recomputation), `color`, `scale_factor`, `tag`. One difference
//! in use, not in the matrices: ROSS's static analysis (`run_static`) leaves seals out, while
//! rubsim's scene has no such flag — a seal imported into a run with gravity carries load.
//!
//! **Tables over speed.** ROSS 2 evaluates a table of four or more points through scipy's
//! `UnivariateSpline` (a cubic smoothing spline with s = the number of points, extrapolated
//! outside the table), of two or three points by linear or quadratic interpolation; rubsim
//! interpolates linearly and holds the end values outside. The two agree at the table's speeds
//! when the spline passes through the points (four points; points on one cubic) and at every
//! speed inside the table when the coefficients are linear in speed; elsewhere they differ by
//! the spline's curvature between points, and at a table speed ROSS's smoothing may move a
//! value by up to √(number of points) in SI units (N/m, N·s/m). The scene says so above each
//! tabulated bearing.
//!
//! What rubsim cannot represent is refused at the element's key: elements that differ in
//! their switches or (where they are the damping) Rayleigh factors, axial force or torque on
//! an element, bearing mass coefficients (`mxx … mzz` ≠ 0), speed-dependent kzz, bearings
//! linked to another node
//! (`n_link`), magnetic bearings (`MagneticBearingElement`, saved by ROSS as a
//! `BearingElement_…` table carrying its controller's `kp_pid`, `ki_pid`, `kd_pid`: in ROSS's
//! time response the controller acts, not the saved coefficients), point masses with mx ≠ my
//! or (ROSS 3) mz ≠ mx, and every other element class (couplings, gears, …).

//! **What is checked, and where errors point.** Every number must be finite, every node
//! number `n` a whole number ≥ 0 (never rounded or clamped), every coefficient list non-empty;
//! the scene is then validated as rubsim reads it, and each refusal — the converter's or the
//! scene's — names the ROSS file, the line and ROSS's own key (`"ShaftElement_…".L`), not the
//! generated scene's. The scene is written by `toml_edit` (strings escaped by it; ROSS's names
//! in comments escaped as Rust string literals), each table under a comment naming the ROSS
//! element and line it came from.

mod damping;
mod source;

use crate::error::SceneError;
use damping::{Damping, Format};
use source::{Element, Source};
use std::path::Path;
use toml::Value;
use toml_edit::{ArrayOfTables, DocumentMut, Item, Table as EditTable, Value as EditValue};

/// The rubsim scene (TOML text) of a ROSS rotor file's text `text` read from `path`: the TOML
/// form of `Rotor.save`, or its JSON form (ROSS writes JSON when the file name ends in
/// `.json`; rubsim takes a file whose text starts with `{` as JSON). JSON `null`s in objects
/// — ROSS's `None`, which its TOML form leaves out — are left out too; a `null` in a list is
/// refused. The scene is validated (as [`super::parse`] reads it) before it is returned.
///
/// # Errors
/// [`SceneError::Parse`] for a file that is neither TOML nor JSON; [`SceneError::Invalid`]
/// naming the ROSS file, the element table's key and its line for anything that cannot be
/// represented, is missing or is out of range.
pub fn import(path: &Path, text: &str) -> Result<String, SceneError> {
    let src = Source::parse(path, text)?;
    let format = Format::of(&src);
    let mut shafts = Vec::new();
    let mut body = Vec::new();
    for (name, v) in &src.doc {
        let toml::Value::Table(t) = v else { continue };
        let el = src.element(name, t);
        let class = name.split('_').next().unwrap_or("");
        match class {
            "parameters" if name == "parameters" => {}
            "ShaftElement" => shafts.push(shaft(&el)?),
            "DiskElement" => body.push(Entry::new(
                "disk",
                &el,
                vec![
                    ("node", node_value(el.node("n")?), "n"),
                    ("mass", float(el.number("m")?), "m"),
                    ("diametral_inertia", float(el.number("Id")?), "Id"),
                    ("polar_inertia", float(el.number("Ip")?), "Ip"),
                ],
            )),
            c if BEARING_CLASSES.contains(&c) => bearing(&mut body, &el, format)?,
            "PointMass" => body.push(point_mass(&el)?),
            _ => return Err(el.error("", format!("ROSS element class `{class}` cannot be represented in rubsim (shaft elements, disks, bearings, seals and point masses can)"))),
        }
    }
    shafts.sort_by_key(|s| s.n);
    let Some(first) = shafts.first() else {
        return Err(src.error(&["ShaftElement"], "the file has no shaft element".into()));
    };
    let any_elemental = shafts.iter().any(|s| s.flags[3..] != [0.0; 2]);
    let factors = [first.flags[3], first.flags[4]];
    let damping = damping::damping(&src, &first.entry.table, factors, any_elemental)?;
    // The elements' Rayleigh factors are compared only where they are ROSS's damping.
    let compared = if damping.elemental { 5 } else { 3 };
    for (i, s) in shafts.iter().enumerate() {
        if s.n != i {
            return Err(src.error(&[&s.entry.table, "n"], format!("shaft element n = {}, expected {i}: elements must follow each other from node 0", s.n)));
        }
        if let Some(k) = (0..compared).find(|&k| s.flags[k].to_bits() != first.flags[k].to_bits()) {
            let show = |x: f64| {
                if k < 3 {
                    (x != 0.0).to_string()
                } else {
                    format!("{x:?}")
                }
            };
            return Err(src.error(&[&s.entry.table, FLAGS[k]], format!("`{}` = {} on this element, {} on element n = 0: shear_effects, rotary_inertia, gyroscopic, alpha and beta must be the same on every shaft element (rubsim sets them for the rotor)", FLAGS[k], show(s.flags[k]), show(first.flags[k]))));
        }
    }
    let version = match src.doc.get("ross_version") {
        Some(Value::String(v)) => format!("{v:?}"),
        _ => "(unknown version)".into(),
    };
    let mut w = Writer::new(&first.entry.table, first.flags, &damping);
    for s in shafts {
        w.push(s.entry);
    }
    for e in body {
        w.push(e);
    }
    let scene = w.finish(&version, &src.file_name(), format, &damping);
    match super::parse(path, &scene, &[]) {
        Ok(_) => Ok(scene),
        Err(e) => Err(w.origins.translate(&src, e)),
    }
}

/// ROSS 2.3.0's bearing classes (3.0.0 has them all but `BearingFluidFlow`) whose `M`, `K`,
/// `C` are `BearingElement`'s: coefficients over
/// `frequency` between the node and ground.
const BEARING_CLASSES: [&str; 13] = [
    "BearingElement",
    "SealElement",
    "BallBearingElement",
    "RollerBearingElement",
    "CylindricalBearing",
    "BearingFluidFlow",
    "PlainJournal",
    "TiltingPad",
    "SqueezeFilmDamper",
    "ThrustPad",
    "LabyrinthSeal",
    "HolePatternSeal",
    "HybridSeal",
];

/// The shaft elements' switches and Rayleigh factors, which rubsim sets for the whole rotor.
const FLAGS: [&str; 5] = [
    "shear_effects",
    "rotary_inertia",
    "gyroscopic",
    "alpha",
    "beta",
];

/// A float as TOML, written as Rust writes it (shortest round trip: `0.25`, `1e-5`,
/// `211000000000.0`); `x` is finite (checked when read).
fn float(x: f64) -> EditValue {
    format!("{x:?}")
        .parse()
        .unwrap_or_else(|_| EditValue::from(x))
}

/// A list of floats as a TOML array.
fn floats(v: &[f64]) -> EditValue {
    EditValue::Array(v.iter().map(|x| float(*x)).collect())
}

/// A node number as a TOML integer.
fn node_value(n: usize) -> EditValue {
    EditValue::from(i64::try_from(n).unwrap_or(i64::MAX))
}

/// One table of an array of the scene's `[rotor]` (`[[rotor.disk]]` …) from one ROSS element:
/// its keys with their values and the ROSS key each comes from (`""`: none, set by rubsim).
struct Entry {
    /// The array under `rotor` (`"shaft"`, `"disk"`, …).
    array: &'static str,
    /// The ROSS element table's name.
    table: String,
    /// Its line in the ROSS file.
    line: Option<usize>,
    /// What the scene's reader should know about this table (a comment), if anything.
    note: Option<String>,
    /// The element as errors name it (`shaft element n = 3`), if not by its table alone.
    label: Option<String>,
    /// (scene key, value, ROSS key).
    values: Vec<(&'static str, EditValue, &'static str)>,
}

impl Entry {
    fn new(
        array: &'static str,
        el: &Element,
        values: Vec<(&'static str, EditValue, &'static str)>,
    ) -> Self {
        Entry {
            array,
            table: el.name.to_string(),
            line: el.line(""),
            note: None,
            label: None,
            values,
        }
    }
}

/// A shaft element: its entry, its `n` and its switches and Rayleigh factors (as numbers, in
/// the order of [`FLAGS`]).
struct Shaft {
    n: usize,
    entry: Entry,
    flags: [f64; 5],
}

fn shaft(el: &Element) -> Result<Shaft, SceneError> {
    for k in ["axial_force", "torque"] {
        if el.number_or(k, Some(0.0))? != 0.0 {
            return Err(el.error(
                k,
                format!("`{k}` on a shaft element is not modelled by rubsim"),
            ));
        }
    }
    match el.table.get("shear_method_calc") {
        None => {}
        Some(Value::String(m)) if m == "cowper" => {}
        Some(m) => {
            return Err(el.error(
                "shear_method_calc",
                format!("shear_method_calc = {m}: rubsim uses Cowper's shear factor"),
            ))
        }
    }
    if !matches!(el.table.get("material"), Some(Value::Table(_))) {
        return Err(el.error("material", "no `material` table (rho, E, G_s)".into()));
    }
    let (idl, odl, idr, odr) = (
        el.number("idl")?,
        el.number("odl")?,
        el.number("idr")?,
        el.number("odr")?,
    );
    let (rho, e, g) = (
        el.number("material.rho")?,
        el.number("material.E")?,
        el.number("material.G_s")?,
    );
    if g == 0.0 {
        return Err(el.error(
            "material.G_s",
            "`G_s` = 0: the shear modulus must be positive".into(),
        ));
    }
    let mut values = vec![
        ("length", float(el.number("L")?), "L"),
        ("outer_diameter", float(odl), "odl"),
        ("inner_diameter", float(idl), "idl"),
    ];
    if idl != idr || odl != odr {
        values.push(("outer_diameter_right", float(odr), "odr"));
        values.push(("inner_diameter_right", float(idr), "idr"));
    }
    values.extend([
        ("elements", EditValue::from(1), ""),
        ("youngs_modulus", float(e), "material.E"),
        ("poisson", float(e / (2.0 * g) - 1.0), "material.G_s"),
        ("density", float(rho), "material.rho"),
    ]);
    let mut flags = [0.0; 5];
    for (f, k) in flags.iter_mut().zip(FLAGS) {
        *f = match k {
            "alpha" | "beta" => match el.number_or(k, Some(0.0))? {
                x if x < 0.0 => {
                    let m = format!("`{k}` = {x}: Rayleigh factors must be zero or positive");
                    return Err(el.error(k, m));
                }
                x => x,
            },
            _ => f64::from(u8::from(el.flag(k, true)?)),
        };
    }
    let n = el.node("n")?;
    let mut entry = Entry::new("shaft", el, values);
    entry.label = Some(format!("shaft element n = {n}"));
    Ok(Shaft { n, entry, flags })
}

fn point_mass(el: &Element) -> Result<Entry, SceneError> {
    let (mx, my, key) = match el.table.get("m") {
        Some(_) => (el.number("m")?, el.number("m")?, "m"),
        None => (el.number("mx")?, el.number("my")?, "mx"),
    };
    // ROSS 3 saves `mz` too (the mass on u_z), which rubsim's point mass carries as its `mass`.
    let mz = el.number_or("mz", Some(mx))?;
    if let Some((k, v)) = [("my", my), ("mz", mz)].into_iter().find(|(_, v)| *v != mx) {
        return Err(el.error(
            k,
            format!("point mass {k} = {v} ≠ mx = {mx}: rubsim's point masses are isotropic"),
        ));
    }
    Ok(Entry::new(
        "point_mass",
        el,
        vec![
            ("node", node_value(el.node("n")?), "n"),
            ("mass", float(mx), key),
        ],
    ))
}

/// A bearing's `[[rotor.bearing]]` (and `[[rotor.axial_support]]` for kzz, czz) entries, its
/// table's note written as the file's `format` interpolates it.
fn bearing(body: &mut Vec<Entry>, el: &Element, format: Format) -> Result<(), SceneError> {
    let t = el.table;
    if let Some(k) = ["kp_pid", "ki_pid", "kd_pid", "controller_transfer_function"]
        .into_iter()
        .find(|k| t.contains_key(*k))
    {
        return Err(el.error(k, format!("a magnetic bearing (`{k}`: ROSS's MagneticBearingElement, saved as a BearingElement table) cannot be represented: in ROSS's time response its controller acts, not the saved coefficients")));
    }
    if t.get("n_link")
        .is_some_and(|v| !matches!(v, Value::String(s) if s == "None"))
    {
        return Err(el.error("n_link", "a bearing linked to another node (`n_link`, pedestal or support mass) is not read yet; model the pedestal with `rotor.bearing.pedestal`".into()));
    }
    if let Some(k) = ["n", "kxx", "cxx"]
        .into_iter()
        .find(|k| !t.contains_key(*k))
    {
        return Err(el.error(
            "",
            format!("`{k}` missing: every ROSS bearing or seal table has `n`, `kxx` and `cxx`"),
        ));
    }
    for k in ["mxx", "mxy", "myx", "myy", "mzz"] {
        if el.list(k)?.unwrap_or_default().iter().any(|v| *v != 0.0) {
            return Err(el.error(
                k,
                format!("bearing mass coefficient `{k}` ≠ 0 cannot be represented"),
            ));
        }
    }
    let node = el.node("n")?;
    if t.contains_key("frequency") && t.contains_key("speed") {
        return Err(el.error("speed", "a table over both speed and whirl frequency (ROSS 3's two-axis table) cannot be represented: rubsim's bearing tables are over speed alone".into()));
    }
    // ROSS 2's `CylindricalBearing` saves the speeds of its table as `speed` (rad/s), the
    // `frequency` it hands to `BearingElement`; ROSS 3 saves a table over rotor speed as
    // `speed` and one over whirl frequency as `frequency`, which its synchronous analyses
    // (every `run_*`, the frequency the speed) evaluate at the speed: both are tables over speed.
    let fkey = if !t.contains_key("frequency") && t.contains_key("speed") {
        "speed"
    } else {
        "frequency"
    };
    let freq = el.list(fkey)?.unwrap_or_default();
    let tabulated = freq.len() > 1;
    let mut values = vec![("node", node_value(node), "n")];
    for k in ["kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy"] {
        let v = el.list(k)?.unwrap_or_else(|| vec![0.0]);
        let value = if tabulated && v.len() == freq.len() {
            floats(&v)
        } else if v.iter().all(|x| *x == v[0]) {
            float(v[0])
        } else {
            return Err(el.error(
                k,
                format!(
                    "`{k}` has {} values but `{fkey}` has {}",
                    v.len(),
                    freq.len()
                ),
            ));
        };
        values.push((k, value, k));
    }
    let mut entry = Entry::new("bearing", el, values);
    if tabulated {
        entry.values.push(("speeds", floats(&freq), fkey));
        entry.note = Some(table_note(el, format, freq.len())?);
    }
    body.push(entry);
    let mut axial = [0.0; 2];
    for (a, k) in axial.iter_mut().zip(["kzz", "czz"]) {
        let v = el.list(k)?.unwrap_or_else(|| vec![0.0]);
        if v.iter().any(|x| *x != v[0]) {
            return Err(el.error(k, format!("speed-dependent `{k}` = {v:?} cannot be represented (rubsim's axial supports are constant)")));
        }
        *a = v[0];
    }
    if axial != [0.0; 2] {
        body.push(Entry::new(
            "axial_support",
            el,
            vec![
                ("node", node_value(node), "n"),
                ("stiffness", float(axial[0]), "kzz"),
                ("damping", float(axial[1]), "czz"),
            ],
        ));
    }
    Ok(())
}

/// What the scene says above a bearing table of `points` points of `el`: how ROSS of the file's
/// `format` interpolates it and where rubsim's linear interpolation, held constant outside the
/// table, agrees with it.
///
/// # Errors
/// A ROSS 3 `interpolation` other than `"pchip"` or `"linear"`.
fn table_note(el: &Element, format: Format, points: usize) -> Result<String, SceneError> {
    if format == Format::Ross2 {
        let how = match points {
            2 => "linearly, as rubsim does",
            3 => "with a parabola through the three points, rubsim linearly",
            _ => "with a cubic smoothing spline, rubsim linearly",
        };
        return Ok(format!("ROSS interpolates this table {how};\n# they agree at `speeds` (for a spline: when it passes through the points), and between them when\n# the coefficients are linear in speed."));
    }
    let linear = match el.table.get("interpolation") {
        None => points == 2,
        Some(Value::String(m)) if m == "pchip" => points == 2,
        Some(Value::String(m)) if m == "linear" => true,
        Some(m) => {
            let msg = format!("interpolation = {m}: ROSS 3 knows \"pchip\" and \"linear\"");
            return Err(el.error("interpolation", msg));
        }
    };
    let how = if linear {
        "linearly, as rubsim does; they agree inside `speeds`"
    } else {
        "by PCHIP (a monotone cubic through the points), rubsim linearly;\n# they agree at `speeds`, and between them when the coefficients are linear in speed"
    };
    Ok(format!("ROSS 3 interpolates this table {how}. Outside\n# `speeds` ROSS extrapolates linearly from the end slopes, rubsim holds the end values."))
}

/// Where each key of the generated scene came from: (scene key, ROSS table, ROSS key, the
/// element as errors name it or `""`).
struct Origins(Vec<(String, String, &'static str, String)>);

impl Origins {
    /// The scene's error `e` as an error in the ROSS file: at the ROSS key the scene's key
    /// came from (the nearest recorded one above it), the scene's key named in the message.
    fn translate(&self, src: &Source, e: SceneError) -> SceneError {
        let (key, message) = match e {
            SceneError::Invalid { key, message, .. } => (key, message),
            SceneError::Parse { file, message } => {
                return SceneError::Parse {
                    file,
                    message: format!("the scene converted from it does not parse (a rubsim bug, please report it): {message}"),
                }
            }
            e => return e,
        };
        let under = |scene: &str| key == scene || key.starts_with(&format!("{scene}."));
        let Some((scene, table, ross, label)) = self
            .0
            .iter()
            .filter(|(scene, ..)| under(scene))
            .max_by_key(|(scene, ..)| scene.len())
        else {
            return src.error(&[&key], format!("{message} (a key of the imported scene)"));
        };
        let how = match scene.rsplit('.').next() {
            Some("poisson") => " = E/(2·G_s) − 1",
            _ => "",
        };
        let mut keys = vec![table.as_str()];
        keys.extend(ross.split('.').filter(|k| !k.is_empty()));
        let label = if label.is_empty() {
            String::new()
        } else {
            format!("{label}; ")
        };
        src.error(&keys, format!("{message} ({label}rubsim's `{key}`{how})"))
    }
}

/// The scene being written: its `[rotor]` table, the next table's position and the origins.
struct Writer {
    rotor: EditTable,
    position: usize,
    origins: Origins,
}

impl Writer {
    /// The `[rotor]` table with the switches `flags` of the shaft element `table` and the
    /// Rayleigh damping `damping`.
    fn new(table: &str, flags: [f64; 5], damping: &Damping) -> Self {
        let mut rotor = EditTable::new();
        rotor.set_position(1);
        rotor.insert("kind", toml_edit::value("fe"));
        rotor.insert("axial", toml_edit::value(true));
        rotor.insert("torsion", toml_edit::value(true));
        let mut origins = Vec::new();
        for (k, f) in [("shear", 0), ("rotary_inertia", 1), ("gyroscopic", 2)] {
            rotor.insert(k, toml_edit::value(flags[f] != 0.0));
            origins.push((
                format!("rotor.{k}"),
                table.to_string(),
                FLAGS[f],
                String::new(),
            ));
        }
        rotor.insert("rayleigh", Item::Value(floats(&damping.rayleigh)));
        for (key, ross) in [("", "alpha"), (".0", "alpha"), (".1", "beta")] {
            let origin = (format!("rotor.rayleigh{key}"), damping.table.clone(), ross);
            origins.push((origin.0, origin.1, origin.2, String::new()));
        }
        rotor.insert("rayleigh_on", toml_edit::value(damping.on));
        Writer {
            rotor,
            position: 2,
            origins: Origins(origins),
        }
    }

    /// Appends `e` to its array under `[rotor]`, under a comment naming its ROSS element.
    fn push(&mut self, e: Entry) {
        let array = self
            .rotor
            .entry(e.array)
            .or_insert(Item::ArrayOfTables(ArrayOfTables::new()));
        let Some(array) = array.as_array_of_tables_mut() else {
            return;
        };
        let at = format!("rotor.{}.{}", e.array, array.len());
        let label = e.label.unwrap_or_default();
        let mut t = EditTable::new();
        for (k, v, ross) in e.values {
            t.insert(k, Item::Value(v));
            if !ross.is_empty() {
                let origin = (format!("{at}.{k}"), e.table.clone(), ross, label.clone());
                self.origins.0.push(origin);
            }
        }
        let line = e.line.map(|l| format!(" (line {l})")).unwrap_or_default();
        let note = e.note.map(|n| format!("\n# {n}")).unwrap_or_default();
        t.decor_mut()
            .set_prefix(format!("\n# ROSS {:?}{line}{note}\n", e.table));
        t.set_position(self.position);
        self.position += 1;
        array.push(t);
        self.origins.0.push((at, e.table, "", label));
    }

    /// The scene's text: a header naming the ROSS version `version` (a quoted, escaped string),
    /// the file's format, the file `file` and the damping, the title, `[rotor]` with its
    /// arrays, and `[run]`.
    fn finish(&mut self, version: &str, file: &str, format: Format, damping: &Damping) -> String {
        let mut doc = DocumentMut::new();
        let damping: String = damping.comment.iter().map(|l| format!("# {l}\n")).collect();
        doc.decor_mut().set_prefix(format!(
            "# Imported from ROSS {version} by `rubsim import-ross` from {file:?}; each table's\n# comment names the ROSS element (and its line) it comes from.\n# Format: {}.\n{damping}",
            format.describe()
        ));
        doc.insert("title", toml_edit::value(format!("ROSS rotor {file}")));
        doc.insert("rotor", Item::Table(std::mem::take(&mut self.rotor)));
        let mut run = EditTable::new();
        run.insert("speed_ratio", Item::Value(float(1.0)));
        run.set_position(self.position);
        doc.insert("run", Item::Table(run));
        doc.to_string()
    }
}
