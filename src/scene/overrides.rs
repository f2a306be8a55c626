//! `--set key=value` overrides and locating dotted keys in the TOML text.

use crate::error::SceneError;

/// Applies one `path.to.key=value` assignment; array elements are addressed by index
/// (`stator.0.clearance_nd=0.5`). The value is parsed as TOML (number, bool, array, inline
/// table, quoted string) and falls back to a bare string.
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
    let mut cur = root;
    for (i, part) in parts.iter().enumerate() {
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
                a.get_mut(idx).ok_or_else(|| {
                    err(&format!(
                        "index {idx} out of range (array has {len} entries)"
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
    *cur = value;
    Ok(())
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
