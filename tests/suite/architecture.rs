//! The house keeps its shape: every library module imports only modules of its own stage or
//! below (the one-way pipeline of `src/lib.rs` and `docs/ARCHITECTURE.md`), no source file
//! takes part in an import cycle with other files, the binary's `src/cli/` is the only user of
//! `anyhow`, no source file outgrows 800 lines, no function outside the tests outgrows 100
//! lines, and docs/ARCHITECTURE.md's stage table says what each module imports.
//!
//! Everything here reads the sources as text: comments and the contents of string and
//! character literals are blanked first ([`code`]), so only code is read.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The stages, lowest first: a module may import modules of its own stage or of a lower one.
const STAGES: &[&[&str]] = &[
    &["error", "math"],
    &["linalg", "signal", "mesh", "element", "assembly", "plot"],
    &["contact"],
    &["scene"],
    &["resolve"],
    &["model"],
    &["linear"],
    &["time"],
    &["analysis"],
    &["output", "results"],
    &["study"],
];

/// The longest a function may be, from its `fn` line to its closing brace.
const MAX_FUNCTION_LINES: usize = 100;

/// Temporary exceptions to [`MAX_FUNCTION_LINES`]: functions in files other developers are
/// reworking this session (the run path: "driver"; studies, sweeps and maps: "study"), each
/// accepted only while it is at most its length of today. Remove a row when its branch merges;
/// a row no longer needed fails the test so that it cannot be forgotten.
const LONG_FUNCTION_EXCEPTIONS: &[(&str, &str, usize)] = &[];

/// Temporary exceptions to the file-level acyclicity: import edges of the files other
/// developers are reworking this session (see [`LONG_FUNCTION_EXCEPTIONS`]), which close a
/// cycle today. Remove a row when its branch merges; a row no longer needed fails the test.
const CYCLE_EXCEPTIONS: &[(&str, &str)] = &[];

fn stage(module: &str) -> usize {
    STAGES
        .iter()
        .position(|s| s.contains(&module))
        .unwrap_or_else(|| {
            panic!("module `{module}` is in no stage of tests/suite/architecture.rs")
        })
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// Every file of `src/` as (path relative to `src/` with `/` separators, text), sorted.
fn sources() -> Vec<(String, String)> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut out: Vec<(String, String)> = files
        .iter()
        .map(|f| {
            let rel = f.strip_prefix(&src).unwrap();
            let rel: Vec<String> = rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            (rel.join("/"), std::fs::read_to_string(f).unwrap())
        })
        .collect();
    out.sort();
    out
}

fn is_ident(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_' || b >= 0x80
}

/// The code of a Rust source with its comments (line, block, doc) and the contents of its
/// string and character literals blanked to spaces; newlines are kept, so line numbers hold.
fn code(text: &str) -> String {
    let c = text.as_bytes();
    let mut out = c.to_vec();
    let blank = |out: &mut Vec<u8>, from: usize, to: usize| {
        for b in &mut out[from..to] {
            if *b != b'\n' {
                *b = b' ';
            }
        }
    };
    let mut i = 0;
    while i < c.len() {
        let starts_word = i == 0 || !is_ident(c[i - 1]);
        if c[i..].starts_with(b"//") {
            let end = c[i..]
                .iter()
                .position(|&b| b == b'\n')
                .map_or(c.len(), |k| i + k);
            blank(&mut out, i, end);
            i = end;
        } else if c[i..].starts_with(b"/*") {
            let (mut depth, mut k) = (0, i);
            while k < c.len() {
                if c[k..].starts_with(b"/*") {
                    depth += 1;
                    k += 2;
                } else if c[k..].starts_with(b"*/") {
                    depth -= 1;
                    k += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    k += 1;
                }
            }
            blank(&mut out, i, k.min(c.len()));
            i = k;
        } else if c[i] == b'r'
            && (starts_word || (i >= 1 && c[i - 1] == b'b' && (i < 2 || !is_ident(c[i - 2]))))
            && c[i + 1..].iter().take_while(|&&b| b == b'#').count() < c.len() - i - 1
            && c[i + 1 + c[i + 1..].iter().take_while(|&&b| b == b'#').count()] == b'"'
        {
            // A raw string r#"…"#: its end is a quote followed by as many hashes.
            let hashes = c[i + 1..].iter().take_while(|&&b| b == b'#').count();
            let open = i + 2 + hashes;
            let mut close = vec![b'"'];
            close.extend(std::iter::repeat_n(b'#', hashes));
            let end = c[open..]
                .windows(close.len())
                .position(|w| w == close.as_slice())
                .map_or(c.len(), |k| open + k);
            blank(&mut out, open, end);
            i = (end + close.len()).min(c.len());
        } else if c[i] == b'"' {
            let mut k = i + 1;
            while k < c.len() && c[k] != b'"' {
                k += if c[k] == b'\\' { 2 } else { 1 };
            }
            blank(&mut out, i + 1, k.min(c.len()));
            i = k + 1;
        } else if c[i] == b'\'' && i + 1 < c.len() {
            // A character literal ('x', '\n', '─'), else a lifetime or label ('a).
            let width = match c[i + 1] {
                b'\\' => c[(i + 3).min(c.len())..]
                    .iter()
                    .position(|&b| b == b'\'')
                    .map(|k| k + 2),
                b if b < 0x80 => Some(1),
                b if b >= 0xF0 => Some(4),
                b if b >= 0xE0 => Some(3),
                _ => Some(2),
            };
            match width {
                Some(w) if c.get(i + 1 + w) == Some(&b'\'') => {
                    blank(&mut out, i + 1, i + 1 + w);
                    i += w + 2;
                }
                _ => i += 1,
            }
        } else {
            i += 1;
        }
    }
    String::from_utf8(out).unwrap()
}

/// The byte just after the item that starts at `from`: its `;`, or the brace closing the
/// first `{` outside parentheses and brackets.
fn item_end(code: &[u8], from: usize) -> usize {
    let mut depth = 0i32;
    let mut k = from;
    while k < code.len() {
        match code[k] {
            b'(' | b'[' => depth += 1,
            b')' | b']' => depth -= 1,
            b';' if depth == 0 => return k + 1,
            b'{' if depth == 0 => return matching_brace(code, k) + 1,
            _ => {}
        }
        k += 1;
    }
    code.len()
}

/// The position of the brace closing the one at `open`.
fn matching_brace(code: &[u8], open: usize) -> usize {
    let mut depth = 0;
    for (k, &b) in code.iter().enumerate().skip(open) {
        match b {
            b'{' => depth += 1,
            b'}' => {
                depth -= 1;
                if depth == 0 {
                    return k;
                }
            }
            _ => {}
        }
    }
    code.len() - 1
}

/// `code` with every item under `#[cfg(test)]` (test modules, test-only functions) blanked.
fn without_tests(code: &str) -> String {
    let mut out = code.as_bytes().to_vec();
    let mut from = 0;
    while let Some(k) = String::from_utf8_lossy(&out[from..]).find("#[cfg(test)]") {
        let at = from + k;
        let end = item_end(&out, at + "#[cfg(test)]".len());
        for b in &mut out[at..end] {
            if *b != b'\n' {
                *b = b' ';
            }
        }
        from = end;
    }
    String::from_utf8(out).unwrap()
}

/// The positions where the word `word` starts in `code`, not preceded by `::` (the second
/// `super` of `super::super` is part of the first's path).
fn word_starts(code: &str, word: &str) -> Vec<usize> {
    let b = code.as_bytes();
    code.match_indices(word)
        .map(|(i, _)| i)
        .filter(|&i| {
            (i == 0 || (!is_ident(b[i - 1]) && b[i - 1] != b':'))
                && b.get(i + word.len()).is_none_or(|&c| !is_ident(c))
        })
        .collect()
}

/// Every function with a body in `code` (comments and literals already blanked): its name,
/// the line of its `fn` (1-based) and its length in lines, from that line to its closing
/// brace.
fn functions(code: &str) -> Vec<(String, usize, usize)> {
    let b = code.as_bytes();
    let line = |at: usize| 1 + b[..at].iter().filter(|&&c| c == b'\n').count();
    let mut out = Vec::new();
    for at in word_starts(code, "fn") {
        let rest = &code[at + 2..];
        let name: String = rest
            .trim_start()
            .chars()
            .take_while(|&c| c.is_alphanumeric() || c == '_')
            .collect();
        if name.is_empty() || !rest.starts_with(char::is_whitespace) {
            continue; // a function pointer type `fn(…)`
        }
        let end = item_end(b, at);
        if b[end - 1] == b'}' {
            out.push((name, line(at), line(end - 1) - line(at) + 1));
        }
    }
    out
}

/// The paths named after `prefix::` in `code`, each as its segments after the prefix, grouped
/// imports expanded (`crate::{a::{b, c}, d}` gives `a::b`, `a::c` and `d`; `self` and `*` in a
/// group name the group's own path); with the position of the prefix.
fn paths(code: &str, prefix: &str) -> Vec<(usize, Vec<String>)> {
    fn tree(s: &[u8], mut k: usize) -> Vec<Vec<String>> {
        while k < s.len() && s[k].is_ascii_whitespace() {
            k += 1;
        }
        match s.get(k) {
            Some(b'{') => {
                let close = matching_brace(s, k);
                let (mut depth, mut start, mut out) = (0, k + 1, Vec::new());
                for j in k + 1..=close {
                    match s[j] {
                        b'{' => depth += 1,
                        b'}' if depth > 0 => depth -= 1,
                        b',' | b'}' if depth == 0 => {
                            if !s[start..j].iter().all(u8::is_ascii_whitespace) {
                                out.extend(tree(&s[..j], start));
                            }
                            start = j + 1;
                        }
                        _ => {}
                    }
                }
                out
            }
            Some(b'*') => vec![Vec::new()],
            Some(&c) if is_ident(c) => {
                let end = k + s[k..].iter().take_while(|&&c| is_ident(c)).count();
                let name = String::from_utf8_lossy(&s[k..end]).into_owned();
                if name == "self" {
                    return vec![Vec::new()];
                }
                let mut j = end;
                while j < s.len() && s[j].is_ascii_whitespace() {
                    j += 1;
                }
                if s[j..].starts_with(b"::") {
                    let mut sub = tree(s, j + 2);
                    for p in &mut sub {
                        p.insert(0, name.clone());
                    }
                    sub
                } else {
                    vec![vec![name]]
                }
            }
            _ => Vec::new(),
        }
    }
    let b = code.as_bytes();
    word_starts(code, prefix)
        .into_iter()
        .filter(|&at| b[at + prefix.len()..].starts_with(b"::"))
        .flat_map(|at| {
            tree(b, at + prefix.len() + 2)
                .into_iter()
                .map(move |p| (at, p))
        })
        .collect()
}

/// A source file's crate (`true`: the binary, `main.rs` and `cli/`) and module path.
fn module_of(rel: &str) -> (bool, Vec<String>) {
    let binary = rel == "main.rs" || rel.starts_with("cli/");
    let mut path: Vec<String> = rel
        .trim_end_matches(".rs")
        .split('/')
        .map(str::to_string)
        .collect();
    if matches!(
        path.last().map(String::as_str),
        Some("mod" | "lib" | "main")
    ) {
        path.pop();
    }
    (binary, path)
}

/// The inline modules (`mod name { … }`) of `code` as (name, first byte, last byte).
fn inline_modules(code: &str) -> Vec<(String, usize, usize)> {
    let b = code.as_bytes();
    word_starts(code, "mod")
        .into_iter()
        .filter_map(|at| {
            let rest = &code[at + 3..];
            let name: String = rest
                .trim_start()
                .chars()
                .take_while(|&c| c.is_alphanumeric() || c == '_')
                .collect();
            let after = at + 3 + (rest.len() - rest.trim_start().len()) + name.len();
            let open = after + (code[after..].len() - code[after..].trim_start().len());
            (b.get(open) == Some(&b'{')).then(|| (name, open, matching_brace(b, open)))
        })
        .collect()
}

/// The child modules a file declares in files of their own (`mod name;`).
fn child_modules(code: &str) -> Vec<String> {
    word_starts(code, "mod")
        .into_iter()
        .filter_map(|at| {
            let rest = code[at + 3..].trim_start();
            let name: String = rest
                .chars()
                .take_while(|&c| c.is_alphanumeric() || c == '_')
                .collect();
            (!name.is_empty() && rest[name.len()..].trim_start().starts_with(';')).then_some(name)
        })
        .collect()
}

/// `code` with its re-exports (`pub use …;`, `pub(crate) use …;`) blanked.
fn without_re_exports(code: &str) -> String {
    let mut out = code.as_bytes().to_vec();
    for at in word_starts(code, "pub") {
        let rest = &code[at + 3..];
        let vis = if rest.starts_with('(') {
            rest.find(')').map_or(0, |k| k + 1)
        } else {
            0
        };
        if word_starts(&rest[vis..], "use").first()
            == Some(&(rest[vis..].len() - rest[vis..].trim_start().len()))
        {
            let end = item_end(&out, at);
            for b in &mut out[at..end] {
                if *b != b'\n' {
                    *b = b' ';
                }
            }
        }
    }
    String::from_utf8(out).unwrap()
}

/// The file-level import graph of a crate's sources (path relative to `src/` → text): a
/// file imports the files its `crate::`, `super::` and `self::` paths (and, in the binary,
/// `rubsim::` paths) resolve to — the file of the longest leading part of the path that is a
/// module — and the files of its child modules (`mod name;`) it imports by `use name::…`
/// (the same import as `use self::name::…`). A re-export (`pub use name::…`) is the module's
/// face, not an import of its code, and a parent's calls into its own children
/// (`name::f()`, the dispatch of a `mod.rs`) do not count either: a parent may call its
/// children while they use its shared items. The code under `#[cfg(test)]` does not count,
/// nor does a file importing itself.
fn file_graph(files: &[(String, String)]) -> BTreeMap<String, BTreeSet<String>> {
    let modules: BTreeMap<(bool, Vec<String>), &str> = files
        .iter()
        .map(|(rel, _)| (module_of(rel), rel.as_str()))
        .collect();
    let resolve = |binary: bool, path: &[String]| {
        (0..=path.len())
            .rev()
            .find_map(|n| modules.get(&(binary, path[..n].to_vec())).copied())
    };
    let mut graph = BTreeMap::new();
    for (rel, text) in files {
        let code = without_re_exports(&without_tests(&code(text)));
        let (binary, here) = module_of(rel);
        let inline = inline_modules(&code);
        // The module path at byte `at`: the file's, then the inline modules around it.
        let at_module = |at: usize| {
            let mut m = here.clone();
            m.extend(
                inline
                    .iter()
                    .filter(|(_, a, b)| *a < at && at < *b)
                    .map(|(n, _, _)| n.clone()),
            );
            m
        };
        let mut deps = BTreeSet::new();
        let children = child_modules(&code);
        let uses: Vec<(usize, usize)> = word_starts(&code, "use")
            .into_iter()
            .map(|at| (at, item_end(code.as_bytes(), at)))
            .collect();
        let prefixes = ["crate", "super", "self", "rubsim"];
        for prefix in prefixes
            .iter()
            .copied()
            .chain(children.iter().map(String::as_str))
        {
            if prefix == "rubsim" && !binary {
                continue;
            }
            for (at, mut path) in paths(&code, prefix) {
                let mut base = match prefix {
                    "crate" | "rubsim" => Vec::new(),
                    _ => at_module(at),
                };
                if !prefixes.contains(&prefix) {
                    if !uses.iter().any(|&(a, b)| a < at && at < b) {
                        continue; // a parent's own call into its child, `child::f()`
                    }
                    base.push(prefix.to_string());
                }
                if prefix == "super" {
                    base.pop();
                }
                while path.first().is_some_and(|s| s == "super") {
                    path.remove(0);
                    base.pop();
                }
                base.extend(path);
                if let Some(f) = resolve(binary && prefix != "rubsim", &base) {
                    if f != rel {
                        deps.insert(f.to_string());
                    }
                }
            }
        }
        graph.insert(rel.clone(), deps);
    }
    graph
}

/// The files `from` reaches in `graph` without the `allowed` edges.
fn reach<'a>(
    graph: &'a BTreeMap<String, BTreeSet<String>>,
    allowed: &[(&str, &str)],
    from: &'a str,
) -> BTreeSet<&'a str> {
    let mut seen = BTreeSet::new();
    let mut stack = vec![from];
    while let Some(f) = stack.pop() {
        for d in graph.get(f).into_iter().flatten() {
            if !allowed.contains(&(f, d.as_str())) && seen.insert(d.as_str()) {
                stack.push(d.as_str());
            }
        }
    }
    seen
}

/// The import cycles of `graph` once the `allowed` edges are taken out: one line per
/// strongly connected component of more than one file, naming its files and its edges.
fn cycles(graph: &BTreeMap<String, BTreeSet<String>>, allowed: &[(&str, &str)]) -> Vec<String> {
    let reached: BTreeMap<&str, BTreeSet<&str>> = graph
        .keys()
        .map(|f| (f.as_str(), reach(graph, allowed, f)))
        .collect();
    let mut done = BTreeSet::new();
    let mut out = Vec::new();
    for f in graph.keys().map(String::as_str) {
        if done.contains(f) || !reached[f].contains(f) {
            continue;
        }
        // Files that reach each other both ways form one component.
        let scc: BTreeSet<&str> = reached[f]
            .iter()
            .copied()
            .filter(|g| reached.get(g).is_some_and(|r| r.contains(f)))
            .collect();
        let inner: Vec<String> = scc
            .iter()
            .flat_map(|&g| {
                graph[g]
                    .iter()
                    .filter(|d| scc.contains(d.as_str()) && !allowed.contains(&(g, d.as_str())))
                    .map(move |d| format!("{g} → {d}"))
            })
            .collect();
        out.push(format!("cycle among {scc:?}: {}", inner.join(", ")));
        done.extend(scc);
    }
    out
}

/// Library module → the library modules its files import (from [`file_graph`]).
fn module_imports(
    graph: &BTreeMap<String, BTreeSet<String>>,
) -> BTreeMap<String, BTreeSet<String>> {
    let top = |rel: &str| {
        let (binary, m) = module_of(rel);
        (!binary).then(|| m.first().cloned()).flatten()
    };
    let mut out: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (f, deps) in graph {
        let Some(m) = top(f) else { continue };
        let entry = out.entry(m.clone()).or_default();
        entry.extend(deps.iter().filter_map(|d| top(d)).filter(|d| *d != m));
    }
    out
}

/// The differences between a stage table (`| stage | module | … | imports |`, the imports a
/// comma-separated list of module names, each optionally followed by a parenthesis; `—` for
/// none) and the modules' imports: a line per module whose row is missing, extra, at another
/// stage than [`STAGES`] or imports other modules than it says.
fn table_mismatches(doc: &str, imports: &BTreeMap<String, BTreeSet<String>>) -> Vec<String> {
    let mut rows = BTreeMap::new();
    for line in doc.lines().filter(|l| l.starts_with('|')) {
        let cells: Vec<&str> = line
            .trim()
            .trim_matches('|')
            .split('|')
            .map(str::trim)
            .collect();
        let Ok(stage) = cells[0].parse::<usize>() else {
            continue;
        };
        let module = cells[1].trim_matches('`').to_string();
        let (mut said, mut depth, mut start) = (BTreeSet::new(), 0, 0);
        let list = cells[cells.len() - 1];
        for (k, ch) in list.char_indices().chain([(list.len(), ',')]) {
            match ch {
                '(' => depth += 1,
                ')' => depth -= 1,
                ',' if depth == 0 => {
                    let name: String = list[start..k]
                        .trim()
                        .trim_start_matches('`')
                        .chars()
                        .take_while(|&c| c.is_alphanumeric() || c == '_')
                        .collect();
                    if !name.is_empty() {
                        said.insert(name);
                    }
                    start = k + 1;
                }
                _ => {}
            }
        }
        rows.insert(module, (stage, said));
    }
    let mut out = Vec::new();
    for (m, real) in imports {
        let Some((stage_said, said)) = rows.get(m) else {
            out.push(format!("`{m}` has no row; it imports {real:?}"));
            continue;
        };
        if STAGES.iter().flat_map(|s| s.iter()).any(|s| s == m) && *stage_said != stage(m) {
            out.push(format!(
                "`{m}`: the table says stage {stage_said}, tests/suite/architecture.rs {}",
                stage(m)
            ));
        }
        if said != real {
            let missing: Vec<_> = real.difference(said).collect();
            let extra: Vec<_> = said.difference(real).collect();
            out.push(format!(
                "`{m}`: add {missing:?}, remove {extra:?} (it imports {real:?})"
            ));
        }
    }
    for m in rows.keys().filter(|m| !imports.contains_key(*m)) {
        out.push(format!("`{m}` has a row but no files"));
    }
    out
}

#[test]
fn stages_import_only_downward_and_without_cycles() {
    let graph = module_imports(&file_graph(&sources()));
    assert!(graph.len() >= 16, "modules found: {:?}", graph.keys());
    let mut upward = Vec::new();
    for (m, deps) in &graph {
        for d in deps {
            if stage(d) > stage(m) {
                upward.push(format!(
                    "{m} (stage {}) imports {d} (stage {})",
                    stage(m),
                    stage(d)
                ));
            }
        }
    }
    assert!(
        upward.is_empty(),
        "imports against the pipeline:\n{}",
        upward.join("\n")
    );
    let mut modules = BTreeMap::new();
    for (m, deps) in &graph {
        modules.insert(m.clone(), deps.iter().cloned().collect());
    }
    let found = cycles(&modules, &[]);
    assert!(
        found.is_empty(),
        "module import cycles:\n{}",
        found.join("\n")
    );
}

#[test]
fn no_file_takes_part_in_an_import_cycle() {
    let graph = file_graph(&sources());
    let found = cycles(&graph, CYCLE_EXCEPTIONS);
    let stale: Vec<_> = CYCLE_EXCEPTIONS
        .iter()
        .filter(|(a, b)| {
            // Needed only while the edge exists and closes a cycle.
            !graph.get(*a).is_some_and(|d| d.contains(*b)) || !reach(&graph, &[], b).contains(a)
        })
        .collect();
    assert!(
        found.is_empty() && stale.is_empty(),
        "file import cycles (paths under src/; break them by moving what both sides need into \
         a file both import):\n{}\ntemporary exceptions no longer needed (remove them from \
         CYCLE_EXCEPTIONS):\n{stale:?}",
        found.join("\n")
    );
}

#[test]
fn no_function_outside_the_tests_outgrows_100_lines() {
    let mut long = Vec::new();
    let mut used = BTreeSet::new();
    for (rel, text) in sources() {
        if rel.ends_with("/tests.rs") {
            continue;
        }
        for (name, line, lines) in functions(&without_tests(&code(&text))) {
            if lines <= MAX_FUNCTION_LINES {
                continue;
            }
            let excepted = LONG_FUNCTION_EXCEPTIONS
                .iter()
                .find(|(f, n, max)| *f == rel && *n == name && lines <= *max);
            match excepted {
                Some(e) => {
                    used.insert(*e);
                }
                None => long.push(format!("src/{rel}:{line} fn {name}: {lines} lines")),
            }
        }
    }
    let stale: Vec<_> = LONG_FUNCTION_EXCEPTIONS
        .iter()
        .filter(|e| !used.contains(*e))
        .collect();
    assert!(
        long.is_empty() && stale.is_empty(),
        "functions over {MAX_FUNCTION_LINES} lines (split them into named steps):\n{}\n\
         temporary exceptions no longer needed (remove them from LONG_FUNCTION_EXCEPTIONS):\n\
         {stale:?}",
        long.join("\n")
    );
}

#[test]
fn the_stage_table_says_what_each_module_imports() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let doc = std::fs::read_to_string(root.join("docs/ARCHITECTURE.md")).unwrap();
    let wrong = table_mismatches(&doc, &module_imports(&file_graph(&sources())));
    assert!(
        wrong.is_empty(),
        "docs/ARCHITECTURE.md's stage table (column \"imports\") against the code:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn only_the_binary_uses_anyhow_and_no_file_outgrows_800_lines() {
    let mut long = Vec::new();
    for (rel, text) in sources() {
        let lines = text.lines().count();
        if lines > 800 {
            long.push(format!("src/{rel}: {lines} lines"));
        }
        let binary = module_of(&rel).0;
        assert!(
            binary || !code(&text).contains("anyhow"),
            "src/{rel}: the library returns typed errors, not anyhow"
        );
    }
    assert!(
        long.is_empty(),
        "files over 800 lines:\n{}",
        long.join("\n")
    );
}

fn set(names: &[&str]) -> BTreeSet<String> {
    names.iter().map(|s| s.to_string()).collect()
}

#[test]
fn the_import_reader_sees_grouped_and_inline_paths() {
    let c = code(
        "use crate::{error::Result, math::{V2, dot}, self};\nlet x = crate::time::plan_steps(a);\n\
         // crate::plot in a comment\nlet s = \"crate::output in a string\";",
    );
    let refs: BTreeSet<String> = paths(&c, "crate")
        .into_iter()
        .filter_map(|(_, p)| p.first().cloned())
        .collect();
    assert_eq!(refs, set(&["error", "math", "time"]));
}

#[test]
fn the_cycle_reader_resolves_paths_to_files_and_finds_cycles() {
    let files = |a: &str, b: &str, c: &str| {
        vec![
            ("lib.rs".to_string(), "pub mod a;".to_string()),
            ("a/mod.rs".to_string(), a.to_string()),
            ("a/b.rs".to_string(), b.to_string()),
            ("a/c.rs".to_string(), c.to_string()),
        ]
    };
    // a/b → a/c → a/mod.rs → a/b, through `super::`, `crate::` and a group with `self::`.
    let g = file_graph(&files(
        "mod b; mod c; use self::{b::X, c};",
        "use super::c::Y;\n#[cfg(test)]\nmod tests { use super::*; }",
        "fn f() { crate::a::Z::new(); }",
    ));
    assert_eq!(g["a/b.rs"], set(&["a/c.rs"]));
    assert_eq!(g["a/c.rs"], set(&["a/mod.rs"]));
    assert_eq!(g["a/mod.rs"], set(&["a/b.rs", "a/c.rs"]));
    assert_eq!(cycles(&g, &[]).len(), 1, "{:?}", cycles(&g, &[]));
    assert!(cycles(&g, &[("a/c.rs", "a/mod.rs")]).is_empty());
    // Without the edge back to mod.rs there is none: `mod c;` and a `use c::…` without
    // `self::` name no path.
    let g = file_graph(&files("mod b; mod c; use c::Z;", "use super::c::Y;", ""));
    assert!(cycles(&g, &[]).is_empty(), "{:?}", cycles(&g, &[]));
}

#[test]
fn the_function_reader_measures_from_fn_to_closing_brace_outside_tests() {
    let long_body = "    let x = 1;\n".repeat(99);
    let text = format!(
        "fn short() {{\n    let s = \"}}\"; let c = '{{';\n}}\n\
         pub(crate) fn long<T: Fn(u8) -> u8>(f: T) -> [u8; 2] {{\n{long_body}}}\n\
         trait T {{ fn declared(&self); }}\n\
         #[cfg(test)]\nmod tests {{\n    fn long_test() {{\n{long_body}    }}\n}}\n"
    );
    let found = functions(&without_tests(&code(&text)));
    assert_eq!(
        found,
        vec![("short".to_string(), 1, 3), ("long".to_string(), 4, 101)]
    );
}

#[test]
fn the_table_reader_names_what_differs() {
    let doc = "| stage | module | what it holds | imports |\n|---|---|---|---|\n\
               | 0 | `error` | errors, |x| | — |\n\
               | 5 | `model` | Case at ω (|Z0|) | error, contact (`Dashpot`), scene |\n";
    let mut imports = BTreeMap::new();
    imports.insert("error".to_string(), set(&[]));
    imports.insert("model".to_string(), set(&["error", "scene", "math"]));
    let wrong = table_mismatches(doc, &imports);
    assert_eq!(wrong.len(), 1, "{wrong:?}");
    assert!(wrong[0].contains("add [\"math\"]") && wrong[0].contains("remove [\"contact\"]"));
    imports.insert("model".to_string(), set(&["error", "scene", "contact"]));
    assert!(table_mismatches(doc, &imports).is_empty());
}
