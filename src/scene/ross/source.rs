//! The ROSS file as read: its element tables (TOML or JSON), the typed, checked values of an
//! element (finite numbers, node numbers, coefficient lists) and the line of any key in the
//! user's file, so that every error names the file, the line and ROSS's own key.

use crate::error::SceneError;
use std::path::Path;
use toml::{Table, Value};

/// The saved rotor: the file's path and text, its element tables and where its keys are.
pub(super) struct Source<'a> {
    path: &'a Path,
    text: &'a str,
    /// The TOML document with its spans (`None` for JSON).
    spans: Option<toml_edit::ImDocument<&'a str>>,
    /// The element tables (and `ross_version`), JSON `null`s in objects left out.
    pub doc: Table,
}

impl<'a> Source<'a> {
    /// Reads `text` (from `path`): JSON when it starts with `{`, else TOML.
    ///
    /// # Errors
    /// [`SceneError::Parse`] for a file that is neither; [`SceneError::Invalid`] for a `null`
    /// inside a JSON list (ROSS writes none; leaving it out would shift the list).
    pub fn parse(path: &'a Path, text: &'a str) -> Result<Self, SceneError> {
        let parse_error = |message: String| SceneError::Parse {
            file: path.to_path_buf(),
            message,
        };
        let mut src = Source {
            path,
            text,
            spans: None,
            doc: Table::new(),
        };
        if text.trim_start().starts_with('{') {
            let v: serde_json::Value =
                serde_json::from_str(text).map_err(|e| parse_error(format!("JSON: {e}")))?;
            let mut at = Vec::new();
            match json_to_toml(v, &mut at) {
                Ok(Some(Value::Table(t))) => src.doc = t,
                Ok(_) => return Err(parse_error("JSON: not an object of element tables".into())),
                Err(()) => {
                    let keys: Vec<&str> = at.iter().map(String::as_str).collect();
                    return Err(src.error(&keys, "`null` in a list of numbers".into()));
                }
            }
        } else {
            src.doc = text
                .parse()
                .map_err(|e: toml::de::Error| parse_error(e.to_string()))?;
            src.spans = toml_edit::ImDocument::parse(text).ok();
        }
        Ok(src)
    }

    /// The file's name (for the scene's title).
    pub fn file_name(&self) -> String {
        self.path
            .file_name()
            .map(|f| f.to_string_lossy().to_string())
            .unwrap_or_default()
    }

    /// The 1-based line of the deepest of `keys` (a table name, then keys inside it; empty
    /// names skipped: `""` is the file's top level) found in the file.
    pub fn line(&self, keys: &[&str]) -> Option<usize> {
        let keys: Vec<&str> = keys.iter().copied().filter(|k| !k.is_empty()).collect();
        let keys = keys.as_slice();
        let at = match &self.spans {
            Some(doc) => toml_offset(doc.as_table(), keys),
            None => json_offset(self.text, keys),
        }?;
        Some(self.text.get(..at)?.matches('\n').count() + 1)
    }

    /// An error at `keys` (the element table's name, then ROSS's key in it) of the file.
    pub fn error(&self, keys: &[&str], message: String) -> SceneError {
        SceneError::Invalid {
            file: self.path.to_path_buf(),
            key: keys
                .iter()
                .filter(|k| !k.is_empty())
                .map(|k| toml_key(k))
                .collect::<Vec<_>>()
                .join("."),
            line: self.line(keys),
            message,
        }
    }

    /// The element table `name` with its typed accessors.
    pub fn element(&'a self, name: &'a str, table: &'a Table) -> Element<'a> {
        Element {
            src: self,
            name,
            table,
        }
    }
}

/// `key` as a part of a dotted TOML key: bare when it can be, else quoted and escaped.
fn toml_key(key: &str) -> String {
    let bare = |b: u8| b.is_ascii_alphanumeric() || b == b'_' || b == b'-';
    if !key.is_empty() && key.bytes().all(bare) {
        key.to_string()
    } else {
        format!("{key:?}")
    }
}

/// The byte offset of the deepest key of `keys` in a TOML document.
fn toml_offset(table: &dyn toml_edit::TableLike, keys: &[&str]) -> Option<usize> {
    let (first, rest) = keys.split_first()?;
    let (key, item) = table.get_key_value(first)?;
    let here = key.span().map(|s| s.start);
    match item.as_table_like() {
        Some(t) if !rest.is_empty() => toml_offset(t, rest).or(here),
        _ => here,
    }
}

/// The byte offset of the deepest key of `keys` (object keys from the top) in a JSON text:
/// a scan of its strings and brackets (serde_json keeps no positions).
fn json_offset(text: &str, keys: &[&str]) -> Option<usize> {
    let b = text.as_bytes();
    // The key last read in each open object (`None` in lists and before the first key).
    let mut open: Vec<Option<String>> = Vec::new();
    let (mut best, mut depth) = (None, 0);
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'{' | b'[' => open.push(None),
            b'}' | b']' => {
                open.pop();
            }
            b'"' => {
                let start = i;
                i += 1;
                while i < b.len() && b[i] != b'"' {
                    i += if b[i] == b'\\' { 2 } else { 1 };
                }
                let is_key = text
                    .get(i + 1..)
                    .is_some_and(|r| r.trim_start().starts_with(':'));
                if is_key {
                    let key = text
                        .get(start..=i)
                        .and_then(|raw| serde_json::from_str::<String>(raw).ok());
                    if let Some(last) = open.last_mut() {
                        *last = key;
                    }
                    let d = open.len();
                    let on_path = d <= keys.len()
                        && open.iter().zip(keys).all(|(k, p)| k.as_deref() == Some(*p));
                    if on_path && d > depth {
                        (best, depth) = (Some(start), d);
                        if d == keys.len() {
                            return best;
                        }
                    }
                }
            }
            _ => {}
        }
        i += 1;
    }
    best
}

/// A JSON value as TOML, `null`s in objects left out (ROSS's `None`, which its TOML form
/// leaves out); `None` for a bare `null`. A `null` in a list is an error at the keys in `at`.
fn json_to_toml(v: serde_json::Value, at: &mut Vec<String>) -> Result<Option<Value>, ()> {
    use serde_json::Value as J;
    Ok(Some(match v {
        J::Null => return Ok(None),
        J::Bool(b) => Value::Boolean(b),
        J::Number(n) => match n.as_i64() {
            Some(i) => Value::Integer(i),
            None => match n.as_f64() {
                Some(x) => Value::Float(x),
                None => return Ok(None),
            },
        },
        J::String(s) => Value::String(s),
        J::Array(a) => {
            let mut out = Vec::with_capacity(a.len());
            for v in a {
                out.push(json_to_toml(v, at)?.ok_or(())?);
            }
            Value::Array(out)
        }
        J::Object(o) => {
            let mut t = Table::new();
            for (k, v) in o {
                at.push(k.clone());
                if let Some(v) = json_to_toml(v, at)? {
                    t.insert(k, v);
                }
                at.pop();
            }
            Value::Table(t)
        }
    }))
}

/// One element table of the saved rotor: its values read as ROSS means them, each refusal an
/// error at the element's own key and line.
pub(super) struct Element<'a> {
    src: &'a Source<'a>,
    /// The table's name, `"<Class>_<tag>"`.
    pub name: &'a str,
    /// Its values.
    pub table: &'a Table,
}

/// A finite number, from a TOML/JSON integer or float.
fn as_number(v: &Value) -> Option<f64> {
    match v {
        Value::Float(x) => Some(*x),
        Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

impl Element<'_> {
    /// An error at the element's key `key` (a key path inside the table, e.g. `material.E`;
    /// empty for the table itself).
    pub fn error(&self, key: &str, message: String) -> SceneError {
        let mut keys = vec![self.name];
        keys.extend(key.split('.').filter(|k| !k.is_empty()));
        self.src.error(&keys, message)
    }

    /// The value at `key` (`material.E` for a key of a sub-table).
    fn get(&self, key: &str) -> Option<&Value> {
        let mut t = self.table;
        let mut parts = key.split('.').peekable();
        while let Some(k) = parts.next() {
            let v = t.get(k)?;
            if parts.peek().is_none() {
                return Some(v);
            }
            t = v.as_table()?;
        }
        None
    }

    /// The finite number at `key`, `default` when the key is absent.
    pub fn number_or(&self, key: &str, default: Option<f64>) -> Result<f64, SceneError> {
        let Some(v) = self.get(key) else {
            return default.ok_or_else(|| self.error(key, format!("`{key}` missing")));
        };
        match as_number(v) {
            Some(x) if x.is_finite() => Ok(x),
            Some(x) => Err(self.error(key, format!("`{key}` = {x} is not a finite number"))),
            None => Err(self.error(key, format!("`{key}` = {v} is not a number"))),
        }
    }

    /// The finite number at `key`, which must be present.
    pub fn number(&self, key: &str) -> Result<f64, SceneError> {
        self.number_or(key, None)
    }

    /// The switch at `key`, `default` when absent.
    pub fn flag(&self, key: &str, default: bool) -> Result<bool, SceneError> {
        match self.get(key) {
            None => Ok(default),
            Some(Value::Boolean(b)) => Ok(*b),
            Some(v) => Err(self.error(key, format!("`{key}` = {v} is not true or false"))),
        }
    }

    /// The node number at `key` (ROSS's `n`): a whole number ≥ 0, never rounded or clamped.
    pub fn node(&self, key: &str) -> Result<usize, SceneError> {
        let v = self.get(key);
        let n = match v {
            Some(Value::Integer(i)) => usize::try_from(*i).ok(),
            Some(Value::Float(x)) if x.fract() == 0.0 && (0.0..9.0e15).contains(x) => {
                Some(*x as usize)
            }
            None => return Err(self.error(key, format!("`{key}` missing"))),
            _ => None,
        };
        n.ok_or_else(|| {
            let v = v.map(ToString::to_string).unwrap_or_default();
            self.error(
                key,
                format!("`{key}` = {v} is not a node number (a whole number ≥ 0)"),
            )
        })
    }

    /// The coefficient list at `key` (a bare number is a list of one); `None` when absent.
    /// Empty lists and non-finite values are refused.
    pub fn list(&self, key: &str) -> Result<Option<Vec<f64>>, SceneError> {
        let Some(v) = self.get(key) else {
            return Ok(None);
        };
        let items = match v {
            Value::Array(a) => a.as_slice(),
            v => std::slice::from_ref(v),
        };
        if items.is_empty() {
            return Err(self.error(key, format!("`{key}` is an empty list")));
        }
        items
            .iter()
            .map(|v| match as_number(v) {
                Some(x) if x.is_finite() => Ok(x),
                _ => Err(self.error(
                    key,
                    format!("`{key}` must be finite numbers (a list of them), has {v}"),
                )),
            })
            .collect::<Result<Vec<f64>, _>>()
            .map(Some)
    }

    /// The line of the element's key `key` in the file (its table's line when absent).
    pub fn line(&self, key: &str) -> Option<usize> {
        let mut keys = vec![self.name];
        keys.extend(key.split('.').filter(|k| !k.is_empty()));
        self.src.line(&keys)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_keys_are_found_by_their_path_and_nulls_in_lists_refused() {
        let text =
            "{\n \"a\": {\"L\": 1},\n \"b\\\"q\": {\n  \"x\": [1, {\"L\": 2}],\n  \"L\": 3\n }\n}";
        assert_eq!(
            json_offset(text, &["b\"q", "L"]).map(|o| &text[o..o + 3]),
            Some("\"L\"")
        );
        let src = Source::parse(Path::new("r.json"), text).unwrap();
        assert_eq!(src.line(&["b\"q", "L"]), Some(5));
        assert_eq!(src.line(&["a", "L"]), Some(2));
        assert_eq!(src.line(&["b\"q", "absent"]), Some(3));
        let e = Source::parse(Path::new("r.json"), "{\"B\": {\n\"kxx\": [null]}}")
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("r.json:2: key `B.kxx`") && e.contains("null"),
            "{e}"
        );
    }

    #[test]
    fn toml_keys_are_found_in_sub_tables() {
        let text = "[\"S_0\"]\nL = 1\n\n[\"S_0\".material]\nE = 2\n";
        let src = Source::parse(Path::new("r.toml"), text).unwrap();
        assert_eq!(src.line(&["S_0", "material", "E"]), Some(5));
        assert_eq!(src.line(&["S_0", "L"]), Some(2));
        assert_eq!(src.line(&["S_0", "absent"]), Some(1));
        let t = src.doc["S_0"].as_table().unwrap();
        let el = src.element("S_0", t);
        assert_eq!(el.number("material.E").unwrap(), 2.0);
        assert!(el.node("L").is_ok() && el.node("absent").is_err());
    }
}
