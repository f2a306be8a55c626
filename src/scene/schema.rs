//! The scene format as a JSON Schema (draft 7) derived from the scene types, and the key
//! reference (docs/SCENE.md) generated from that schema — the keys documented once, where
//! they are defined.
//!
//! The schema mirrors the serde attributes of the types (`schemars` reads them):
//! `deny_unknown_fields` → `additionalProperties: false`, renames (`[[station]]`,
//! `[[stator]]`), defaults, the `kind`-tagged enums (`[rotor]`, `[[stator]]`, FE stator
//! elements) and the untagged ones (a scalar or a table, `output.per_speed`). The alternative
//! keys of a table (`clearance` / `clearance_nd`, …: exactly one, or at most one) are stated on
//! the types. TOML has no null: an optional key is one that may be left out, so the `null`
//! that `Option` adds is removed. The doc comments of the types become the descriptions.

use super::Scene;
use schemars::generate::SchemaSettings;
use serde_json::{Map, Value};

/// The command that writes [`json_text`] to the committed file.
pub const SCHEMA_COMMAND: &str = "rubsim schema --out schema/scene.schema.json";
/// The command that writes [`markdown`] to the committed file.
pub const MARKDOWN_COMMAND: &str = "rubsim schema --markdown docs/SCENE.md";

/// The JSON Schema (draft 7) of a scene file, as a JSON value.
pub fn json_schema() -> Value {
    let generator = SchemaSettings::draft07().for_deserialize().into_generator();
    let mut value = generator.into_root_schema_for::<Scene>().to_value();
    strip_null(&mut value);
    if let Value::Object(root) = &mut value {
        root.insert("title".into(), "rubsim scene".into());
        root.insert(
            "$comment".into(),
            format!("Generated from the scene types by `{SCHEMA_COMMAND}`: do not edit.").into(),
        );
    }
    value
}

/// [`json_schema`] as pretty-printed JSON text with a final newline.
pub fn json_text() -> String {
    let mut text = serde_json::to_string_pretty(&json_schema()).unwrap_or_default();
    text.push('\n');
    text
}

/// Removes what `Option` adds for JSON and TOML cannot say: `null` in a `type` list, a
/// `{"type": "null"}` alternative of `anyOf`/`oneOf` (a single alternative left is unwrapped,
/// under `allOf` when it is a `$ref` with siblings, which draft 7 would ignore) and a `null`
/// default.
fn strip_null(value: &mut Value) {
    match value {
        Value::Object(obj) => {
            strip_null_here(obj);
            obj.values_mut().for_each(strip_null);
        }
        Value::Array(items) => items.iter_mut().for_each(strip_null),
        _ => {}
    }
}

fn strip_null_here(obj: &mut Map<String, Value>) {
    match obj.get_mut("default") {
        Some(Value::Null) => {
            obj.remove("default");
        }
        Some(Value::Object(d)) => d.retain(|_, v| !v.is_null()),
        _ => {}
    }
    if let Some(Value::Array(types)) = obj.get_mut("type") {
        types.retain(|t| t != "null");
        if types.len() == 1 {
            let only = types.remove(0);
            obj.insert("type".into(), only);
        }
    }
    for key in ["anyOf", "oneOf"] {
        let Some(Value::Array(alternatives)) = obj.get_mut(key) else {
            continue;
        };
        let is_null = |v: &Value| {
            v.get("type").is_some_and(|t| t == "null")
                && v.as_object().is_some_and(|o| o.len() == 1)
        };
        if !alternatives.iter().any(is_null) {
            continue;
        }
        alternatives.retain(|v| !is_null(v));
        if alternatives.len() == 1 {
            let only = alternatives.remove(0);
            obj.remove(key);
            match only {
                Value::Object(o) if o.contains_key("$ref") && !obj.is_empty() => {
                    obj.insert("allOf".into(), Value::Array(vec![Value::Object(o)]));
                }
                Value::Object(o) => obj.extend(o),
                _ => {}
            }
        }
    }
    if obj
        .get("enum")
        .is_some_and(|e| e.as_array().is_some_and(|a| a.iter().any(Value::is_null)))
    {
        if let Some(Value::Array(e)) = obj.get_mut("enum") {
            e.retain(|v| !v.is_null());
        }
    }
}

/// The definitions of a root schema (`definitions`, draft 7).
type Defs = Map<String, Value>;

/// `s` with a `$ref` (alone or as the one member of `allOf`) followed to its definition.
fn resolve<'a>(defs: &'a Defs, s: &'a Value) -> &'a Value {
    let target = s.get("$ref").or_else(|| {
        s.get("allOf")
            .and_then(Value::as_array)
            .filter(|a| a.len() == 1)
            .and_then(|a| a[0].get("$ref"))
    });
    match target.and_then(Value::as_str) {
        Some(r) => r
            .rsplit('/')
            .next()
            .and_then(|name| defs.get(name))
            .map_or(s, |d| resolve(defs, d)),
        None => s,
    }
}

/// The variants of a `kind`-tagged enum: object alternatives, each with a `const` tag.
fn variants(s: &Value) -> Option<&Vec<Value>> {
    let alts = s.get("oneOf").or_else(|| s.get("anyOf"))?.as_array()?;
    alts.iter()
        .all(|a| a.pointer("/properties/kind/const").is_some())
        .then_some(alts)
}

/// Whether `s` is written as a TOML table: an object with properties or a tagged enum.
fn is_table(s: &Value) -> bool {
    s.get("properties").is_some() || variants(s).is_some()
}

/// The table (and whether it is an array of tables, `[[…]]`) a key's schema `s` holds.
fn sub_table<'a>(defs: &'a Defs, s: &'a Value) -> Option<(&'a Value, bool)> {
    let r = resolve(defs, s);
    if is_table(r) {
        return Some((r, false));
    }
    let items = r.get("items").filter(|i| i.is_object())?;
    let t = resolve(defs, items);
    is_table(t).then_some((t, true))
}

/// The TOML header of the table at dotted `path`.
fn header(path: &str, array: bool) -> String {
    if array {
        format!("[[{path}]]")
    } else {
        format!("[{path}]")
    }
}

/// The type of a key as a reader says it: `number`, `[number, number]`, `array of string`,
/// `number or array of number`, a table's header.
fn type_name(defs: &Defs, s: &Value, path: &str) -> String {
    if let Some((_, array)) = sub_table(defs, s) {
        return format!("table `{}`", header(path, array));
    }
    let r = resolve(defs, s);
    if let Some(c) = r.get("const") {
        return format!("`{}`", toml_text(c));
    }
    if let Some(alts) = r.get("anyOf").and_then(Value::as_array) {
        let names: Vec<String> = alts.iter().map(|a| type_name(defs, a, path)).collect();
        return names.join(" or ");
    }
    if let Some(alts) = r.get("oneOf").and_then(Value::as_array) {
        // An enum of documented constants: the type of its values.
        let first = alts.first().and_then(|a| a.get("const"));
        return match first {
            Some(Value::Number(n)) if n.is_f64() => "number".into(),
            Some(Value::Number(_)) => "integer".into(),
            Some(Value::Bool(_)) => "boolean".into(),
            _ => "string".into(),
        };
    }
    match r.get("type").and_then(Value::as_str) {
        Some("array") => array_type(defs, r, path),
        Some("object") => match r.get("additionalProperties").filter(|a| a.is_object()) {
            Some(v) => format!("table of {}", type_name(defs, v, path)),
            None => "table".into(),
        },
        Some(t) => t.to_string(),
        None => "any".into(),
    }
}

/// The type of an array: a tuple (`[integer, number]`), a fixed length (`[number, number]`)
/// or a list (`array of number`).
fn array_type(defs: &Defs, r: &Value, path: &str) -> String {
    match r.get("items") {
        Some(Value::Array(items)) => {
            let names: Vec<String> = items.iter().map(|i| type_name(defs, i, path)).collect();
            format!("[{}]", names.join(", "))
        }
        Some(items) => {
            let item = type_name(defs, items, path);
            let (lo, hi) = (r.get("minItems"), r.get("maxItems"));
            match (lo.and_then(Value::as_u64), hi.and_then(Value::as_u64)) {
                (Some(n), Some(m)) if n == m && n <= 4 => {
                    format!("[{}]", vec![item; n as usize].join(", "))
                }
                _ => format!("array of {item}"),
            }
        }
        None => "array".into(),
    }
}

/// The values a key allows (`enum`, or `oneOf` of constants with their descriptions), also
/// for the items of an array.
fn allowed(defs: &Defs, s: &Value) -> Vec<(String, String)> {
    let r = resolve(defs, s);
    if let Some(items) = r.get("items").filter(|i| i.is_object()) {
        return allowed(defs, items);
    }
    if let Some(e) = r.get("enum").and_then(Value::as_array) {
        return e.iter().map(|v| (toml_text(v), String::new())).collect();
    }
    let Some(alts) = r.get("oneOf").and_then(Value::as_array) else {
        return Vec::new();
    };
    alts.iter()
        .filter_map(|a| {
            let c = a.get("const").or_else(|| {
                a.get("enum")
                    .and_then(Value::as_array)
                    .filter(|e| e.len() == 1)
                    .map(|e| &e[0])
            })?;
            Some((toml_text(c), text(a.get("description"))))
        })
        .collect()
}

/// A JSON value as TOML text (strings quoted, arrays inline).
fn toml_text(v: &Value) -> String {
    match v {
        Value::String(s) => format!("\"{s}\""),
        Value::Array(a) => {
            let items: Vec<String> = a.iter().map(toml_text).collect();
            format!("[{}]", items.join(", "))
        }
        Value::Object(o) if o.is_empty() => "{}".into(),
        Value::Object(o) => {
            let items: Vec<String> = o
                .iter()
                .map(|(k, v)| format!("{k} = {}", toml_text(v)))
                .collect();
            format!("{{ {} }}", items.join(", "))
        }
        other => other.to_string(),
    }
}

/// A description on one line, for a Markdown table cell: whitespace runs joined, `|`
/// escaped, rustdoc links `` [`x`] `` shown as `` `x` ``.
fn text(d: Option<&Value>) -> String {
    let raw = d.and_then(Value::as_str).unwrap_or_default();
    let joined = raw.split_whitespace().collect::<Vec<_>>().join(" ");
    let mut out = String::with_capacity(joined.len());
    let mut rest = joined.as_str();
    while let Some(i) = rest.find("[`") {
        out.push_str(&rest[..i]);
        let after = &rest[i + 1..];
        match after.find("`]") {
            Some(j) if !after[..j + 1].contains('[') => {
                out.push_str(&after[..j + 1]);
                rest = &after[j + 2..];
                // `[`x`](link)`: drop the link target too.
                if rest.starts_with('(') {
                    if let Some(k) = rest.find(')') {
                        rest = &rest[k + 1..];
                    }
                }
            }
            _ => {
                out.push('[');
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out.replace('|', "\\|")
}

/// The rules between keys a table's schema states: `oneOf` of `required` groups (exactly
/// one), `not` of `required` (not together), each under `allOf` or alone.
fn rules(s: &Value) -> Vec<String> {
    let keys = |v: &Value| -> Vec<String> {
        v.get("required")
            .and_then(Value::as_array)
            .map(|r| {
                r.iter()
                    .map(|k| format!("`{}`", k.as_str().unwrap_or_default()))
                    .collect()
            })
            .unwrap_or_default()
    };
    let one = |v: &Value| -> Option<String> {
        if let Some(alts) = v.get("oneOf").and_then(Value::as_array) {
            let names: Vec<String> = alts.iter().flat_map(keys).collect();
            return (names.len() == alts.len() && !names.is_empty())
                .then(|| format!("Give exactly one of {}.", names.join(", ")));
        }
        let names = keys(v.get("not")?);
        (!names.is_empty()).then(|| format!("Give at most one of {}.", names.join(", ")))
    };
    let mut out: Vec<String> = s
        .get("allOf")
        .and_then(Value::as_array)
        .map(|a| a.iter().filter_map(one).collect())
        .unwrap_or_default();
    if variants(s).is_none() {
        out.extend(one(s));
    }
    out
}

/// The Markdown key table of the table `t` at `path`, then the sections of its sub-tables
/// not written yet (`done` holds the headers written).
fn table_section(
    defs: &Defs,
    t: &Value,
    path: &str,
    level: usize,
    done: &mut Vec<String>,
    out: &mut String,
) {
    let Some(props) = t.get("properties").and_then(Value::as_object) else {
        return;
    };
    let required: Vec<&str> = t
        .get("required")
        .and_then(Value::as_array)
        .map(|r| r.iter().filter_map(Value::as_str).collect())
        .unwrap_or_default();
    out.push_str("| key | type | default | description |\n|---|---|---|---|\n");
    let mut children = Vec::new();
    for (key, s) in props {
        let sub = if path.is_empty() {
            key.clone()
        } else {
            format!("{path}.{key}")
        };
        let default = match s.get("default") {
            _ if required.contains(&key.as_str()) => "required".to_string(),
            Some(d) => format!("`{}`", toml_text(d)),
            None => "—".into(),
        };
        let mut desc = text(s.get("description"));
        if key == "kind" && desc.is_empty() {
            desc = "Which model this table is.".into();
        }
        let values = allowed(defs, s);
        if !values.is_empty() {
            let list: Vec<String> = values
                .iter()
                .map(|(v, d)| match d.trim_end_matches('.') {
                    "" => format!("`{v}`"),
                    d => format!("`{v}`: {d}"),
                })
                .collect();
            desc = format!("{desc} One of: {}.", list.join("; "))
                .trim()
                .to_string();
        }
        let ty = type_name(defs, s, &sub);
        out.push_str(&format!("| `{key}` | {ty} | {default} | {desc} |\n"));
        if let Some(child) = sub_table(defs, s) {
            children.push((sub, child));
        }
    }
    let rules = rules(t);
    if !rules.is_empty() {
        out.push_str(&format!("\n{}\n", rules.join(" ")));
    }
    out.push('\n');
    for (sub, (c, is_array)) in children {
        section(defs, c, (&sub, is_array), level, done, out);
    }
}

/// The section of the table `t` at `path`: its header and description, then its keys — one
/// section per variant of a `kind`-tagged table. A header written before is not repeated.
fn section(
    defs: &Defs,
    t: &Value,
    (path, array): (&str, bool),
    level: usize,
    done: &mut Vec<String>,
    out: &mut String,
) {
    let hashes = "#".repeat(level.min(4));
    let head = header(path, array);
    if let Some(alts) = variants(t) {
        heading(out, &format!("{hashes} `{head}`"), t);
        let kinds: Vec<String> = alts
            .iter()
            .map(|a| format!("`{}`", toml_text(&a["properties"]["kind"]["const"])))
            .collect();
        out.push_str(&format!("`kind` is one of {}.\n\n", kinds.join(", ")));
        for a in alts {
            let kind = toml_text(&a["properties"]["kind"]["const"]);
            let name = format!("{head} kind = {kind}");
            if done.contains(&name) {
                continue;
            }
            done.push(name.clone());
            heading(out, &format!("{hashes}# `{head}` kind = {kind}"), a);
            table_section(defs, a, path, level + 2, done, out);
        }
        return;
    }
    if done.contains(&head) {
        return;
    }
    done.push(head.clone());
    heading(out, &format!("{hashes} `{head}`"), t);
    table_section(defs, t, path, level + 1, done, out);
}

/// A Markdown heading line `title`, then the schema `node`'s description as a paragraph when
/// it has one.
fn heading(out: &mut String, title: &str, node: &Value) {
    out.push_str(&format!("{title}\n\n"));
    let desc = text(node.get("description"));
    if !desc.is_empty() {
        out.push_str(&format!("{desc}\n\n"));
    }
}

/// The key reference of a scene file (docs/SCENE.md) from the schema [`json_schema`] gives:
/// every table and key with its type, default, allowed values and description (units
/// included), and the rules between alternative keys.
pub fn markdown(schema: &Value) -> String {
    let empty = Defs::new();
    let defs = schema
        .get("definitions")
        .and_then(Value::as_object)
        .unwrap_or(&empty);
    let mut out = format!(
        "# Scene keys\n\n<!-- Generated from the scene types (src/scene/) by `{MARKDOWN_COMMAND}`: do not edit; \
         tests/suite/schema.rs fails when it is stale. -->\n\n\
         Every key of a scene file, generated from the scene types — the same source as the JSON \
         Schema `schema/scene.schema.json` (`{SCHEMA_COMMAND}`) that editors use to complete and \
         check scene files (docs/GUIDE.md). All values are SI (kg, m, s, N, Pa, rad/s) unless a \
         key says otherwise; angles are in degrees where the key ends in `_deg`. A key marked \
         *required* must be given; one with a default may be left out; one with neither is \
         optional (its description says what leaving it out means). Unknown keys are refused.\n\n"
    );
    out.push_str(&format!("{}\n\n", text(schema.get("description"))));
    out.push_str("## Top level\n\n");
    let mut done = Vec::new();
    table_section(defs, schema, "", 2, &mut done, &mut out);
    while out.ends_with("\n\n") {
        out.pop();
    }
    out
}
