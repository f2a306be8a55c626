//! Mutation test over every scene in `scenes/` (issue 13): every scalar value set negative,
//! zero, NaN, inf, 1e308, to the wrong type, to an empty string or array; every array emptied
//! and given a duplicate entry. Each mutant goes through the path `rubsim check` takes — load
//! (`--set`), validation, resolve, model build, the case at the first speed, the step plan and
//! its estimate — in-process, without the time loop. Asserted: no panic, no mutant over its
//! time budget (the CPU time of the thread that checks it, so a loaded machine does not fail it;
//! a mutant that blocks is caught by the wall-clock wait for the next result), and every refused
//! mutant's error names the mutated dotted key (no refusal is excused: not the step budget's,
//! not the model stage's). Slow tier (about 50 s of CPU): `scripts/test-slow.sh`.
//!
//! Meshed stators: mutants of what the mesh depends on (geometry, parameters, order, quads,
//! serendipity, size factor) are only loaded and validated, so gmsh never runs per mutant; the
//! other mutants of meshed scenes use the cached mesh (`meshes/`), made by gmsh once when
//! absent. With `RUBSIM_SKIP_GMSH` set, meshed scenes are only loaded and validated.
//!
//! Figures (scenes, mutants, accepted, refused, by kind) are printed; docs/VALIDATION.md
//! records them with the command: `cargo test --release --test suite mutation:: -- --nocapture`.

use crate::common;

use rayon::prelude::*;
use rubsim::analysis::{self, RunSettings};
use rubsim::model::Model;
use rubsim::scene;
use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Longest CPU time one mutant may take (load, model, case, plan), on the thread that checks it.
const BUDGET: Duration = Duration::from_secs(20);

/// Longest wall time without any mutant finishing: a hang (a loaded machine stretches the wall
/// time of a mutant several times over its CPU time).
const HANG: Duration = Duration::from_secs(120);

/// CPU time consumed by the calling thread so far.
fn thread_cpu() -> Duration {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec through a valid pointer.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID)");
    Duration::new(ts.tv_sec as u64, ts.tv_nsec as u32)
}

/// Keys of a meshed stator that change the mesh (a new gmsh run per mutant).
const MESH_KEYS: &[&str] = &[
    "geometry",
    "parameters",
    "order",
    "quads",
    "serendipity",
    "size_factor",
];

#[derive(Debug, Clone)]
struct Mutant {
    scene: PathBuf,
    key: String,
    value: String,
    kind: &'static str,
    /// Only load and validate (a mesh key of a meshed stator, or gmsh skipped).
    validate_only: bool,
}

#[derive(Debug)]
enum Outcome {
    Accepted,
    Refused(String),
    Panicked(String),
}

fn scenes(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            scenes(&p, out);
        } else if p.extension().is_some_and(|e| e == "toml") {
            out.push(p);
        }
    }
}

/// A value as `--set` text.
fn text(v: &toml::Value) -> String {
    v.to_string()
}

/// Every mutant of one leaf or array at `key` holding `v`.
fn mutate(key: &str, v: &toml::Value, push: &mut dyn FnMut(String, String, &'static str)) {
    use toml::Value as V;
    match v {
        V::Integer(_) | V::Float(_) => {
            let x = v
                .as_float()
                .unwrap_or_else(|| v.as_integer().unwrap() as f64);
            let neg = if x == 0.0 { -1.0 } else { -x };
            push(key.into(), format!("{neg:?}"), "negative");
            push(key.into(), "0".into(), "zero");
            push(key.into(), "nan".into(), "nan");
            push(key.into(), "inf".into(), "inf");
            push(key.into(), "1e308".into(), "huge");
            push(key.into(), "\"x\"".into(), "wrong type");
            push(key.into(), "[]".into(), "empty array");
        }
        V::String(_) => {
            push(key.into(), "\"\"".into(), "empty string");
            push(key.into(), "0".into(), "wrong type");
            push(key.into(), "[]".into(), "empty array");
        }
        V::Boolean(_) => {
            push(key.into(), "\"x\"".into(), "wrong type");
            push(key.into(), "0".into(), "wrong type");
        }
        V::Datetime(_) => {}
        V::Array(a) => {
            push(key.into(), "[]".into(), "empty array");
            if let Some(first) = a.first() {
                push(format!("{key}.{}", a.len()), text(first), "duplicate");
            }
            for (i, x) in a.iter().enumerate() {
                mutate(&format!("{key}.{i}"), x, push);
            }
        }
        V::Table(t) => {
            for (k, x) in t {
                let kk = if key.is_empty() {
                    k.clone()
                } else {
                    format!("{key}.{k}")
                };
                mutate(&kk, x, push);
            }
        }
    }
}

fn mutants(gmsh: bool) -> (usize, Vec<Mutant>) {
    let mut files = Vec::new();
    scenes(&common::repo("scenes"), &mut files);
    let mut all = Vec::new();
    for f in &files {
        let src = std::fs::read_to_string(f).unwrap();
        let value: toml::Value = toml::from_str(&src).unwrap();
        let meshed: Vec<usize> = value
            .get("stator")
            .and_then(|s| s.as_array())
            .map(|a| {
                a.iter()
                    .enumerate()
                    .filter(|(_, s)| s.get("kind").and_then(|k| k.as_str()) == Some("mesh"))
                    .map(|(i, _)| i)
                    .collect()
            })
            .unwrap_or_default();
        let mut push = |key: String, value: String, kind: &'static str| {
            let mesh_key = meshed.iter().any(|i| {
                MESH_KEYS.iter().any(|m| {
                    let p = format!("stator.{i}.{m}");
                    key == p || key.starts_with(&format!("{p}."))
                }) || key == format!("stator.{i}")
            }) || key == "stator";
            all.push(Mutant {
                scene: f.clone(),
                key,
                value,
                kind,
                validate_only: mesh_key || (!gmsh && !meshed.is_empty()),
            });
        };
        mutate("", &value, &mut push);
    }
    (files.len(), all)
}

/// The path `rubsim check` takes, without printing: load, model, case, plan, estimate.
fn check(m: &Mutant) -> Result<(), String> {
    let sets = vec![format!("{}={}", m.key, m.value)];
    let ls = scene::load(&m.scene, &sets).map_err(|e| e.to_string())?;
    if m.validate_only {
        return Ok(());
    }
    let model = Model::from_scene(&ls).map_err(|e| e.to_string())?;
    // As `rubsim check`: the settings of the whole scene (the implicit schemes' ρ∞ defaults to
    // 0 with a stator with mass).
    let settings = RunSettings::from_scene(&ls.scene);
    let speed = analysis::single_speed(&ls.scene.run, &model)
        .or_else(|| ls.scene.run.sweep.as_ref().map(|w| w.from))
        .unwrap_or(1.0);
    let prep = analysis::prepare(&model, &settings.request(speed)).map_err(|e| e.to_string())?;
    let b = rubsim::time::estimate(&prep.case, &prep.plan, settings.error_estimate);
    assert!(b.steps.is_finite() && b.wall_s.is_finite());
    Ok(())
}

/// Whether `message` names `key` or, for an entry of an array of numbers, the array.
fn names_key(message: &str, key: &str) -> bool {
    let mut k = key;
    loop {
        if message.contains(&format!("`{k}`"))
            || message.contains(&format!("`{k}."))
            || message.contains(&format!("{k}="))
        {
            return true;
        }
        match k.rsplit_once('.') {
            Some((head, last)) if last.parse::<usize>().is_ok() => k = head,
            _ => return false,
        }
    }
}

#[test]
#[ignore = "slow tier (scripts/test-slow.sh): about 50 s of CPU"]
fn every_mutant_of_every_scene_is_accepted_or_refused_naming_its_key() {
    let gmsh = std::env::var("RUBSIM_SKIP_GMSH").is_err();
    let (nscenes, list) = mutants(gmsh);
    // Mesh the meshed scenes once (cache), so no mutant pays for gmsh.
    if gmsh {
        let mut files: Vec<&PathBuf> = list.iter().map(|m| &m.scene).collect();
        files.dedup();
        for f in files {
            let ls = scene::load(f, &[]).unwrap();
            Model::from_scene(&ls).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        }
    }
    std::panic::set_hook(Box::new(|_| {}));
    let t0 = Instant::now();
    let (tx, rx) = mpsc::channel();
    let work = list.clone();
    let runner = std::thread::spawn(move || {
        work.par_iter().enumerate().for_each_with(tx, |tx, (i, m)| {
            let t = thread_cpu();
            let out = match catch_unwind(AssertUnwindSafe(|| check(m))) {
                Ok(Ok(())) => Outcome::Accepted,
                Ok(Err(e)) => Outcome::Refused(e),
                Err(p) => Outcome::Panicked(
                    p.downcast_ref::<String>()
                        .cloned()
                        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                        .unwrap_or_default(),
                ),
            };
            let _ = tx.send((i, thread_cpu().saturating_sub(t), out));
        });
    });
    let mut results = Vec::with_capacity(list.len());
    while results.len() < list.len() {
        match rx.recv_timeout(HANG) {
            Ok(r) => results.push(r),
            Err(_) => {
                let _ = std::panic::take_hook();
                panic!(
                    "no mutant finished within {HANG:?} ({} of {} done): a hang",
                    results.len(),
                    list.len()
                );
            }
        }
    }
    runner.join().unwrap();
    let _ = std::panic::take_hook();
    let wall = t0.elapsed();

    let mut by_kind: BTreeMap<&str, [usize; 3]> = BTreeMap::new();
    let mut failures = Vec::new();
    let (mut accepted, mut refused, mut slowest) = (0, 0, Duration::ZERO);
    let mut huge = Vec::new();
    for (i, dt, out) in &results {
        let m = &list[*i];
        slowest = slowest.max(*dt);
        let e = by_kind.entry(m.kind).or_default();
        let scene = m.scene.strip_prefix(common::repo("")).unwrap_or(&m.scene);
        let what = format!("{} --set {}={}", scene.display(), m.key, m.value);
        match out {
            Outcome::Accepted => {
                accepted += 1;
                e[0] += 1;
                if m.kind == "huge" {
                    huge.push(what.clone());
                }
            }
            Outcome::Refused(msg) => {
                refused += 1;
                e[1] += 1;
                if !names_key(msg, &m.key) {
                    failures.push(format!("{what}: refused without naming the key: {msg}"));
                }
            }
            Outcome::Panicked(msg) => {
                e[2] += 1;
                failures.push(format!("{what}: PANIC {msg}"));
            }
        }
        if *dt > BUDGET {
            failures.push(format!(
                "{what}: took {dt:?} of CPU, over the budget {BUDGET:?}"
            ));
        }
    }
    println!(
        "mutation test: {nscenes} scenes, {} mutants ({} only validated), {accepted} accepted, {refused} refused; {:.1} s wall, slowest mutant {:.2} s of CPU",
        list.len(),
        list.iter().filter(|m| m.validate_only).count(),
        wall.as_secs_f64(),
        slowest.as_secs_f64()
    );
    println!(
        "accepted at 1e308 (sizes and indices refused elsewhere, values legal): {}",
        huge.len()
    );
    for h in &huge {
        println!("  {h}");
    }
    println!("| kind | mutants | accepted | refused | panics |");
    println!("|---|---|---|---|---|");
    for (k, [a, r, p]) in &by_kind {
        println!("| {k} | {} | {a} | {r} | {p} |", a + r + p);
    }
    assert!(
        failures.is_empty(),
        "{} of {} mutants failed:\n{}",
        failures.len(),
        list.len(),
        failures.join("\n")
    );
}
