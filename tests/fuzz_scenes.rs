//! A seeded, deterministic fuzz test of the scene parser, validator and builder
//! (issue 19): thousands of mutations of the verification scenes (verification/*.toml)
//! — numbers replaced by extreme, non-finite, negative or scaled values, lines deleted,
//! duplicated or swapped, keywords replaced, text cut short — each parsed and built.
//!
//! Asserted for every mutation: no panic (a bad scene is an error; an accepted one also
//! takes two time steps), no hang (each parse + build + steps finishes within a bound, and the whole loop runs in a worker thread watched by a
//! deadline), and no unbounded allocation: with `CRAMP_MEMORY_LIMIT` at 64 MB, the live
//! heap during a build (counted by a global allocator) stays within 3× that limit — the
//! memory estimate refuses anything bigger before allocating it. The allocator refuses
//! any single request above 1 GB outright, so a regression aborts the test instead of the
//! machine. Reference: the contract of src/scene.rs; no tolerance.
//!
//! To reproduce a failure, the message gives the mutation's index and text;
//! `CRAMP_FUZZ_CASES=N` changes the number of mutations (default 5000) and
//! `CRAMP_FUZZ_SEED=S` the generator's seed, to search further.

use cramp::scene::Scene;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{mpsc, Arc, Mutex};
use std::time::{Duration, Instant};

struct Capped;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);
/// Largest single allocation allowed (a request above it fails, which aborts the test).
const MAX_REQUEST: usize = 1 << 30;

unsafe impl GlobalAlloc for Capped {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if layout.size() > MAX_REQUEST {
            return std::ptr::null_mut();
        }
        let p = System.alloc(layout);
        if !p.is_null() {
            PEAK.fetch_max(LIVE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size(), Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout);
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if new_size > MAX_REQUEST {
            return std::ptr::null_mut();
        }
        let p = System.realloc(ptr, layout, new_size);
        if !p.is_null() {
            PEAK.fetch_max(LIVE.fetch_add(new_size, Ordering::Relaxed) + new_size, Ordering::Relaxed);
            LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        }
        p
    }
}

#[global_allocator]
static GLOBAL: Capped = Capped;

/// The memory limit the builder is given (bytes).
const LIMIT: f64 = 64e6;

/// SplitMix64: a small deterministic generator.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn pick<'a, T>(&mut self, xs: &'a [T]) -> &'a T {
        &xs[self.below(xs.len())]
    }
}

const NUMBERS: &[&str] = &[
    "0",
    "0.0",
    "-0.0",
    "-1",
    "1",
    "2",
    "1e-300",
    "5e-324",
    "-5e-324",
    "1e300",
    "-1e300",
    "1.7976931348623157e308",
    "nan",
    "inf",
    "-inf",
    "1e7",
    "1e8",
    "10000",
    "100000",
    "0.5",
    "3",
    "8",
    "9",
    "65536",
    "4294967296",
    "18446744073709551615",
    "-9223372036854775808",
    "1e-9",
];
const WORDS: &[&str] = &[
    "\"usl\"",
    "\"musl\"",
    "\"usf\"",
    "\"usavg\"",
    "\"linear\"",
    "\"ugimp\"",
    "\"plane_stress\"",
    "\"plane_strain\"",
    "\"none\"",
    "\"stick\"",
    "\"frictionless\"",
    "\"start\"",
    "\"end\"",
    "\"both\"",
    "\"grid\"",
    "\"particles\"",
    "\"visibility\"",
    "\"velocity_fields\"",
    "\"\"",
    "true",
    "false",
    "[]",
    "[0.0]",
    "[0.0, 0.0, 0.0]",
    "{}",
];
const LINES: &[&str] = &[
    "max_steps = 1",
    "damping = 1e300",
    "dt = 1e-300",
    "history_interval = 1e-300",
    "archive_interval = 1e-300",
    "velocity = [nan, 0.0]",
    "[[cracks]]\npoints = [[0.0, 0.0], [inf, 1.0]]",
    "[[cracks]]\npoints = [[1.0, 1.0], [1.0, 1.0]]",
    "[[bodies]]\nmaterial = \"x\"\nshape = { disk = { center = [nan, 0.0], radius = 1.0 } }",
    "[output]\nhistory_interval = 5e-324",
    "particles_per_cell = 8",
    "cell = [1e-6, 1e-6]",
    "size = [1e7, 1e7]",
];

/// Byte offsets of the number tokens of a text.
fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts = b[i].is_ascii_digit() || (b[i] == b'-' && i + 1 < b.len() && b[i + 1].is_ascii_digit());
        let in_word = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_' || b[i - 1] == b'.');
        if starts && !in_word {
            let mut j = i + 1;
            while j < b.len() && (b[j].is_ascii_digit() || matches!(b[j], b'.' | b'e' | b'E' | b'-' | b'+' | b'_')) {
                j += 1;
            }
            spans.push((i, j));
            i = j;
        } else {
            i += 1;
        }
    }
    spans
}

/// One random mutation of `text`.
fn mutate(text: &str, rng: &mut Rng) -> String {
    let lines: Vec<&str> = text.lines().collect();
    if lines.is_empty() {
        return rng.pick(LINES).to_string();
    }
    match rng.below(10) {
        0..=3 => {
            let spans = number_spans(text);
            if spans.is_empty() {
                return text.to_string();
            }
            let (a, b) = *rng.pick(&spans);
            let old: f64 = text[a..b].replace('_', "").parse().unwrap_or(1.0);
            let new = match rng.below(3) {
                0 => rng.pick(NUMBERS).to_string(),
                1 => format!("{:?}", old * 10f64.powi(rng.below(25) as i32 - 12)),
                _ => format!("{:?}", -old),
            };
            format!("{}{new}{}", &text[..a], &text[b..])
        }
        4 => {
            // A quoted word or boolean replaced.
            let quoted: Vec<usize> = text.match_indices('"').map(|(i, _)| i).collect();
            if quoted.len() < 2 {
                return text.to_string();
            }
            let k = rng.below(quoted.len() / 2) * 2;
            format!("{}{}{}", &text[..quoted[k]], rng.pick(WORDS), &text[quoted[k + 1] + 1..])
        }
        5 => {
            let k = rng.below(lines.len());
            lines.iter().enumerate().filter(|&(i, _)| i != k).map(|(_, l)| *l).collect::<Vec<_>>().join("\n")
        }
        6 => {
            let k = rng.below(lines.len());
            let mut v = lines.clone();
            v.insert(k, lines[k]);
            v.join("\n")
        }
        7 => {
            let (i, j) = (rng.below(lines.len()), rng.below(lines.len()));
            let mut v = lines.clone();
            v.swap(i, j);
            v.join("\n")
        }
        8 => {
            let k = rng.below(lines.len() + 1);
            let mut v = lines.clone();
            v.insert(k, *rng.pick(LINES));
            v.join("\n")
        }
        _ => {
            let mut cut = rng.below(text.len() + 1);
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            text[..cut].to_string()
        }
    }
}

#[test]
fn mutated_scenes_never_panic_hang_or_allocate_without_bound() {
    // The only test of this file, so setting the variable races with nothing.
    std::env::set_var("CRAMP_MEMORY_LIMIT", format!("{LIMIT}"));
    let cases: usize = std::env::var("CRAMP_FUZZ_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(5000);
    let seed: u64 = std::env::var("CRAMP_FUZZ_SEED").ok().and_then(|s| s.parse().ok()).unwrap_or(0x1915_5EED);
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("verification");
    let mut seeds: Vec<(String, String)> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml") && p.file_stem().is_some_and(|s| s != "cases"))
        .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read_to_string(&p).unwrap()))
        .collect();
    seeds.sort();
    let current = Arc::new(Mutex::new(String::new()));
    let (tx, rx) = mpsc::channel();
    let watched = Arc::clone(&current);
    let worker = std::thread::spawn(move || {
        let mut rng = Rng(seed);
        let (mut accepted, mut refused, mut slowest, mut peak_max) = (0usize, 0usize, (0.0f64, 0usize), 0usize);
        let mut fields = std::collections::BTreeSet::new();
        for i in 0..cases {
            let (name, seed) = &seeds[i % seeds.len()];
            let mut text = seed.clone();
            for _ in 0..1 + rng.below(3) {
                text = mutate(&text, &mut rng);
            }
            *watched.lock().unwrap() = format!("mutation {i} of {name}:\n{text}");
            let base = LIVE.load(Ordering::Relaxed);
            PEAK.store(base, Ordering::Relaxed);
            let start = Instant::now();
            // Parse and build; an accepted scene also takes two steps (an error is fine).
            let result = std::panic::catch_unwind(|| {
                Scene::from_toml(&text, name).and_then(|s| s.build()).map(|mut sim| {
                    let _ = sim.step().and_then(|()| sim.step());
                })
            });
            let took = start.elapsed().as_secs_f64();
            let peak = PEAK.load(Ordering::Relaxed).saturating_sub(base);
            match result {
                Err(_) => panic!("mutation {i} of {name} panicked:\n{text}"),
                Ok(Ok(_)) => accepted += 1,
                Ok(Err(e)) => {
                    if let cramp::scene::SceneError::Invalid { field, .. } = &e {
                        // Indices stripped: the kinds of field, not their instances.
                        fields.insert(field.split(['[', '.']).take(3).collect::<Vec<_>>().join("."));
                    }
                    refused += 1;
                }
            }
            assert!(took < 10.0, "mutation {i} of {name} took {took:.1} s:\n{text}");
            assert!(
                (peak as f64) < 3.0 * LIMIT,
                "mutation {i} of {name} allocated {peak} bytes (limit {LIMIT}):\n{text}"
            );
            if took > slowest.0 {
                slowest = (took, i);
            }
            peak_max = peak_max.max(peak);
        }
        tx.send((accepted, refused, slowest, peak_max, fields.len())).unwrap();
    });
    let deadline = Duration::from_secs(300);
    match rx.recv_timeout(deadline) {
        Ok((accepted, refused, slowest, peak, kinds)) => {
            println!(
                "{cases} mutations: {accepted} accepted and built, {refused} refused with an error ({kinds} kinds of invalid field); slowest {:.3} s (mutation {}), peak heap {:.1} MB",
                slowest.0,
                slowest.1,
                peak as f64 / 1e6
            );
        }
        Err(mpsc::RecvTimeoutError::Timeout) => {
            panic!("the fuzz loop hung for {deadline:?} at {}", current.lock().unwrap())
        }
        Err(mpsc::RecvTimeoutError::Disconnected) => {
            let e = worker.join().unwrap_err();
            std::panic::resume_unwind(e);
        }
    }
}
