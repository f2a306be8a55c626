//! The house keeps its shape: every library module imports only modules of its own stage or
//! below (the one-way pipeline of `src/lib.rs` and `docs/ARCHITECTURE.md`), the module graph
//! has no cycle, the binary's `src/cli/` is the only user of `anyhow`, and no source file
//! outgrows 800 lines.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The stages, lowest first: a module may import modules of its own stage or of a lower one.
const STAGES: &[&[&str]] = &[
    &["error", "math", "fslock"],
    &["linalg", "signal", "mesh", "element", "assembly", "plot"],
    &["contact"],
    &["scene"],
    &["resolve"],
    &["model"],
    &["linear"],
    &["time"],
    &["analysis"],
    &["output", "results"],
];

fn stage(module: &str) -> usize {
    STAGES
        .iter()
        .position(|s| s.contains(&module))
        .unwrap_or_else(|| panic!("module `{module}` is in no stage of tests/architecture.rs"))
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

/// The code of a file without its comments (line comments and doc comments).
fn code(text: &str) -> String {
    text.lines()
        .map(|l| {
            let t = l.trim_start();
            if t.starts_with("//") {
                ""
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The top-level modules a piece of code names through `crate::`: `crate::a::…` and the
/// members of `use crate::{a::…, b, …}`.
fn crate_refs(code: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut rest = code;
    while let Some(i) = rest.find("crate::") {
        rest = &rest[i + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            // The members of a grouped import, at brace depth 1.
            let (mut depth, mut start) = (1, 0);
            for (k, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' | ',' if depth == 1 => {
                        let name: String = group[start..k]
                            .trim()
                            .chars()
                            .take_while(|c| c.is_alphanumeric() || *c == '_')
                            .collect();
                        if !name.is_empty() && name != "self" {
                            out.insert(name);
                        }
                        start = k + 1;
                        if c == '}' {
                            break;
                        }
                    }
                    '}' => depth -= 1,
                    _ => {}
                }
            }
        } else {
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                out.insert(name);
            }
        }
    }
    out
}

/// Library module → the library modules its files import.
fn library_imports() -> BTreeMap<String, BTreeSet<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for f in files {
        let rel = f.strip_prefix(&src).unwrap();
        let first = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy();
        let module = first.trim_end_matches(".rs").to_string();
        if module == "cli" || module == "main" || module == "lib" {
            continue;
        }
        let refs = crate_refs(&code(&std::fs::read_to_string(&f).unwrap()));
        let entry = graph.entry(module.clone()).or_default();
        entry.extend(refs.into_iter().filter(|r| *r != module));
    }
    graph
}

#[test]
fn stages_import_only_downward_and_without_cycles() {
    let graph = library_imports();
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
    // No cycle between modules (of the same stage): depth-first search for a back edge.
    fn visit<'a>(
        m: &'a str,
        graph: &'a BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<&'a str, u8>,
        path: &mut Vec<&'a str>,
    ) {
        state.insert(m, 1);
        path.push(m);
        for d in graph.get(m).into_iter().flatten() {
            match state.get(d.as_str()) {
                Some(1) => panic!("import cycle: {} → {d}", path.join(" → ")),
                Some(_) => {}
                None => visit(d, graph, state, path),
            }
        }
        path.pop();
        state.insert(m, 2);
    }
    let mut state = BTreeMap::new();
    for m in graph.keys() {
        if !state.contains_key(m.as_str()) {
            visit(m, &graph, &mut state, &mut Vec::new());
        }
    }
}

#[test]
fn only_the_binary_uses_anyhow_and_no_file_outgrows_800_lines() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    let mut long = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        let rel = f.strip_prefix(root).unwrap().display().to_string();
        let lines = text.lines().count();
        if lines > 800 {
            long.push(format!("{rel}: {lines} lines"));
        }
        let binary = rel.starts_with("src/cli/") || rel == "src/main.rs";
        assert!(
            binary || !code(&text).contains("anyhow"),
            "{rel}: the library returns typed errors, not anyhow"
        );
    }
    assert!(
        long.is_empty(),
        "files over 800 lines:\n{}",
        long.join("\n")
    );
}

#[test]
fn the_import_reader_sees_grouped_and_inline_paths() {
    let refs = crate_refs(
        "use crate::{error::Result, math::{V2, dot}, self};\nlet x = crate::time::plan_steps(a);",
    );
    let want: BTreeSet<String> = ["error", "math", "time"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    assert_eq!(refs, want);
}
