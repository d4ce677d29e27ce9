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

thread_local! {
    static RECORDER: RefCell<Option<Vec<u64>>> = const { RefCell::new(None) };
}

/// While alive, collects the fingerprint of every simulation dropped on this thread.
pub struct Recorder(());

impl Recorder {
    /// Start recording on this thread (replacing an unfinished recording).
    pub fn start() -> Recorder {
        RECORDER.with(|r| *r.borrow_mut() = Some(Vec::new()));
        Recorder(())
    }

    /// Stop recording and return the fingerprints in the order the simulations were dropped.
    pub fn finish(self) -> Vec<u64> {
        RECORDER.with(|r| r.borrow_mut().take().unwrap_or_default())
    }
}

impl Drop for Recorder {
    fn drop(&mut self) {
        RECORDER.with(|r| *r.borrow_mut() = None);
    }
}

/// Called when a simulation is dropped: record its fingerprint if a recorder is open.
pub(crate) fn on_drop<S: Dimension>(sim: &Simulation<S>) {
    let active = RECORDER.with(|r| r.borrow().is_some());
    if active {
        let f = fingerprint(sim);
        RECORDER.with(|r| {
            if let Some(v) = r.borrow_mut().as_mut() {
                v.push(f)
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
