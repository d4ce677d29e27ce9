//! The counting global allocator of the no-allocation tests (tests/no_alloc.rs,
//! tests/three_d_no_alloc.rs; included by each with `#[path]`, since a global allocator
//! needs a test binary of its own). It wraps `std::alloc::System` and counts `alloc`,
//! `alloc_zeroed` and `realloc` calls while counting is on; with tracing on it keeps a
//! backtrace of the first counted allocations, which [`print_allocation_sites`] groups by
//! the allocating cramp function.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::Mutex;

struct Counting;

pub static COUNTING: AtomicBool = AtomicBool::new(false);
pub static CALLS: AtomicU64 = AtomicU64::new(0);
pub static TRACE: AtomicBool = AtomicBool::new(false);
static TRACED: AtomicUsize = AtomicUsize::new(0);
static TRACES: Mutex<Vec<std::backtrace::Backtrace>> = Mutex::new(Vec::new());
/// Backtraces kept in trace mode (symbolised only at the end).
const MAX_TRACES: usize = 2000;

thread_local! {
    /// Set while this thread records a backtrace, whose own allocations are not counted.
    static IN_TRACE: Cell<bool> = const { Cell::new(false) };
}

impl Counting {
    #[inline]
    fn record(&self) {
        if !COUNTING.load(Ordering::Relaxed) {
            return;
        }
        if IN_TRACE.with(|t| t.get()) {
            return;
        }
        CALLS.fetch_add(1, Ordering::Relaxed);
        if TRACE.load(Ordering::Relaxed) && TRACED.fetch_add(1, Ordering::Relaxed) < MAX_TRACES {
            IN_TRACE.with(|t| t.set(true));
            let bt = std::backtrace::Backtrace::force_capture();
            if let Ok(mut v) = TRACES.lock() {
                v.push(bt);
            }
            IN_TRACE.with(|t| t.set(false));
        }
    }
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        self.record();
        System.alloc(layout)
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        self.record();
        System.alloc_zeroed(layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        self.record();
        System.realloc(ptr, layout, new_size)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

/// Allocator calls of each of `steps` calls of `step`, counted one call at a time.
pub fn count_each<E: std::fmt::Debug>(steps: usize, mut step: impl FnMut() -> Result<(), E>) -> Vec<u64> {
    let mut counts = Vec::with_capacity(steps);
    for _ in 0..steps {
        CALLS.store(0, Ordering::SeqCst);
        COUNTING.store(true, Ordering::SeqCst);
        let r = step();
        COUNTING.store(false, Ordering::SeqCst);
        counts.push(CALLS.load(Ordering::SeqCst));
        r.unwrap();
    }
    counts
}

/// Turn tracing on when `CRAMP_ALLOC_TRACE` is set.
pub fn trace_if_requested() {
    TRACE.store(std::env::var_os("CRAMP_ALLOC_TRACE").is_some(), Ordering::SeqCst);
}

/// Trace mode: the counted allocations grouped by the innermost cramp function (outside
/// `cramp::exact`) on their stack, with one full backtrace per group.
pub fn print_allocation_sites() {
    let traces = std::mem::take(&mut *TRACES.lock().unwrap());
    if traces.is_empty() {
        return;
    }
    let mut groups: Vec<(String, usize, String)> = Vec::new();
    for bt in &traces {
        let text = bt.to_string();
        let lines: Vec<&str> = text.lines().collect();
        let mut site = String::from("(no cramp frame)");
        for (k, l) in lines.iter().enumerate() {
            // Frames read "  N: function", followed by "at file:line".
            let Some((n, f)) = l.trim_start().split_once(": ") else { continue };
            if n.chars().all(|c| c.is_ascii_digit()) && f.contains("cramp::") && !f.contains("cramp::exact") {
                let at = lines.get(k + 1).map(|a| a.trim()).unwrap_or("");
                site = format!("{f}  {at}");
                break;
            }
        }
        match groups.iter_mut().find(|g| g.0 == site) {
            Some(g) => g.1 += 1,
            None => groups.push((site, 1, text)),
        }
    }
    eprintln!("allocation sites of the first {} counted allocations:", traces.len());
    for (site, n, _) in &groups {
        eprintln!("{n:6}  {site}");
    }
    for (site, _, text) in &groups {
        eprintln!("\n--- {site}\n{text}");
    }
}
