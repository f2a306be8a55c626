//! The time loop allocates nothing: the number of heap allocations of a run does not grow with
//! the number of steps (everything is allocated before the loop, the recorder up front), and
//! once a meshed stator's touched nodes are known a step allocates nothing at all — for the
//! Jeffcott and FE rotors, massless and massive stators, with and without a frame sink.

mod common;

use common::scenes::paper_single;
use common::{case_and_plan, file_model, repo, scene_model, settings};
use rubsim::linalg::{Cholesky, Csc};
use rubsim::time::Scheme;
use rubsim::time::{integrate, Initial};
use std::alloc::{GlobalAlloc, Layout, System};

struct Counting;

thread_local! {
    // Only the test's own thread is counted, in its own counter (the harness and the other
    // tests, which run in parallel, allocate too).
    static COUNTING: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
    static ALLOCS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

fn count() {
    if COUNTING.with(|c| c.get()) {
        ALLOCS.with(|a| a.set(a.get() + 1));
    }
}

/// Allocations counted on this thread so far.
fn allocs() -> usize {
    ALLOCS.with(|a| a.get())
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { System.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(p, l, n) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn allocations_do_not_grow_with_steps() {
    let text = paper_single();
    for (kind, extra) in [
        (Scheme::Collocated, "stator.0.density=0.0"),
        (Scheme::ForwardIncrement, "stator.0.density=0.0"),
        (Scheme::ForwardIncrement, "stator.0.density=20.0"),
        (Scheme::Newmark, "stator.0.density=0.0"),
        (
            Scheme::GeneralizedAlpha { rho_inf: 0.0 },
            "stator.0.density=20.0",
        ),
    ] {
        let mut counts = Vec::new();
        for revs in [20usize, 80] {
            let ov = vec![
                "run.speed_ratio=1.7".to_string(),
                format!("run.revolutions={revs}"),
                "run.transient_revolutions=10".to_string(),
                "stator.0.elements=3".to_string(),
                extra.to_string(),
            ];
            let (ls, model) = scene_model(&text, &ov);
            let (case, plan) = case_and_plan(&ls, &model, 1.7, kind);
            let before = allocs();
            COUNTING.with(|c| c.set(true));
            let (_rec, stats) = integrate(&case, kind, &plan, Initial::default()).unwrap();
            COUNTING.with(|c| c.set(false));
            let n = allocs() - before;
            assert!(stats.contact_steps > 0);
            counts.push((plan.steps, n));
        }
        assert_eq!(
            counts[0].1, counts[1].1,
            "{kind:?} {extra}: allocations {} for {} steps vs {} for {} steps",
            counts[0].1, counts[0].0, counts[1].1, counts[1].0
        );
    }
}

/// A sink that reads every frame (rotor DOFs, each stator's displacement field, the pairs)
/// without keeping anything, so any allocation counted is the loop's.
struct ReadingSink {
    every: usize,
    stators: usize,
    checksum: f64,
    frames: usize,
}

impl rubsim::time::FrameSink for ReadingSink {
    fn every(&self) -> usize {
        self.every
    }
    fn frame(&mut self, f: &rubsim::time::Frame<'_>) -> rubsim::error::Result<()> {
        self.checksum += f.rotor_u.iter().sum::<f64>();
        for k in 0..self.stators {
            self.checksum += f.stator_u(k).iter().sum::<f64>();
        }
        self.checksum += f.pairs.iter().map(|p| p.p).sum::<f64>();
        self.frames += 1;
        Ok(())
    }
}

/// One case of [`steps_after_warm_up_allocate_nothing`].
struct WarmCase {
    scene: &'static str,
    speed: f64,
    warm_revs: usize,
    count_revs: usize,
    /// Frame interval of a [`ReadingSink`] (0: no sink).
    every: usize,
    /// An extra `--set` (empty: none), e.g. the integrator.
    extra: &'static str,
}

/// Allocations made by the steps of `c.count_revs` revolutions after `c.warm_revs`, the
/// steps counted and the frames read meanwhile.
fn allocations_after_warm_up(c: &WarmCase) -> (usize, usize, usize) {
    let ov = vec![
        format!("run.revolutions={}", c.warm_revs + c.count_revs + 1),
        "run.transient_revolutions=1".to_string(),
        "run.error_estimate=false".to_string(),
    ]
    .into_iter()
    .chain((!c.extra.is_empty()).then(|| c.extra.to_string()))
    .collect::<Vec<_>>();
    let (ls, model) = file_model(&repo(c.scene), &ov);
    let scheme = settings(&ls).step.integrator;
    let (case, plan) = case_and_plan(&ls, &model, c.speed, scheme);
    let mut stepper = rubsim::time::Stepper::new(&case, scheme, &plan, Initial::default()).unwrap();
    let mut sink = ReadingSink {
        every: c.every,
        stators: case.stators.len(),
        checksum: 0.0,
        frames: 0,
    };
    let mut run_steps = |sink: &mut ReadingSink, steps: usize| {
        let mut s: rubsim::time::Sink<'_> = if c.every > 0 { Some(sink) } else { None };
        for _ in 0..steps {
            assert!(stepper.step(&mut s).unwrap());
        }
    };
    run_steps(&mut sink, c.warm_revs * plan.steps_per_rev);
    let frames_before = sink.frames;
    let steps = c.count_revs * plan.steps_per_rev;
    let before = allocs();
    COUNTING.with(|c| c.set(true));
    run_steps(&mut sink, steps);
    COUNTING.with(|c| c.set(false));
    (allocs() - before, steps, sink.frames - frames_before)
}

/// Once the touched contact nodes of a meshed stator are known (its compliance columns are
/// computed the first time a node touches), a step allocates nothing — for an FE rotor (sparse
/// or block LU of M̃; reduced), a meshed massless stator, and with a frame sink reading every
/// frame (which rebuilds the massless stators' whole displacement field and expands a reduced
/// rotor's u = T q).
#[test]
fn steps_after_warm_up_allocate_nothing() {
    let fe = "scenes/fe/paper_rotor_rub.toml";
    let annulus = "scenes/stators/annulus.toml";
    let implicit = "run.integrator=\"generalized_alpha\"";
    // The reduced rotor (`[run.reduction]`): dense r × r operators; a frame expands u = T q.
    let reduced = "run.reduction={}";
    let cases = [
        (fe, 1.7, 40, 10, 0, ""),
        (fe, 1.7, 40, 10, 7, ""),
        (fe, 1.7, 40, 10, 7, implicit),
        (fe, 1.7, 40, 10, 7, reduced),
        (fe, 1.7, 40, 10, 0, reduced),
        (annulus, 1.2, 30, 3, 0, ""),
        (annulus, 1.2, 30, 3, 97, ""),
        (annulus, 1.2, 30, 3, 0, implicit),
    ];
    for (scene, speed, warm_revs, count_revs, every, extra) in cases {
        let c = WarmCase {
            scene,
            speed,
            warm_revs,
            count_revs,
            every,
            extra,
        };
        let (n, steps, frames) = allocations_after_warm_up(&c);
        assert!(every == 0 || frames > 0, "{scene}: no frame read");
        assert_eq!(
            n, 0,
            "{scene} {extra} with a sink every {every} steps: {n} allocations in {steps} steps after warm-up ({frames} frames)"
        );
    }
}

/// A ring in contact takes a second complementarity solve per step with its normal re-aligned
/// (exact ring kinematics, docs/VALIDATION.md §15.1): still nothing allocated, massless and with
/// mass, both explicit schemes.
#[test]
fn ring_contact_steps_allocate_nothing() {
    let massless = "tests/data/scenes/ring_full_rub.toml";
    let with_mass = "tests/data/scenes/ring.toml";
    let fi = "run.integrator=\"forward_increment\"";
    for (scene, speed, extra) in [
        (massless, 2.0, ""),
        (massless, 2.0, fi),
        (with_mass, 1.7, ""),
    ] {
        let c = WarmCase {
            scene,
            speed,
            warm_revs: 20,
            count_revs: 5,
            every: 0,
            extra,
        };
        let (n, steps, _) = allocations_after_warm_up(&c);
        assert_eq!(n, 0, "{scene} {extra}: {n} allocations in {steps} steps");
    }
}

/// Allocations made on this thread by `f`.
fn allocations(f: impl FnOnce()) -> usize {
    let before = allocs();
    COUNTING.with(|c| c.set(true));
    f();
    COUNTING.with(|c| c.set(false));
    allocs() - before
}

/// Repeated Cholesky solves with caller-owned scratch allocate nothing (the massless-stator
/// compliance solves them inside the time loop), where the one-off solve does.
#[test]
fn cholesky_solves_with_scratch_do_not_allocate() {
    // A 2-D grid Laplacian plus identity: symmetric positive definite with fill-in.
    let (w, h) = (12, 10);
    let n = w * h;
    let mut t = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let p = j * w + i;
            t.push((p, p, 5.0));
            if i + 1 < w {
                t.extend([(p, p + 1, -1.0), (p + 1, p, -1.0)]);
            }
            if j + 1 < h {
                t.extend([(p, p + w, -1.0), (p + w, p, -1.0)]);
            }
        }
    }
    let ch = Cholesky::new(&Csc::from_triplets(n, n, &t)).unwrap();
    let mut scratch = ch.solve_scratch(4);
    let mut b: Vec<f64> = (0..4 * n).map(|i| (i as f64 * 0.7).sin()).collect();
    let mut one: Vec<f64> = b[..n].to_vec();
    let a = allocations(|| {
        for _ in 0..50 {
            ch.solve_in_place_with(&mut b, &mut scratch);
            ch.solve_in_place_with(&mut one, &mut scratch);
        }
    });
    assert_eq!(a, 0, "{a} allocations in 100 solves");
    // The one-off solve does allocate (its scratch): the counter sees faer's buffers.
    assert!(allocations(|| ch.solve_in_place(&mut one)) > 0);
}

#[test]
fn a_speed_profile_allocates_nothing_per_step() {
    // The paper's case on a run-up with rub: the profile's Ω, Ω̇, φ are evaluated every step.
    let text = paper_single();
    let mut counts = Vec::new();
    for duration in [0.2, 0.8] {
        let (ls, model) = scene_model(&text, &["run.speed_ratio=1.0"]);
        let s = settings(&ls);
        let case = model.case(model.rotor.natural_frequency()).unwrap();
        let wn = model.rotor.natural_frequency();
        let profile = rubsim::model::SpeedProfile::ramp(0.8 * wn, 2.0 * wn, duration, 0.0).unwrap();
        let plan = rubsim::time::plan_duration(&case, &s.step, 2.0 * wn, duration).unwrap();
        let stepper = rubsim::time::Stepper::with_profile(
            &case,
            Scheme::Collocated,
            &plan,
            Initial::default(),
            Some(&profile),
        )
        .unwrap();
        let before = allocs();
        COUNTING.with(|c| c.set(true));
        let (_rec, stats) = stepper.run(None).unwrap();
        COUNTING.with(|c| c.set(false));
        assert!(stats.contact_steps > 0, "the run-up must rub");
        counts.push((plan.steps, allocs() - before));
    }
    assert!(counts[1].0 > 3 * counts[0].0);
    assert_eq!(
        counts[0].1, counts[1].1,
        "allocations grow with steps: {counts:?}"
    );
}
