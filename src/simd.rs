//! Runtime selection of wider vector instructions for the hot loops, without changing a
//! bit of any result.
//!
//! The release build targets baseline x86-64 (SSE2), so it runs on any x86-64 CPU. The
//! accumulations of the step ([`crate::exact::FastSum`]: a few lanes of the same IEEE
//! additions, subtractions, `abs` and `min`) vectorise better with AVX2, so the step
//! keeps a second copy of its hot gathers and of the shape functions compiled with the
//! `avx2` target feature (`step::avx2`) and calls it when the CPU has AVX2 (detected
//! once). Both copies perform the same IEEE-754 operations in the same order — Rust
//! never contracts a multiply and an add into a fused multiply-add (only an explicit
//! `mul_add` would) — so they return the same bits; `tests/threads.rs` runs a cracked
//! scene both ways and compares every bit.
//!
//! `CRAMP_SIMD=off` in the environment, or [`set_enabled`]`(false)`, forces the baseline
//! copy.

use std::sync::atomic::{AtomicU8, Ordering};

/// 0: not decided yet, 1: baseline, 2: AVX2.
static MODE: AtomicU8 = AtomicU8::new(0);

/// Is the AVX2 copy in use? Decided on first use: the CPU has AVX2 and `CRAMP_SIMD` is not `off`.
#[inline]
pub fn enabled() -> bool {
    match MODE.load(Ordering::Relaxed) {
        0 => decide(),
        m => m == 2,
    }
}

#[cold]
fn decide() -> bool {
    let on = detect() && std::env::var("CRAMP_SIMD").map(|v| v != "off").unwrap_or(true);
    MODE.store(if on { 2 } else { 1 }, Ordering::Relaxed);
    on
}

/// Use the AVX2 copies (if the CPU has AVX2) or not; for tests that compare the two.
pub fn set_enabled(on: bool) {
    MODE.store(if on && detect() { 2 } else { 1 }, Ordering::Relaxed);
}

fn detect() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}
