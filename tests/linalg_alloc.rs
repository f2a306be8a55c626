//! Repeated Cholesky solves with caller-owned scratch allocate nothing (the massless-stator
//! compliance solves them inside the time loop).

use rubsim::linalg::{Cholesky, Csc};
use std::alloc::{GlobalAlloc, Layout, System};
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

/// Allocations made by `f` on this thread.
fn allocations(f: impl FnOnce()) -> usize {
    let before = ALLOCS.load(Ordering::Relaxed);
    COUNTING.with(|c| c.set(true));
    f();
    COUNTING.with(|c| c.set(false));
    ALLOCS.load(Ordering::Relaxed) - before
}

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
