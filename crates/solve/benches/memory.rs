//! Memory per part of reading, building and verifying a model (DESIGN §10): peak heap bytes
//! measured by a counting global allocator, on `parallelogram_chain(N)` (2N + 1 parts), per
//! stage as `linkage verify` runs them (the dataset is freed once the model is built).
//!
//! `cargo bench -p linkage-solve --bench memory` prints one line per size:
//!
//! ```text
//!  loops   parts   read B/part  +build B/part  verify B/part  peak MB   time s
//! ```
//!
//! `read` is the peak while reading (text, statements, typed elements); `+build` the peak
//! while the model is built beside the dataset; `verify` the peak while verifying (model,
//! compiled system, rank analysis). The bytes per part should not grow with N; they are what
//! the 150 MB budget of the 10,000-loop chain (20,001 parts) is spent on, beside the
//! report. Time is wall-clock for the three stages.

use linkage_solve::constraints::drivers::NoDrivers;
use linkage_solve::generate::parallelogram_chain;
use linkage_solve::pipeline::verify::verify;
use linkage_solve::tolerances::Tolerances;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// The system allocator, counting the bytes live now and the most live since the last reset.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn add(bytes: usize) {
    let now = LIVE.fetch_add(bytes, Ordering::Relaxed) + bytes;
    PEAK.fetch_max(now, Ordering::Relaxed);
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        add(layout.size());
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        // SAFETY: `ptr` came from `alloc`/`realloc` above with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        add(layout.size());
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // Counted as the new block allocated before the old one is freed (the worst case).
        add(new_size);
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// Peak bytes above what was live when `f` started.
fn peak_of<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let base = LIVE.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let out = f();
    (out, PEAK.load(Ordering::Relaxed).saturating_sub(base))
}

fn main() {
    println!(" loops   parts   read B/part  +build B/part  verify B/part  peak MB   time s");
    for n in [100usize, 1000, 10_000] {
        let text = parallelogram_chain(n, 60.0);
        let parts = 2 * n + 1;
        let start = Instant::now();
        let (ds, read) = peak_of(|| {
            linkage_adm::parse_dataset(Arc::from("chain.adm"), &text)
                .expect("generated dataset reads")
        });
        let (built, build) =
            peak_of(|| linkage_model::build_model(&ds).expect("generated model builds"));
        let dataset_bytes = read;
        drop(ds);
        let model = built.model;
        let (v, check) = peak_of(|| verify(&model, &NoDrivers, &Tolerances::default()));
        let seconds = start.elapsed().as_secs_f64();
        assert_eq!(v.redundant.len(), 3 * n);
        let peak = (dataset_bytes + build).max(check + build);
        println!(
            "{n:>6} {parts:>7} {:>12} {:>14} {:>14} {:>8.1} {seconds:>8.3}",
            read / parts,
            build / parts,
            check / parts,
            peak as f64 / 1e6,
        );
    }
}
