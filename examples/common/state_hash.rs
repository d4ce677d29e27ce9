//! The state hash of examples/steps3d.rs and window3d.rs: FNV-1a over every bit of each
//! particle's x, v, σ, ε and ∇u in storage order (equal hashes, equal bits).

pub fn state_hash(sim: &cramp::simulation::Simulation<cramp::dim::D3>) -> u64 {
    let mut hash = 0xcbf29ce484222325u64;
    let mut eat = |x: f64| {
        for b in x.to_bits().to_le_bytes() {
            hash = (hash ^ b as u64).wrapping_mul(0x100000001b3);
        }
    };
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
    hash
}
