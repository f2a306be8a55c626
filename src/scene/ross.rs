//! A rotor saved by ROSS (`Rotor.save`, TOML or JSON; checked with ROSS 2.3.0) as a rubsim scene
//! (`rubsim import-ross FILE`).
//!
//! ROSS writes one table per element, named `"<Class>_<tag>"`: `ShaftElement_…` (`L`, `idl`,
//! `odl`, `idr`, `odr`, `n`, `shear_effects`, `rotary_inertia`, `gyroscopic`, `alpha`, `beta`,
//! and a `material` sub-table with `rho`, `E`, `G_s`), `DiskElement_…` (`n`, `m`, `Id`, `Ip`),
//! `BearingElement_…` (`n`, coefficient lists `kxx … kzz`, `cxx … czz`, `mxx … mzz`, and
//! `frequency` when they are tabulated; `CylindricalBearing` names it `speed`), `PointMass_…` (`n`, `m` or `mx`, `my`). They map to
//! `[[rotor.shaft]]` segments of one element each (ν = E/(2G) − 1; a tapered element, `idl ≠ idr`
//! or `odl ≠ odr`, with `outer_diameter_right`, `inner_diameter_right`), `[[rotor.disk]]` by
//! inertias, `[[rotor.bearing]]` with `kxx … cyy` (tables over `speeds` when ROSS gives a
//! `frequency`), `[[rotor.point_mass]]`. ROSS's rotor is 6-DOF: the scene has `axial = true`,
//! `torsion = true`; a bearing's `kzz`, `czz` becomes an `[[rotor.axial_support]]` (kzz = 0
//! everywhere leaves u_z free), θ_z is always free. Rayleigh `alpha`, `beta` act on the shaft
//! elements (`rayleigh_on = "shaft"`).
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
//! **Tables over speed.** ROSS evaluates a table of four or more points through scipy's
//! `UnivariateSpline` (a cubic smoothing spline with s = the number of points, extrapolated
//! outside the table), of two or three points by linear or quadratic interpolation; rubsim
//! interpolates linearly and holds the end values outside. The two agree at the table's speeds
//! when the spline passes through the points (four points; points on one cubic) and at every
//! speed inside the table when the coefficients are linear in speed; elsewhere they differ by
//! the spline's curvature between points, and at a table speed ROSS's smoothing may move a
//! value by up to √(number of points) in SI units (N/m, N·s/m). The scene says so above each
//! tabulated bearing.
//!
//! What rubsim cannot represent is refused by the element's table name: elements that differ in
//! their switches or Rayleigh factors, axial force or torque on an element, bearing mass
//! coefficients (`mxx … mzz` ≠ 0), speed-dependent kzz, bearings linked to another node
//! (`n_link`), magnetic bearings (`MagneticBearingElement`, saved by ROSS as a
//! `BearingElement_…` table carrying its controller's `kp_pid`, `ki_pid`, `kd_pid`: in ROSS's
//! time response the controller acts, not the saved coefficients), point masses with mx ≠ my,
//! and every other element class (couplings, gears, …).

use crate::error::SceneError;
use std::fmt::Write as _;
use std::path::Path;
use toml::{Table, Value};

/// The saved rotor as a table of element tables: JSON when the text starts with `{`, else
/// TOML.
fn parse_doc(path: &Path, text: &str) -> Result<Table, SceneError> {
    let parse_error = |message: String| SceneError::Parse {
        file: path.to_path_buf(),
        message,
    };
    if text.trim_start().starts_with('{') {
        let v: serde_json::Value =
            serde_json::from_str(text).map_err(|e| parse_error(format!("JSON: {e}")))?;
        match json_to_toml(v) {
            Some(Value::Table(t)) => Ok(t),
            _ => Err(parse_error("JSON: not an object of element tables".into())),
        }
    } else {
        text.parse()
            .map_err(|e: toml::de::Error| parse_error(e.to_string()))
    }
}

/// An error in the element table `table` of the saved rotor, at the line that opens it (TOML
/// `[table]` or `["table"…`, JSON `"table":`).
fn table_error(path: &Path, text: &str, table: &str, message: String) -> SceneError {
    SceneError::Invalid {
        file: path.to_path_buf(),
        key: table.to_string(),
        line: text
            .lines()
            .position(|l| {
                let l = l.trim_start();
                l.starts_with(&format!("[\"{table}\""))
                    || l.starts_with(&format!("[{table}]"))
                    || l.starts_with(&format!("\"{table}\":"))
            })
            .map(|i| i + 1),
        message,
    }
}

/// The rubsim scene (TOML text) of a ROSS rotor file's text `text` read from `path`: the TOML
/// form of `Rotor.save`, or its JSON form (ROSS writes JSON when the file name ends in
/// `.json`; rubsim takes a file whose text starts with `{` as JSON). JSON `null`s — ROSS's
/// `None`, which its TOML form leaves out — are left out too.
///
/// # Errors
/// [`SceneError::Parse`] for a file that is neither; [`SceneError::Invalid`] naming the
/// element table (and its line) for anything that cannot be represented or is missing.
pub fn import(path: &Path, text: &str) -> Result<String, SceneError> {
    let doc = parse_doc(path, text)?;
    let bad = |table: &str, message: String| table_error(path, text, table, message);
    let mut shafts = Vec::new();
    let mut out = String::new();
    let mut body = String::new();
    for (name, v) in &doc {
        let Value::Table(t) = v else { continue };
        let class = name.split('_').next().unwrap_or("");
        let num = |k: &str| -> Result<f64, SceneError> {
            match t.get(k) {
                Some(Value::Float(x)) => Ok(*x),
                Some(Value::Integer(i)) => Ok(*i as f64),
                _ => Err(bad(name, format!("`{k}` missing or not a number"))),
            }
        };
        match class {
            "parameters" if name == "parameters" => {}
            "ShaftElement" => {
                let refuse = |m: String| bad(name, m);
                shafts.push((num("n")? as usize, name.clone(), shaft(t, &num, &refuse)?));
            }
            "DiskElement" => {
                let _ = writeln!(
                    body,
                    "[[rotor.disk]]\nnode = {}\nmass = {:?}\ndiametral_inertia = {:?}\npolar_inertia = {:?}",
                    num("n")? as usize,
                    num("m")?,
                    num("Id")?,
                    num("Ip")?
                );
            }
            c if BEARING_CLASSES.contains(&c) => {
                bearing(&mut body, name, t, &num).map_err(|m| bad(name, m))?;
            }
            "PointMass" => {
                let (mx, my) = match t.get("m") {
                    Some(_) => (num("m")?, num("m")?),
                    None => (num("mx")?, num("my")?),
                };
                if mx != my {
                    return Err(bad(name, format!("point mass mx = {mx} ≠ my = {my}: rubsim's point masses are isotropic")));
                }
                let _ = writeln!(body, "[[rotor.point_mass]]\nnode = {}\nmass = {mx:?}", num("n")? as usize);
            }
            _ => {
                return Err(bad(
                    name,
                    format!("ROSS element class `{class}` cannot be represented in rubsim (shaft elements, disks, bearings, seals and point masses can)"),
                ))
            }
        }
    }
    shafts.sort_by_key(|s| s.0);
    let Some(first) = shafts.first() else {
        return Err(bad("ShaftElement", "the file has no shaft element".into()));
    };
    for (i, (n, name, s)) in shafts.iter().enumerate() {
        if *n != i {
            return Err(bad(name, format!("shaft element n = {n}, expected {i}: elements must follow each other from node 0")));
        }
        if s.flags != first.2.flags {
            return Err(bad(name, "shear_effects, rotary_inertia, gyroscopic, alpha and beta must be the same on every shaft element (rubsim sets them for the rotor)".into()));
        }
    }
    let (shear, rot, gyro, alpha, beta) = first.2.flags;
    let (alpha, beta) = (f64::from_bits(alpha), f64::from_bits(beta));
    let _ = writeln!(
        out,
        "# Imported from ROSS ({}) by `rubsim import-ross`.\ntitle = \"ROSS rotor {}\"\n[rotor]\nkind = \"fe\"\naxial = true\ntorsion = true\nshear = {shear}\nrotary_inertia = {rot}\ngyroscopic = {gyro}\nrayleigh = [{alpha:?}, {beta:?}]\nrayleigh_on = \"shaft\"",
        doc.get("ross_version").and_then(Value::as_str).unwrap_or("unknown version"),
        path.file_name().map(|f| f.to_string_lossy().to_string()).unwrap_or_default()
    );
    for (_, _, s) in &shafts {
        out.push_str(&s.toml);
    }
    out.push_str(&body);
    out.push_str("[run]\nspeed_ratio = 1.0\n");
    Ok(out)
}

/// ROSS 2.3.0's bearing classes whose `M`, `K`, `C` are `BearingElement`'s: coefficients over
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

/// A shaft element: its `[[rotor.shaft]]` text and its switches and Rayleigh factors.
struct Shaft {
    toml: String,
    flags: (bool, bool, bool, u64, u64),
}

fn shaft(
    t: &Table,
    num: &dyn Fn(&str) -> Result<f64, SceneError>,
    bad: &dyn Fn(String) -> SceneError,
) -> Result<Shaft, SceneError> {
    let flag = |k: &str| t.get(k).and_then(Value::as_bool).unwrap_or(true);
    let (idl, odl, idr, odr) = (num("idl")?, num("odl")?, num("idr")?, num("odr")?);
    let refuse = |m: String| Err(bad(m));
    let right = if idl != idr || odl != odr {
        format!("outer_diameter_right = {odr:?}\ninner_diameter_right = {idr:?}\n")
    } else {
        String::new()
    };
    for k in ["axial_force", "torque"] {
        if num(k).unwrap_or(0.0) != 0.0 {
            return refuse(format!(
                "`{k}` on a shaft element is not modelled by rubsim"
            ));
        }
    }
    if let Some(m) = t.get("shear_method_calc").and_then(Value::as_str) {
        if m != "cowper" {
            return refuse(format!(
                "shear_method_calc = \"{m}\": rubsim uses Cowper's shear factor"
            ));
        }
    }
    let Some(Value::Table(mat)) = t.get("material") else {
        return refuse("no material table".into());
    };
    let mnum = |k: &str| {
        mat.get(k)
            .and_then(|v| v.as_float().or(v.as_integer().map(|i| i as f64)))
    };
    let (Some(rho), Some(e), Some(g)) = (mnum("rho"), mnum("E"), mnum("G_s")) else {
        return refuse("material needs rho, E and G_s".into());
    };
    let alpha = num("alpha").unwrap_or(0.0);
    let beta = num("beta").unwrap_or(0.0);
    Ok(Shaft {
        toml: format!(
            "[[rotor.shaft]]\nlength = {:?}\nouter_diameter = {odl:?}\ninner_diameter = {idl:?}\n{right}elements = 1\nyoungs_modulus = {e:?}\npoisson = {:?}\ndensity = {rho:?}\n",
            num("L")?,
            e / (2.0 * g) - 1.0
        ),
        flags: (
            flag("shear_effects"),
            flag("rotary_inertia"),
            flag("gyroscopic"),
            alpha.to_bits(),
            beta.to_bits(),
        ),
    })
}

/// A bearing's `[[rotor.bearing]]` (and `[[rotor.axial_support]]` for kzz, czz) text.
fn bearing(
    body: &mut String,
    name: &str,
    t: &Table,
    num: &dyn Fn(&str) -> Result<f64, SceneError>,
) -> Result<(), String> {
    let list = |k: &str| -> Result<Vec<f64>, String> {
        match t.get(k) {
            None => Ok(vec![0.0]),
            Some(Value::Array(a)) => a
                .iter()
                .map(|v| v.as_float().or(v.as_integer().map(|i| i as f64)))
                .collect::<Option<Vec<f64>>>()
                .ok_or_else(|| format!("`{k}` must be a list of numbers")),
            Some(v) => v
                .as_float()
                .or(v.as_integer().map(|i| i as f64))
                .map(|x| vec![x])
                .ok_or_else(|| format!("`{k}` must be a number or a list")),
        }
    };
    if let Some(k) = ["kp_pid", "ki_pid", "kd_pid", "controller_transfer_function"]
        .into_iter()
        .find(|k| t.contains_key(*k))
    {
        return Err(format!("a magnetic bearing (`{k}`: ROSS's MagneticBearingElement, saved as a BearingElement table) cannot be represented: in ROSS's time response its controller acts, not the saved coefficients"));
    }
    if t.get("n_link")
        .is_some_and(|v| !matches!(v, Value::String(s) if s == "None"))
    {
        return Err("a bearing linked to another node (`n_link`, pedestal or support mass) is not read yet; model the pedestal with `rotor.bearing.pedestal`".into());
    }
    if let Some(k) = ["n", "kxx", "cxx"]
        .into_iter()
        .find(|k| !t.contains_key(*k))
    {
        return Err(format!(
            "`{k}` missing: every ROSS bearing or seal table has `n`, `kxx` and `cxx`"
        ));
    }
    for k in ["mxx", "mxy", "myx", "myy", "mzz"] {
        if list(k)?.iter().any(|v| *v != 0.0) {
            return Err(format!(
                "bearing mass coefficient `{k}` ≠ 0 cannot be represented"
            ));
        }
    }
    let node = num("n").map_err(|e| e.to_string())? as usize;
    // `CylindricalBearing` saves the speeds of its table as `speed` (rad/s), the `frequency` it
    // hands to `BearingElement`; every other class saves `frequency`.
    let fkey = if !t.contains_key("frequency") && t.contains_key("speed") {
        "speed"
    } else {
        "frequency"
    };
    let freq = list(fkey).unwrap_or_default();
    let tabulated = t.contains_key(fkey) && freq.len() > 1;
    if tabulated {
        let how = match freq.len() {
            2 => "linearly, as rubsim does",
            3 => "with a parabola through the three points, rubsim linearly",
            _ => "with a cubic smoothing spline, rubsim linearly",
        };
        let _ = writeln!(
            body,
            "# ROSS \"{name}\": ROSS interpolates this table {how};\n# they agree at `speeds` (for a spline: when it passes through the points), and between them when\n# the coefficients are linear in speed."
        );
    }
    let _ = writeln!(body, "[[rotor.bearing]]\nnode = {node}");
    for k in ["kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy"] {
        let v = list(k)?;
        if tabulated && v.len() == freq.len() {
            let _ = writeln!(body, "{k} = {v:?}");
        } else if v.len() == 1 || v.iter().all(|x| *x == v[0]) {
            let _ = writeln!(body, "{k} = {:?}", v[0]);
        } else {
            return Err(format!(
                "`{k}` has {} values but `{fkey}` has {}",
                v.len(),
                freq.len()
            ));
        }
    }
    if tabulated {
        let _ = writeln!(body, "speeds = {freq:?}");
    }
    let (kz, cz) = (list("kzz")?, list("czz")?);
    if kz.iter().chain(&cz).any(|v| *v != kz[0] && *v != cz[0]) {
        return Err("speed-dependent kzz or czz cannot be represented (rubsim's axial supports are constant)".into());
    }
    if kz[0] != 0.0 || cz[0] != 0.0 {
        let _ = writeln!(
            body,
            "[[rotor.axial_support]]\nnode = {node}\nstiffness = {:?}\ndamping = {:?}",
            kz[0], cz[0]
        );
    }
    Ok(())
}

/// A JSON value as TOML, `null`s (in objects and arrays) left out; `None` for a bare `null`.
fn json_to_toml(v: serde_json::Value) -> Option<Value> {
    use serde_json::Value as J;
    Some(match v {
        J::Null => return None,
        J::Bool(b) => Value::Boolean(b),
        J::Number(n) => match n.as_i64() {
            Some(i) => Value::Integer(i),
            None => Value::Float(n.as_f64()?),
        },
        J::String(s) => Value::String(s),
        J::Array(a) => Value::Array(a.into_iter().filter_map(json_to_toml).collect()),
        J::Object(o) => Value::Table(
            o.into_iter()
                .filter_map(|(k, v)| json_to_toml(v).map(|v| (k, v)))
                .collect(),
        ),
    })
}
