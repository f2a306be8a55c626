//! The time loop allocates nothing: the number of heap allocations of a run does not grow with
//! the number of steps (everything is allocated before the loop, the recorder up front).

use rubsim::model::Model;
use rubsim::scene;
use rubsim::time::Scheme;
use rubsim::time::{integrate, plan_steps, Initial};
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;
static ALLOCS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    // Only the test's own thread is counted (the harness and other threads allocate too).
    static COUNTING: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

fn count() {
    if COUNTING.with(|c| c.get()) {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
    }
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
    let text = include_str!("../scenes/paper/partial_rub.toml")
        .replace("[run.sweep]\nfrom = 0.5\nto = 6.0\nstep = 0.1", "");
    for (kind, extra) in [
        (Scheme::Collocated, "stator.0.density=0.0"),
        (Scheme::ForwardIncrement, "stator.0.density=0.0"),
        (Scheme::ForwardIncrement, "stator.0.density=20.0"),
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
            let ls = scene::parse(Path::new("t.toml"), &text, &ov).unwrap();
            let model = Model::from_scene(&ls).unwrap();
            let case = model.case(1.7 * model.rotor.natural_frequency()).unwrap();
            let mut st = rubsim::analysis::RunSettings::from_run(&ls.scene.run, "y").step;
            st.integrator = kind;
            let plan = plan_steps(&case, &st).unwrap();
            let before = ALLOCS.load(Ordering::Relaxed);
            COUNTING.with(|c| c.set(true));
            let (_rec, stats) = integrate(&case, kind, &plan, Initial::default()).unwrap();
            COUNTING.with(|c| c.set(false));
            let n = ALLOCS.load(Ordering::Relaxed) - before;
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
