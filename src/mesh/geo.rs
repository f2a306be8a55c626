//! What rubsim reads of a gmsh `.geo` text without running gmsh: the parameters it declares
//! with `DefineConstant` (and the bounds it gives them) and the files it imports.
//!
//! A parameter is declared as `name = default` or, with ONELAB attributes,
//! `name = {default, Min a, Max b, Name "Parameters/name"}` (gmsh wants the `Name` attribute
//! in the braced form). gmsh itself does not enforce `Min` and `Max` on values given with
//! `-setnumber`; rubsim does, before it runs gmsh ([`super::gmsh::mesh`]), so a geometry
//! states the ranges its construction needs (a positive pitch, an element size above 0) and a
//! value outside them is refused at once instead of sending gmsh into minutes of failures.

/// A parameter declared by `DefineConstant`, with the numeric bounds its `Min`/`Max`
/// attributes give (inclusive; attributes that are not plain numbers are not read).
#[derive(Debug, Clone, PartialEq)]
pub struct Declared {
    /// The parameter's name (what `-setnumber` sets).
    pub name: String,
    /// `Min` attribute.
    pub min: Option<f64>,
    /// `Max` attribute.
    pub max: Option<f64>,
}

/// Parameters declared by `DefineConstant[ a = …, b = {…, Min 0, Name "…"}, … ]` in a `.geo`
/// text, sorted by name (a name declared twice keeps its first declaration).
pub fn declared_parameters(text: &str) -> Vec<Declared> {
    let text = strip_comments(text);
    let mut out: Vec<Declared> = Vec::new();
    let mut rest = text.as_str();
    while let Some(i) = rest.find("DefineConstant") {
        rest = &rest[i + "DefineConstant".len()..];
        let Some(open) = rest.find('[') else { break };
        let end = matching_close(rest, open).unwrap_or(rest.len());
        let body = &rest[open + 1..end];
        for item in split_top_level(body) {
            let Some((name, value)) = item.split_once('=') else {
                continue;
            };
            let name = name.trim();
            if name.is_empty() || !name.chars().all(|c| c.is_alphanumeric() || c == '_') {
                continue;
            }
            if out.iter().any(|d| d.name == name) {
                continue;
            }
            let (min, max) = bounds(value);
            out.push(Declared {
                name: name.to_string(),
                min,
                max,
            });
        }
        rest = &rest[end..];
    }
    out.sort_by(|a, b| a.name.cmp(&b.name));
    out
}

/// Names declared by `DefineConstant` in a `.geo` text, sorted.
pub fn defined_parameters(text: &str) -> Vec<String> {
    declared_parameters(text)
        .into_iter()
        .map(|d| d.name)
        .collect()
}

/// Byte offset of the bracket closing the one at `open` (any of `[{(`), if any.
fn matching_close(text: &str, open: usize) -> Option<usize> {
    let mut depth = 0usize;
    for (k, c) in text[open..].char_indices() {
        match c {
            '[' | '{' | '(' => depth += 1,
            ']' | '}' | ')' => {
                depth = depth.saturating_sub(1);
                if depth == 0 {
                    return Some(open + k);
                }
            }
            _ => {}
        }
    }
    None
}

/// The comma-separated items of `body` that are not inside brackets.
fn split_top_level(body: &str) -> Vec<&str> {
    let mut depth = 0usize;
    let mut start = 0;
    let mut items = Vec::new();
    for (k, c) in body.char_indices() {
        match c {
            '[' | '{' | '(' => depth += 1,
            ']' | '}' | ')' => depth = depth.saturating_sub(1),
            ',' if depth == 0 => {
                items.push(&body[start..k]);
                start = k + 1;
            }
            _ => {}
        }
    }
    items.push(&body[start..]);
    items
}

/// `Min` and `Max` of a braced value `{default, Min a, Max b, …}`.
fn bounds(value: &str) -> (Option<f64>, Option<f64>) {
    let v = value.trim();
    let Some(inner) = v.strip_prefix('{').and_then(|v| v.strip_suffix('}')) else {
        return (None, None);
    };
    let (mut min, mut max) = (None, None);
    for attr in split_top_level(inner).into_iter().skip(1) {
        let attr = attr.trim();
        let (key, val) = attr.split_once(char::is_whitespace).unwrap_or((attr, ""));
        let num = val.trim().parse::<f64>().ok().filter(|x| x.is_finite());
        match key {
            "Min" => min = num,
            "Max" => max = num,
            _ => {}
        }
    }
    (min, max)
}

/// Files a `.geo` text imports: string arguments of `ShapeFromFile`, `Merge`, `Include`.
pub fn referenced_files(text: &str) -> Vec<String> {
    let text = strip_comments(text);
    let mut out = Vec::new();
    for kw in ["ShapeFromFile", "Merge", "Include"] {
        let mut rest = text.as_str();
        while let Some(i) = rest.find(kw) {
            rest = &rest[i + kw.len()..];
            let t = rest.trim_start().trim_start_matches('(').trim_start();
            if let Some(s) = t.strip_prefix('"') {
                if let Some(e) = s.find('"') {
                    out.push(s[..e].to_string());
                }
            }
        }
    }
    out
}

/// The text without `//` and `/* */` comments (strings kept as they are).
fn strip_comments(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut chars = text.chars().peekable();
    let mut in_str = false;
    while let Some(c) = chars.next() {
        if in_str {
            out.push(c);
            if c == '"' {
                in_str = false;
            }
            continue;
        }
        match (c, chars.peek()) {
            ('"', _) => {
                in_str = true;
                out.push(c);
            }
            ('/', Some('/')) => {
                for d in chars.by_ref() {
                    if d == '\n' {
                        out.push('\n');
                        break;
                    }
                }
            }
            ('/', Some('*')) => {
                chars.next();
                let mut prev = ' ';
                for d in chars.by_ref() {
                    if prev == '*' && d == '/' {
                        break;
                    }
                    prev = d;
                }
            }
            _ => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_declared_parameters_and_imports() {
        let geo = r#"
// DefineConstant[ commented = 1 ];
DefineConstant[ ri = 0.06, ro = {0.08, Min 0.07, Name "Parameters/ro"},
  h = 0.004 ];
/* Merge "ignored.step"; */
v() = ShapeFromFile( "part.step" );
Include "common.geo";
"#;
        assert_eq!(defined_parameters(geo), vec!["h", "ri", "ro"]);
        assert_eq!(referenced_files(geo), vec!["part.step", "common.geo"]);
    }

    #[test]
    fn reads_min_and_max_of_braced_declarations() {
        let geo = r#"DefineConstant[ a = {1, Min 0.5, Max 2e0, Name "P/a"}, b = 3,
            c = {4, Max 9, Min x, Choices {1, 2}}, a = {7, Min 100} ];"#;
        let d = declared_parameters(geo);
        let get = |n: &str| d.iter().find(|x| x.name == n).unwrap().clone();
        assert_eq!((get("a").min, get("a").max), (Some(0.5), Some(2.0)));
        assert_eq!((get("b").min, get("b").max), (None, None));
        // A bound that is an expression is not read.
        assert_eq!((get("c").min, get("c").max), (None, Some(9.0)));
    }

    #[test]
    fn unbalanced_brackets_do_not_panic() {
        for geo in [
            "DefineConstant[ a = 1 ]]]; ",
            "DefineConstant[ a = {1, Min",
            "DefineConstant",
            "DefineConstant[ ) a = 1 ]",
        ] {
            let _ = declared_parameters(geo);
        }
    }
}
