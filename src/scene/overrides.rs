//! `--set key=value` overrides and locating dotted keys in the TOML text.

use crate::error::SceneError;

/// Keys that are alternatives of each other within one table (`validate::one_of`): setting one
/// by `--set` removes the others of its group from that table, so `--set
/// stator.0.clearance=1e-4` switches a stator given with `clearance_nd` to an absolute
/// clearance.
pub const ALTERNATIVE_KEYS: &[&[&str]] = &[
    &["clearance", "clearance_nd"],
    &["stiffness", "stiffness_ratio"],
    &["youngs_modulus", "stiffness_ratio"],
    &["damping", "damping_ratio"],
    &["speed_ratio", "speed"],
];

/// Applies one `path.to.key=value` assignment; array elements are addressed by index
/// (`stator.0.clearance_nd=0.5`), and an index equal to the array's length appends an entry
/// (`rotor.unbalance.1.mass=0.01` adds a second unbalance; its other keys by further `--set`s).
/// Setting a key removes its alternatives from the same table ([`ALTERNATIVE_KEYS`]). The value
/// is parsed as TOML (number, bool, array, inline table, quoted string) and falls back to a bare
/// string.
pub fn apply_override(root: &mut toml::Value, assignment: &str) -> Result<(), SceneError> {
    let err = |m: &str| SceneError::Override {
        assignment: assignment.to_string(),
        message: m.to_string(),
    };
    let (key, raw) = assignment
        .split_once('=')
        .ok_or_else(|| err("expected key=value"))?;
    let key = key.trim();
    if key.is_empty() {
        return Err(err("empty key"));
    }
    let raw = raw.trim();
    let value = match toml::from_str::<toml::Table>(&format!("v = {raw}")) {
        Ok(mut t) => t.remove("v"),
        Err(_) => None,
    }
    .unwrap_or_else(|| toml::Value::String(raw.to_string()));
    let parts: Vec<&str> = key.split('.').collect();
    if parts.iter().any(|p| p.is_empty()) {
        return Err(err("empty segment in the dotted key"));
    }
    let (last, path) = parts.split_last().ok_or_else(|| err("empty key"))?;
    let mut cur = root;
    for (i, part) in path.iter().enumerate() {
        // Scene arrays of tables are named in the singular in TOML (`[[stator]]`); a missing
        // table on the way is created.
        cur = match cur {
            toml::Value::Table(t) => t
                .entry(part.to_string())
                .or_insert_with(|| toml::Value::Table(toml::Table::new())),
            toml::Value::Array(a) => {
                let idx: usize = part
                    .parse()
                    .map_err(|_| err(&format!("`{part}` is not an index into an array")))?;
                let len = a.len();
                if idx == len {
                    // Append: a table for an array of tables, else what the next part makes.
                    a.push(toml::Value::Table(toml::Table::new()));
                }
                a.get_mut(idx).ok_or_else(|| {
                    err(&format!(
                        "index {idx} out of range (array has {len} entries; index {len} appends one)"
                    ))
                })?
            }
            _ => {
                return Err(err(&format!(
                    "`{}` is not a table or array",
                    parts[..i].join(".")
                )))
            }
        };
    }
    match cur {
        toml::Value::Table(t) => {
            for group in ALTERNATIVE_KEYS.iter().filter(|g| g.contains(last)) {
                for other in group.iter().filter(|o| *o != last) {
                    t.remove(*other);
                }
            }
            t.insert(last.to_string(), value);
        }
        toml::Value::Array(a) => {
            let idx: usize = last
                .parse()
                .map_err(|_| err(&format!("`{last}` is not an index into an array")))?;
            let len = a.len();
            match idx.cmp(&len) {
                std::cmp::Ordering::Less => a[idx] = value,
                std::cmp::Ordering::Equal => a.push(value),
                std::cmp::Ordering::Greater => {
                    return Err(err(&format!(
                    "index {idx} out of range (array has {len} entries; index {len} appends one)"
                )))
                }
            }
        }
        _ => {
            return Err(err(&format!(
                "`{}` is not a table or array",
                path.join(".")
            )))
        }
    }
    Ok(())
}

/// The dotted key (array entries by index) whose key or value spans the byte range `span` of
/// the TOML text `source`: the deepest such key, or `None` when the text does not parse or no
/// key covers the range.
pub fn key_at_span(source: &str, span: std::ops::Range<usize>) -> Option<String> {
    use toml_edit::{Item, Table, Value};
    fn covers(s: Option<std::ops::Range<usize>>, span: &std::ops::Range<usize>) -> bool {
        s.is_some_and(|s| s.start <= span.start && span.end <= s.end.max(s.start + 1))
    }
    fn in_value(v: &Value, span: &std::ops::Range<usize>, path: &mut Vec<String>) -> bool {
        match v {
            Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    if covers(x.span(), span) {
                        path.push(i.to_string());
                        in_value(x, span, path);
                        return true;
                    }
                }
                covers(v.span(), span)
            }
            Value::InlineTable(t) => {
                for (k, x) in t.iter() {
                    let key = t.key(k).and_then(|k| k.span());
                    if covers(key, span) || covers(x.span(), span) {
                        path.push(k.to_string());
                        in_value(x, span, path);
                        return true;
                    }
                }
                covers(v.span(), span)
            }
            _ => covers(v.span(), span),
        }
    }
    fn in_table(t: &Table, span: &std::ops::Range<usize>, path: &mut Vec<String>) -> bool {
        for (k, item) in t.iter() {
            let key_span = t.key(k).and_then(|k| k.span());
            let at = path.len();
            path.push(k.to_string());
            let found = match item {
                Item::Value(v) => covers(key_span, span) || in_value(v, span, path),
                Item::Table(sub) => in_table(sub, span, path) || covers(sub.span(), span),
                Item::ArrayOfTables(a) => a.iter().enumerate().any(|(i, sub)| {
                    path.push(i.to_string());
                    let f = in_table(sub, span, path) || covers(sub.span(), span);
                    if !f {
                        path.pop();
                    }
                    f
                }),
                Item::None => false,
            };
            if found {
                return true;
            }
            path.truncate(at);
        }
        false
    }
    let doc: toml_edit::ImDocument<&str> = toml_edit::ImDocument::parse(source).ok()?;
    let mut path = Vec::new();
    in_table(doc.as_table(), &span, &mut path).then(|| path.join("."))
}

/// `x` as a TOML number for a `--set` value: an integer when it is one of moderate size (so
/// `elements = 4` stays an integer), else in Rust's shortest form (`0.9`, `1e308`, `NaN`
/// written `nan`) — never the 309 digits `Display` gives 1e308.
pub fn toml_number(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        format!("{x}")
    } else if x.is_nan() {
        "nan".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.into()
    } else {
        format!("{x:?}")
    }
}

/// 1-based line of a dotted key (`stator.0.clearance_nd`, `rotor.mass`) in TOML text, if
/// present. Array indices count `[[name]]` headers. When the full key is absent, the line of its
/// deepest present parent is returned (e.g. the `[[stator]]` header of a missing key).
pub fn locate_key(source: &str, key: &str) -> Option<usize> {
    use toml_edit::{Item, Table, Value};
    enum Cur<'a> {
        Item(&'a Item),
        Table(&'a Table),
    }
    let doc: toml_edit::ImDocument<&str> = toml_edit::ImDocument::parse(source).ok()?;
    let mut cur = Cur::Table(doc.as_table());
    let mut span = None;
    for part in key.split('.') {
        let idx = part.parse::<usize>().ok();
        let next = match (&cur, idx) {
            (Cur::Table(t), None) => t.get_key_value(part).map(|(k, v)| (k.span(), Cur::Item(v))),
            (Cur::Item(Item::Table(t)), None) => {
                t.get_key_value(part).map(|(k, v)| (k.span(), Cur::Item(v)))
            }
            (Cur::Item(Item::Value(Value::InlineTable(t))), None) => t
                .get_key_value(part)
                .map(|(k, _)| (k.span(), Cur::Item(&Item::None))),
            (Cur::Item(Item::ArrayOfTables(a)), Some(i)) => {
                a.get(i).map(|t| (t.span(), Cur::Table(t)))
            }
            (Cur::Item(Item::Value(Value::Array(a))), Some(i)) => {
                a.get(i).map(|v| (v.span(), Cur::Item(&Item::None)))
            }
            _ => None,
        };
        match next {
            Some((s, c)) => {
                span = s.or(span);
                cur = c;
            }
            None => break,
        }
    }
    let start = span?.start;
    Some(source[..start.min(source.len())].matches('\n').count() + 1)
}
