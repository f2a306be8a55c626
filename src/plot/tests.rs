//! Figure tests: every kind of figure is written as a PNG for ordinary, empty, degenerate and
//! non-finite input, to exactly the path given, and a missing directory is an output error.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use super::*;
use crate::error::Error;

/// A fresh, unique output directory under the system temp dir.
fn out_dir(tag: &str) -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "rubsim-plot-test-{}-{}-{tag}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir).expect("create test dir");
    dir
}

fn assert_png(path: &Path) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(
        bytes.len() > 1024,
        "{}: only {} bytes",
        path.display(),
        bytes.len()
    );
    assert_eq!(
        &bytes[..8],
        b"\x89PNG\r\n\x1a\n",
        "{}: not a PNG",
        path.display()
    );
}

/// Writes synthetic figures of every kind into `dir`; returns the files.
fn write_all(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    write_orbits(dir, &mut files);
    write_cascades(dir, &mut files);
    write_bifurcations(dir, &mut files);
    write_stacked(dir, &mut files);
    write_loglogs(dir, &mut files);
    write_lines(dir, &mut files);
    files
}

/// Orbit grids (and an empty one) into `dir`, their paths appended to `files`.
fn write_orbits(dir: &Path, files: &mut Vec<PathBuf>) {
    let tau = std::f64::consts::TAU;
    // Orbit grid: free orbit, rod contact, ring with NaN gap, tiny/degenerate, empty.
    let n = 2000;
    let t: Vec<f64> = (0..n).map(|k| 20.0 * tau * k as f64 / n as f64).collect();
    let circle = |r: f64, cx: f64, cy: f64| -> (Vec<f64>, Vec<f64>) {
        (
            t.iter().map(|s| cx + r * s.cos()).collect(),
            t.iter().map(|s| cy + r * s.sin()).collect(),
        )
    };
    let (x1, y1) = circle(0.6, 0.0, 0.0);
    let (x2, mut y2) = circle(0.9, 0.0, 0.2);
    for y in &mut y2 {
        *y = y.min(1.0);
    }
    let (mut x3, y3) = (
        t.iter()
            .map(|s| 0.7 * s.cos() + 0.2 * (s / 2.0).cos())
            .collect::<Vec<_>>(),
        t.iter()
            .map(|s| 0.7 * s.sin() + 0.2 * (s / 2.0).sin())
            .collect::<Vec<_>>(),
    );
    for v in x3.iter_mut().skip(500).take(50) {
        *v = f64::NAN;
    }
    let panels = vec![
        OrbitPanel {
            title: "ω/ωn = 0.50".into(),
            x: x1,
            y: y1,
            boundary: Boundary::Line {
                angle_deg: 90.0,
                distance: 1.0,
            },
            poincare: vec![(0.6, 0.0)],
        },
        OrbitPanel {
            title: "ω/ωn = 1.20 (rub)".into(),
            x: x2,
            y: y2,
            boundary: Boundary::Line {
                angle_deg: 90.0,
                distance: 1.0,
            },
            poincare: vec![(0.9, 0.2), (-0.3, 0.9)],
        },
        OrbitPanel {
            title: "ring, 1/2× whirl".into(),
            x: x3,
            y: y3,
            boundary: Boundary::Circle { radius: 1.0 },
            poincare: vec![(0.9, 0.0), (0.5, 0.0)],
        },
        OrbitPanel {
            title: "oblique rod, single point".into(),
            x: vec![0.3],
            y: vec![0.2],
            boundary: Boundary::Line {
                angle_deg: 45.0,
                distance: 0.5,
            },
            poincare: vec![],
        },
        OrbitPanel {
            title: "empty".into(),
            x: vec![],
            y: vec![],
            boundary: Boundary::None,
            poincare: vec![],
        },
    ];
    let p = dir.join("orbits.png");
    orbit_grid(&p, "Orbits (synthetic), rod stator", &panels, 3).expect("orbit grid");
    files.push(p);
    let p = dir.join("orbits_empty.png");
    orbit_grid(&p, "No orbits", &[], 3).expect("orbit grid empty");
    files.push(p);
}

/// Cascades (and an empty one) into `dir`, their paths appended to `files`.
fn write_cascades(dir: &Path, files: &mut Vec<PathBuf>) {
    // Cascade.
    let nf = 400;
    let fmax = 3.0;
    let spectra: Vec<CascadeLine> = (0..30)
        .map(|k| {
            let speed = 0.2 + 0.1 * k as f64;
            let freq: Vec<f64> = (0..nf).map(|i| fmax * i as f64 / nf as f64).collect();
            let peak = |f: f64, f0: f64, a: f64| a * (-((f - f0) / 0.02).powi(2)).exp();
            let amp = freq
                .iter()
                .map(|&f| {
                    peak(f, speed, 1.0)
                        + if speed > 2.0 {
                            peak(f, speed / 2.0, 1.5)
                        } else {
                            0.0
                        }
                        + peak(f, 1.0, 0.3)
                        + 0.01
                })
                .collect();
            CascadeLine { speed, freq, amp }
        })
        .collect();
    let p = dir.join("cascade.png");
    cascade(&p, "Spectrum cascade |Y| (synthetic)", &spectra, fmax, 0.8).expect("cascade");
    files.push(p);
    let p = dir.join("cascade_empty.png");
    cascade(&p, "Empty cascade", &[], 2.0, 0.8).expect("cascade empty");
    files.push(p);
}

/// Bifurcation diagrams into `dir`, their paths appended to `files`.
fn write_bifurcations(dir: &Path, files: &mut Vec<PathBuf>) {
    // Bifurcation diagram: logistic-map-like cloud + NaN.
    let mut pts = Vec::new();
    for k in 0..400 {
        let s = 0.5 + 2.5 * k as f64 / 400.0;
        let r = 2.8 + 1.2 * (s - 0.5) / 2.5;
        let mut x: f64 = 0.3;
        for i in 0..300 {
            x = r * x * (1.0 - x);
            if i >= 200 {
                pts.push((s, x));
            }
        }
    }
    pts.push((f64::NAN, 0.5));
    let p = dir.join("bifurcation.png");
    bifurcation(
        &p,
        "Bifurcation diagram (synthetic)",
        &pts,
        "y/|Z0| at t = k·2π/ω",
    )
    .expect("bifurcation");
    files.push(p);
    let p = dir.join("bifurcation_single.png");
    bifurcation(&p, "Single point", &[(1.0, 0.0)], "y").expect("bifurcation single");
    files.push(p);
}

/// Stacked series into `dir`, their paths appended to `files`.
fn write_stacked(dir: &Path, files: &mut Vec<PathBuf>) {
    let tau = std::f64::consts::TAU;
    // Stacked series.
    let ts: Vec<f64> = (0..3000).map(|k| k as f64 * 1e-4).collect();
    let f1: Vec<f64> = ts
        .iter()
        .map(|t| ((tau * 50.0 * t).sin() * 1200.0).max(0.0))
        .collect();
    let mut f2: Vec<f64> = ts
        .iter()
        .map(|t| ((tau * 25.0 * t).sin() * 3.0e-4).max(0.0))
        .collect();
    f2[1000] = f64::NAN;
    let series = vec![
        Series {
            label: "contact force, node 3".into(),
            t: ts.clone(),
            y: f1,
        },
        Series {
            label: "contact force, node 4".into(),
            t: ts.clone(),
            y: f2,
        },
        Series {
            label: "zero".into(),
            t: ts.clone(),
            y: vec![0.0; ts.len()],
        },
        Series {
            label: "empty".into(),
            t: vec![],
            y: vec![],
        },
    ];
    let p = dir.join("stacked.png");
    stacked_series(&p, "Contact forces (synthetic)", &series, "t (s)", "F (N)").expect("stacked");
    files.push(p);
}

/// Log–log plots into `dir`, their paths appended to `files`.
fn write_loglogs(dir: &Path, files: &mut Vec<PathBuf>) {
    // Log–log.
    let curves: Vec<Curve> = (0..7)
        .map(|k| Curve {
            label: format!("method {k} (order {})", k % 3 + 1),
            points: (0..8)
                .map(|i| {
                    let dt = 1e-3 / 2f64.powi(i);
                    (
                        dt,
                        (k as f64 + 1.0) * dt.powi(k % 3 + 1) * 10f64.powi(k % 3),
                    )
                })
                .chain([(0.0, 1.0), (f64::NAN, 1.0)])
                .collect(),
        })
        .collect();
    let p = dir.join("loglog.png");
    loglog(
        &p,
        "Error vs Δt (synthetic)",
        &curves,
        "Δt (s)",
        "relative error",
    )
    .expect("loglog");
    files.push(p);
    let p = dir.join("loglog_single.png");
    loglog(
        &p,
        "Single point",
        &[Curve {
            label: "one".into(),
            points: vec![(2.0, 3.0)],
        }],
        "x",
        "y",
    )
    .expect("loglog single");
    files.push(p);
}

/// Line plots into `dir`, their paths appended to `files`.
fn write_lines(dir: &Path, files: &mut Vec<PathBuf>) {
    let tau = std::f64::consts::TAU;
    // Lines.
    let xs: Vec<f64> = (0..500).map(|i| i as f64 * 0.01).collect();
    let curves = vec![
        Curve {
            label: "sin".into(),
            points: xs.iter().map(|&x| (x, (tau * x).sin())).collect(),
        },
        Curve {
            label: "cos with NaN gap".into(),
            points: xs
                .iter()
                .map(|&x| {
                    (
                        x,
                        if (2.0..2.5).contains(&x) {
                            f64::NAN
                        } else {
                            (tau * x).cos() * 0.5
                        },
                    )
                })
                .collect(),
        },
        Curve {
            label: "single point".into(),
            points: vec![(2.5, 0.8)],
        },
    ];
    let p = dir.join("lines.png");
    lines(&p, "Lines (synthetic)", &curves, "f/ωn", "amplitude").expect("lines");
    files.push(p);
    let p = dir.join("lines_flat.png");
    lines(
        &p,
        "Flat",
        &[Curve {
            label: String::new(),
            points: vec![(1.0, 5.0), (1.0, 5.0)],
        }],
        "x",
        "y",
    )
    .expect("lines flat");
    files.push(p);
}

#[test]
fn every_kind_writes_a_png() {
    let dir = out_dir("all");
    for f in write_all(&dir) {
        assert_png(&f);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn empty_inputs_write_pngs() {
    let dir = out_dir("empty");
    let p = dir.join("a.png");
    stacked_series(&p, "", &[], "t", "y").expect("stacked empty");
    assert_png(&p);
    loglog(&p, "t", &[], "x", "y").expect("loglog empty");
    assert_png(&p);
    lines(&p, "t", &[], "x", "y").expect("lines empty");
    assert_png(&p);
    bifurcation(&p, "t", &[], "y").expect("bifurcation empty");
    assert_png(&p);
    let all_nan = Curve {
        label: "nan".into(),
        points: vec![(f64::NAN, f64::NAN), (-1.0, 0.0)],
    };
    loglog(&p, "t", std::slice::from_ref(&all_nan), "x", "y").expect("loglog nan");
    assert_png(&p);
    lines(&p, "t", &[all_nan], "x", "y").expect("lines nan");
    assert_png(&p);
    let one = CascadeLine {
        speed: 1.0,
        freq: vec![0.0, 0.5, 1.0, f64::NAN],
        amp: vec![0.0, 0.0, 1.0, 2.0],
    };
    cascade(&p, "t", &[one], f64::NAN, f64::NAN).expect("cascade single");
    assert_png(&p);
    orbit_grid(
        &p,
        "t",
        &[OrbitPanel {
            title: String::new(),
            x: vec![f64::NAN; 3],
            y: vec![1.0; 3],
            boundary: Boundary::Circle { radius: -1.0 },
            poincare: vec![(f64::INFINITY, 0.0)],
        }],
        0,
    )
    .expect("orbit nan");
    assert_png(&p);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn non_png_extension_is_written_exactly() {
    let dir = out_dir("tmpname");
    let p = dir.join("figure.png.tmp");
    bifurcation(&p, "tmp", &[(1.0, 2.0), (2.0, 3.0)], "y").expect("bifurcation");
    assert_png(&p);
    let names: Vec<_> = std::fs::read_dir(&dir)
        .expect("read dir")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("figure.png.tmp")]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn missing_directory_is_an_output_error() {
    let dir = out_dir("missing");
    let p = dir.join("no/such/dir/x.png");
    let err = lines(&p, "t", &[], "x", "y").expect_err("must fail");
    assert!(matches!(err, Error::Output { .. }), "{err}");
    assert!(!p.exists());
    let _ = std::fs::remove_dir_all(&dir);
}
