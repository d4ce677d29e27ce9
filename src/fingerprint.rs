//! Bit fingerprints of a run's final state, so that any reordered sum anywhere in the
//! solver shows up as a changed golden snapshot (issue 14: "2D bits do not move").
//!
//! A fingerprint is the 64-bit FNV-1a hash of the exact bits of every particle's state
//! (in id order: x, v, σ, ε, ∇u), of every crack point and both crack surfaces, of the
//! energies (kinetic, strain, external work, damping), the time and the step count. Two
//! runs with the same fingerprint agree to the bit with overwhelming probability; one
//! changed bit anywhere changes it.
//!
//! The verification runner ([`crate::verify::run_case`]) opens a [`Recorder`] on its
//! thread; every [`Simulation`] dropped on that thread while it is open adds its
//! fingerprint, so every scene a case runs is covered without the case doing anything.
//! Cases run their scenes sequentially on the calling thread, so the order of the
//! recorded fingerprints is the order of the case's code.

use crate::dim::{SymOps, TensorOps};
use crate::simulation::{Dimension, Simulation};
use std::cell::RefCell;

/// 64-bit FNV-1a (Fowler–Noll–Vo): fixed, portable, and enough to detect a changed bit.
#[derive(Clone, Copy, Debug)]
pub struct Fnv1a(u64);

impl Default for Fnv1a {
    fn default() -> Self {
        Fnv1a(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv1a {
    pub fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= b as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    pub fn f64s(&mut self, values: impl IntoIterator<Item = f64>) {
        for v in values {
            self.bytes(&v.to_bits().to_le_bytes());
        }
    }

    pub fn finish(&self) -> u64 {
        self.0
    }
}

/// Where a simulation's scene came from, for `cramp verify --export`.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneSource {
    /// The scene file in `verification/` and the `--set` overrides applied to it; `None`
    /// when the scene was built or changed in Rust (then `text` is the serialized scene).
    pub file: Option<String>,
    pub overrides: Vec<String>,
    /// The scene as TOML with the overrides applied: what `cramp run` reads.
    pub text: String,
}

/// One simulation a recording saw: its fingerprint when dropped, the scene it was built
/// from (None if it was not built from a scene, e.g. a clone changed in Rust), whether it
/// ran checked, and where it stopped.
#[derive(Clone, Debug)]
pub struct Recorded {
    pub fingerprint: u64,
    pub scene: Option<SceneSource>,
    pub checked: bool,
    /// Steps begun (a step that failed a check counts) and the time reached.
    pub steps: u64,
    pub time: f64,
    pub dt: f64,
    /// Particles at the drop (with `steps`, the cost of running the scene again).
    pub particles: usize,
    /// The state after step [`EARLY_STEPS`] (None for a simulation not built from a scene,
    /// or one that stopped before): lets `tests/golden.rs` check that an exported scene
    /// reproduces an expensive run by running only its first steps.
    pub early: Option<Early>,
}

/// The step after which a recorded simulation's state is fingerprinted once more
/// ([`Recorded::early`]).
pub const EARLY_STEPS: u64 = 25;

/// The fingerprint of a simulation after its first [`EARLY_STEPS`] steps, and the time
/// reached (`solver.end_time` of a run that stops there).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Early {
    pub fingerprint: u64,
    pub time: f64,
}

impl Recorded {
    /// Whether every step begun was completed (time advanced by it): a step that fails
    /// mid-way leaves `steps` one ahead of the time.
    pub fn last_step_completed(&self) -> bool {
        ((self.time / self.dt) - self.steps as f64).abs() < 0.5
    }
}

#[derive(Default)]
struct State {
    recorded: Vec<Recorded>,
    /// Scenes read from files (serialized scene → source), see [`note_loaded`].
    loaded: Vec<(String, SceneSource)>,
    /// Live simulations built from a scene, keyed by the address of their particle-id
    /// array (a heap buffer that never moves or reallocates after the build: particles
    /// are only permuted in place), so the key follows the simulation when it is moved.
    built: Vec<(usize, SceneSource, Option<Early>)>,
}

thread_local! {
    static RECORDER: RefCell<Option<State>> = const { RefCell::new(None) };
}

/// While alive, collects the fingerprint of every simulation dropped on this thread.
pub struct Recorder(());

impl Recorder {
    /// Start recording on this thread (replacing an unfinished recording).
    pub fn start() -> Recorder {
        RECORDER.with(|r| *r.borrow_mut() = Some(State::default()));
        Recorder(())
    }

    /// Stop recording and return the simulations in the order they were dropped.
    pub fn finish(self) -> Vec<Recorded> {
        RECORDER.with(|r| r.borrow_mut().take().map(|s| s.recorded).unwrap_or_default())
    }
}

impl Drop for Recorder {
    fn drop(&mut self) {
        RECORDER.with(|r| *r.borrow_mut() = None);
    }
}

fn key<S: Dimension>(sim: &Simulation<S>) -> usize {
    sim.particles.id.as_ptr() as usize
}

/// A scene was read from a file with overrides (`verify::scene_file`): a simulation
/// built from a scene that serializes to `serialized` came from `source`.
pub fn note_loaded(serialized: String, source: SceneSource) {
    RECORDER.with(|r| {
        if let Some(s) = r.borrow_mut().as_mut() {
            s.loaded.push((serialized, source));
        }
    });
}

/// Called when a scene has built a simulation: remember the scene (its serialization,
/// computed only while recording) so the export can write it.
pub(crate) fn on_build<S: Dimension>(sim: &Simulation<S>, serialized: impl FnOnce() -> Option<String>) {
    if !RECORDER.with(|r| r.borrow().is_some()) || sim.particles.id.is_empty() {
        return;
    }
    let Some(text) = serialized() else { return };
    RECORDER.with(|r| {
        if let Some(s) = r.borrow_mut().as_mut() {
            let source = s
                .loaded
                .iter()
                .rev()
                .find(|(t, _)| *t == text)
                .map(|(_, src)| src.clone())
                .unwrap_or(SceneSource { file: None, overrides: Vec::new(), text });
            let k = key(sim);
            s.built.retain(|(b, _, _)| *b != k);
            s.built.push((k, source, None));
        }
    });
}

/// Called after every step that completed: after step [`EARLY_STEPS`] of a simulation
/// built from a scene while recording, remember its fingerprint ([`Recorded::early`]).
pub(crate) fn on_step<S: Dimension>(sim: &Simulation<S>) {
    if sim.step_count != EARLY_STEPS || !RECORDER.with(|r| r.borrow().is_some()) {
        return;
    }
    let k = key(sim);
    let early = Early { fingerprint: fingerprint(sim), time: sim.time };
    RECORDER.with(|r| {
        if let Some(s) = r.borrow_mut().as_mut() {
            if let Some(b) = s.built.iter_mut().find(|(b, _, _)| *b == k) {
                b.2 = Some(early);
            }
        }
    });
}

/// Called when a simulation is dropped: record its fingerprint if a recorder is open.
pub(crate) fn on_drop<S: Dimension>(sim: &Simulation<S>) {
    let active = RECORDER.with(|r| r.borrow().is_some());
    if active {
        let f = fingerprint(sim);
        let k = key(sim);
        RECORDER.with(|r| {
            if let Some(s) = r.borrow_mut().as_mut() {
                let built = s.built.iter().position(|(b, _, _)| *b == k && !sim.particles.id.is_empty()).map(|i| s.built.remove(i));
                let (scene, early) = built.map_or((None, None), |(_, src, early)| (Some(src), early));
                s.recorded.push(Recorded {
                    fingerprint: f,
                    scene,
                    checked: sim.options.checked,
                    steps: sim.step_count,
                    time: sim.time,
                    dt: sim.options.dt,
                    particles: sim.particles.len(),
                    early,
                });
            }
        });
    }
}

/// The fingerprint of a simulation's current state (see the module documentation).
pub fn fingerprint<S: Dimension>(sim: &Simulation<S>) -> u64 {
    let p = &sim.particles;
    let mut order: Vec<usize> = (0..p.len()).collect();
    order.sort_unstable_by_key(|&i| p.id[i]);
    let mut h = Fnv1a::default();
    h.bytes(&(p.len() as u64).to_le_bytes());
    for &i in &order {
        h.bytes(&p.id[i].to_le_bytes());
        h.f64s((0..S::DIM).map(|c| p.x[i][c]));
        h.f64s((0..S::DIM).map(|c| p.v[i][c]));
        h.f64s(p.stress[i].components().into_iter().chain(p.strain[i].components()));
        // Column-major, as nalgebra stores it.
        h.f64s((0..S::DIM).flat_map(|b| (0..S::DIM).map(move |a| (a, b))).map(|(a, b)| p.grad_u[i].get(a, b)));
    }
    for word in S::crack_state_bits(&sim.cracks) {
        h.bytes(&word.to_le_bytes());
    }
    let e = sim.energies();
    h.f64s([e.kinetic, e.strain, e.external_work, e.damping, sim.time]);
    h.bytes(&sim.step_count.to_le_bytes());
    h.finish()
}

/// A case's fingerprints combined into one (hash of the list, in order), for a snapshot.
pub fn combine(prints: &[u64]) -> u64 {
    let mut h = Fnv1a::default();
    for f in prints {
        h.bytes(&f.to_le_bytes());
    }
    h.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_known_values() {
        // Reference values of 64-bit FNV-1a (the algorithm's published test vectors).
        let mut h = Fnv1a::default();
        assert_eq!(h.finish(), 0xcbf29ce484222325);
        h.bytes(b"a");
        assert_eq!(h.finish(), 0xaf63dc4c8601ec8c);
        let mut h = Fnv1a::default();
        h.bytes(b"foobar");
        assert_eq!(h.finish(), 0x85944171f73967e8);
    }
}
