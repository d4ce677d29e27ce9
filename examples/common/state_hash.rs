//! The state hash of examples/steps3d.rs and window3d.rs: FNV-1a over every bit of each
//! particle's x, v, σ, ε and ∇u in storage order (equal hashes, equal bits).

/// FNV-1a over the bits of the f64 values fed to it (little-endian bytes, in order).
pub struct Fnv(pub u64);

impl Fnv {
    pub fn new() -> Fnv {
        Fnv(0xcbf29ce484222325)
    }
    pub fn eat(&mut self, x: f64) {
        for b in x.to_bits().to_le_bytes() {
            self.0 = (self.0 ^ b as u64).wrapping_mul(0x100000001b3);
        }
    }
}

#[allow(dead_code)] // examples/steps.rs (2D) uses only `Fnv`.
pub fn state_hash(sim: &cramp::simulation::Simulation<cramp::dim::D3>) -> u64 {
    let mut fnv = Fnv::new();
    let mut eat = |x: f64| fnv.eat(x);
    let q = &sim.particles;
    for i in 0..q.len() {
        for c in 0..3 {
            eat(q.x[i][c]);
            eat(q.v[i][c]);
        }
        let (s, e) = (&q.stress[i], &q.strain[i]);
        for x in [s.xx, s.yy, s.zz, s.xy, s.xz, s.yz, e.xx, e.yy, e.zz, e.xy, e.xz, e.yz] {
            eat(x);
        }
        for x in q.grad_u[i].iter() {
            eat(*x);
        }
    }
    fnv.0
}
