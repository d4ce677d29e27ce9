//! The fast sums of the 3D step's hot gathers written with explicit AVX2 intrinsics
//! (issue 14), for the pairs no crack splits (every pair in field 0, share 1).
//!
//! Each function is the [`crate::exact::Fast`] instance of a gather in `step.rs`
//! (`node_mass::<_, false, false>`, `node_forces::<_, false>` without external terms,
//! `node_momentum::<_, false>`, `velocity_gradient::<_, false>`,
//! `particle_increments::<_, false>`), computing the same terms with the same IEEE
//! operations in the same order, and accumulating them with the operations of
//! [`crate::exact::FastSum`]'s `add` (TwoSum, compensation, Σ|x|, min |x|), lane by lane,
//! four lanes to a `__m256d` kept in registers. Its certificate is that of
//! `FastSum::certified` (both tests, on the same values: [`certify4`]); when it fails,
//! the caller reruns the generic gather with three-level or exact sums, as before. A
//! certified sum is the correctly rounded one, so these functions move no bit.
//!
//! What makes them cheaper than the generic AVX2 copies (which LLVM vectorises with lane
//! shuffles and accumulators on the stack): the lanes of a pair are built as whole
//! vectors, and the per-particle factors the node gathers share are formed once per step
//! ([`fill_mass_momentum`]: m and m·v, whose products with S are the mass and momentum
//! terms, (m·v_c)·S as in the generic code; [`fill_stress_columns`]: the columns of σ
//! and −V, whose products with G give −(V·(σ·G)) with σ·G summed as `Sym3::dot_vec` does;
//! negation is exact, so (−V)·t = −(V·t) to the bit).
//!
//! Padding lanes (the fourth of a 3-vector) carry ±0 terms (a zero mask load times a
//! factor) and are not certified or read.
#![cfg(target_arch = "x86_64")]

use crate::dim::{Sym3, Tensor3, Vector3, D3};
use crate::exact::ExactSum;
use crate::grid::MAX_FIELDS;
use crate::simulation::{Dimension, Simulation};
use crate::step::{NodeForce, NodeMass};
use std::any::TypeId;
use std::arch::x86_64::*;

/// The simulation as a 3D one, when `S` is [`D3`] (a test of type identities, which the
/// compiler folds per instance).
#[inline(always)]
pub(crate) fn as_d3<S: Dimension>(sim: &crate::simulation::Simulation<S>) -> Option<&Simulation<D3>> {
    if TypeId::of::<S>() == TypeId::of::<D3>() {
        // SAFETY: S is D3, so the two types are the same.
        Some(unsafe { &*(sim as *const Simulation<S> as *const Simulation<D3>) })
    } else {
        None
    }
}

/// `x` as `B`, which is `A` (asserted; the generic step hands D3 results back as its `S`
/// types).
#[inline(always)]
pub(crate) fn same<A: 'static + Copy, B: 'static + Copy>(x: A) -> B {
    assert!(TypeId::of::<A>() == TypeId::of::<B>());
    // SAFETY: A and B are the same type.
    unsafe { std::mem::transmute_copy(&x) }
}

/// Something that takes the four lanes of a gather's terms, one `__m256d` per pair.
pub(crate) trait Add4 {
    unsafe fn add(&mut self, x: __m256d);
}

/// Four lanes of a certified compensated sum.
pub(crate) trait Sum4: Copy + Add4 {
    unsafe fn new() -> Self;
    /// The sums of the first `lanes` lanes of `acc` (n terms) as far as they are
    /// certified: `Ok` if all are, else the certified ones and which they are
    /// ([`Uncertified`], for [`ExactLanes`] to complete).
    unsafe fn lanes(n: usize, lanes: usize, acc: &Self) -> Result<[f64; 4], Uncertified>;
}

/// The lanes of a node gather that its certified sums left open: the sums of the lanes
/// that are certified (the correctly rounded ones), and which those are (bit k: lane k).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Uncertified {
    sums: [f64; 4],
    ok: i32,
}

/// The last resort of the 3D node gathers: the lanes that neither [`Acc4`] nor [`Acc4x3`]
/// certified (`Uncertified`), summed with [`ExactSum`] over the same terms; the other
/// lanes keep their certified sums. Every lane is then the correctly rounded sum, as
/// `exact::Rerun` gives it (which runs the generic gather again with three-level sums and
/// kept terms for every lane, and sums the lanes those do not certify exactly), so the
/// bits are the same; only the lanes left open pay for the exact sum.
struct ExactLanes {
    open: [bool; 4],
    sums: [f64; 4],
    exact: [ExactSum; 4],
}

impl ExactLanes {
    fn new(u: Uncertified) -> Self {
        ExactLanes { open: std::array::from_fn(|k| u.ok & (1 << k) == 0), sums: u.sums, exact: std::array::from_fn(|_| ExactSum::new()) }
    }

    /// Every lane's correctly rounded sum.
    fn finish(&self) -> [f64; 4] {
        std::array::from_fn(|k| if self.open[k] { self.exact[k].value() } else { self.sums[k] })
    }
}

impl Add4 for ExactLanes {
    #[inline(always)]
    unsafe fn add(&mut self, x: __m256d) {
        let mut v = [0.0; 4];
        _mm256_storeu_pd(v.as_mut_ptr(), x);
        for ((e, &open), &x) in self.exact.iter_mut().zip(&self.open).zip(&v) {
            if open {
                e.add(x);
            }
        }
    }
}

/// Four lanes of [`crate::exact::FastSum`]: running sum, compensation, Σ|x|, min |x|.
#[derive(Clone, Copy)]
pub(crate) struct Acc4 {
    s: __m256d,
    c: __m256d,
    a: __m256d,
    m: __m256d,
}

impl Add4 for Acc4 {
    /// `FastSum::add` on four lanes: the same operations in the same order.
    #[inline(always)]
    unsafe fn add(&mut self, x: __m256d) {
        (self.s, self.c) = two_sum_step(self.s, self.c, x);
        let ax = _mm256_andnot_pd(_mm256_set1_pd(-0.0), x);
        self.a = _mm256_add_pd(self.a, ax);
        // minpd(ax, m) = ax < m ? ax : m, the select of FastSum::add (m kept for a NaN ax).
        self.m = _mm256_min_pd(ax, self.m);
    }
}

impl Sum4 for Acc4 {
    #[inline(always)]
    unsafe fn new() -> Self {
        Acc4 { s: _mm256_set1_pd(-0.0), c: _mm256_setzero_pd(), a: _mm256_setzero_pd(), m: _mm256_set1_pd(f64::INFINITY) }
    }

    /// As `FastSum::certified` gives them ([`certify4`]), lane by lane.
    #[inline(always)]
    unsafe fn lanes(n: usize, lanes: usize, acc: &Acc4) -> Result<[f64; 4], Uncertified> {
        let want = (1 << lanes) - 1;
        let mut out = [0.0; 4];
        let ok = if n == 0 {
            want
        } else if n > 1 << 20 {
            0
        } else {
            let nf = n as f64;
            let (sum, mask) = certify4(acc, _mm256_set1_pd(nf * nf));
            _mm256_storeu_pd(out.as_mut_ptr(), sum);
            mask & want
        };
        if ok == want {
            Ok(out)
        } else {
            Err(Uncertified { sums: out, ok: ok | !want })
        }
    }
}

impl Acc4 {
    /// The certified sums of the first `lanes` lanes of each accumulator in `acc` (n
    /// terms each) as `FastSum::certified` gives them ([`certify4`]), or None if one of
    /// them is not certified.
    #[inline(always)]
    unsafe fn certified<const V: usize>(n: usize, lanes: usize, acc: &[Acc4; V]) -> Option<[[f64; 4]; V]> {
        let mut out = [[0.0; 4]; V];
        if n == 0 {
            return Some(out);
        }
        if n > 1 << 20 {
            return None;
        }
        let nf = n as f64;
        let n2 = _mm256_set1_pd(nf * nf);
        let want = (1 << lanes) - 1;
        let mut ok = true;
        for (o, a) in out.iter_mut().zip(acc) {
            let (sum, mask) = certify4(a, n2);
            _mm256_storeu_pd(o.as_mut_ptr(), sum);
            ok &= mask & want == want;
        }
        ok.then_some(out)
    }
}

/// Four lanes of [`crate::exact::FastSum3`] (the three-level sums that certify the
/// cancelling sums of mirror-plane nodes): running sum, compensation c, its error d,
/// Σ|x|, the smallest non-zero |x|; `FastSum3::add`'s operations in its order.
#[derive(Clone, Copy)]
pub(crate) struct Acc4x3 {
    s: __m256d,
    c: __m256d,
    d: __m256d,
    a: __m256d,
    m: __m256d,
}

impl Add4 for Acc4x3 {
    #[inline(always)]
    unsafe fn add(&mut self, x: __m256d) {
        let s0 = self.s;
        let s = _mm256_add_pd(s0, x);
        let bb = _mm256_sub_pd(s, s0);
        let t = _mm256_add_pd(_mm256_sub_pd(s0, _mm256_sub_pd(s, bb)), _mm256_sub_pd(x, bb));
        self.s = s;
        let c0 = self.c;
        let c = _mm256_add_pd(c0, t);
        let bc = _mm256_sub_pd(c, c0);
        self.d = _mm256_add_pd(self.d, _mm256_add_pd(_mm256_sub_pd(c0, _mm256_sub_pd(c, bc)), _mm256_sub_pd(t, bc)));
        self.c = c;
        let ax = _mm256_andnot_pd(_mm256_set1_pd(-0.0), x);
        self.a = _mm256_add_pd(self.a, ax);
        // ax < m && ax != 0 ? ax : m.
        let take = _mm256_and_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(ax, self.m), _mm256_cmp_pd::<_CMP_NEQ_UQ>(ax, _mm256_setzero_pd()));
        self.m = _mm256_blendv_pd(self.m, ax, take);
    }
}

impl Sum4 for Acc4x3 {
    #[inline(always)]
    unsafe fn new() -> Self {
        Acc4x3 { s: _mm256_set1_pd(-0.0), c: _mm256_setzero_pd(), d: _mm256_setzero_pd(), a: _mm256_setzero_pd(), m: _mm256_set1_pd(f64::INFINITY) }
    }

    /// `FastSum3::certified`, lane by lane (`certify`, else `certify3`).
    #[inline(always)]
    unsafe fn lanes(n: usize, lanes: usize, x: &Acc4x3) -> Result<[f64; 4], Uncertified> {
        let mut p = [[0.0; 4]; 5];
        for (q, v) in p.iter_mut().zip([x.s, x.c, x.d, x.a, x.m]) {
            _mm256_storeu_pd(q.as_mut_ptr(), v);
        }
        let (mut out, mut ok) = ([0.0; 4], !((1 << lanes) - 1));
        let n = n as u32;
        for (k, o) in out.iter_mut().enumerate().take(lanes) {
            if let Some(v) = crate::exact::certify(p[0][k], p[1][k], p[3][k], p[4][k], n).or_else(|| crate::exact::certify3(p[0][k], p[1][k], p[2][k], p[3][k], p[4][k], n)) {
                *o = v;
                ok |= 1 << k;
            }
        }
        if ok == -1 {
            Ok(out)
        } else {
            Err(Uncertified { sums: out, ok })
        }
    }
}

/// `FastSum::certified` on the four lanes of `acc` (n ≥ 1 terms, n² = `n2`), written with
/// intrinsics: the same two certificates on the same values, so the same verdicts.
/// Returns the sums and the bit mask of the lanes certified.
#[inline(always)]
unsafe fn certify4(acc: &Acc4, n2: __m256d) -> (__m256d, i32) {
    certify4_parts(acc.s, acc.c, acc.a, acc.m, n2)
}

/// [`certify4`] on its parts: running sum `s`, compensation `c`, Σ|x| (or a bound of it,
/// see [`velocity_gradient`]) `a`, min |x| (or a lower bound of it) `m`.
#[inline(always)]
unsafe fn certify4_parts(s: __m256d, c: __m256d, a: __m256d, m: __m256d, n2: __m256d) -> (__m256d, i32) {
    let p2 = |k: i32| _mm256_set1_pd(f64::from_bits(((1023 + k) as u64) << 52));
    let db = _mm256_mul_pd(n2, _mm256_mul_pd(p2(-104), a));
    // TwoSum(s, c) = (r, t2).
    let r = _mm256_add_pd(s, c);
    let bb = _mm256_sub_pd(r, s);
    let t2 = _mm256_add_pd(_mm256_sub_pd(s, _mm256_sub_pd(r, bb)), _mm256_sub_pd(c, bb));
    let in_range = _mm256_and_pd(_mm256_cmp_pd::<_CMP_GE_OQ>(a, p2(-800)), _mm256_cmp_pd::<_CMP_LE_OQ>(a, p2(1000)));
    // 1. δ = 0.
    let exact = _mm256_and_pd(_mm256_cmp_pd::<_CMP_GE_OQ>(m, p2(-900)), _mm256_cmp_pd::<_CMP_LT_OQ>(db, _mm256_mul_pd(m, p2(-53))));
    // 2. Inside the rounding interval, h from r's bits as in FastSum::certified.
    let frac = _mm256_set1_epi64x(((1u64 << 52) - 1) as i64);
    let bits = _mm256_andnot_si256(_mm256_set1_epi64x(i64::MIN), _mm256_castpd_si256(r));
    let pow2_frac = _mm256_cmpeq_epi64(_mm256_and_si256(bits, frac), _mm256_setzero_si256());
    let drop = _mm256_blendv_epi8(_mm256_set1_epi64x(53 << 52), _mm256_set1_epi64x(54 << 52), pow2_frac);
    let h = _mm256_castsi256_pd(_mm256_sub_epi64(_mm256_andnot_si256(frac, bits), drop));
    let big = _mm256_cmpgt_epi64(bits, _mm256_set1_epi64x((((1023 - 900) as i64) << 52) - 1));
    let abs_t2 = _mm256_andnot_pd(_mm256_set1_pd(-0.0), t2);
    let inside = _mm256_and_pd(_mm256_castsi256_pd(big), _mm256_cmp_pd::<_CMP_LT_OQ>(_mm256_add_pd(db, db), _mm256_sub_pd(h, abs_t2)));
    // All terms ±0: their IEEE sum s.
    let zeros = _mm256_cmp_pd::<_CMP_EQ_OQ>(a, _mm256_setzero_pd());
    let out = _mm256_blendv_pd(r, s, zeros);
    let ok = _mm256_or_pd(zeros, _mm256_and_pd(in_range, _mm256_or_pd(exact, inside)));
    (out, _mm256_movemask_pd(ok))
}

/// Load a 3-vector as (x, y, z, 0).
#[inline(always)]
unsafe fn load3(p: *const f64) -> __m256d {
    _mm256_insertf128_pd::<1>(_mm256_castpd128_pd256(_mm_loadu_pd(p)), _mm_load_sd(p.add(2)))
}

/// Per particle, (m, m·v_x, m·v_y, m·v_z): the factors of the mass and momentum terms.
pub(crate) fn fill_mass_momentum(sim: &Simulation<D3>, out: &mut Vec<[f64; 4]>) {
    use rayon::prelude::*;
    let p = &sim.particles;
    out.resize(p.len(), [0.0; 4]);
    (out.par_iter_mut(), p.mass.par_iter(), p.v.par_iter()).into_par_iter().with_min_len(crate::step::PARTICLE_CHUNK).for_each(|(o, &m, v)| {
        *o = [m, m * v.x, m * v.y, m * v.z];
    });
}

/// Per particle, the columns of σ (x, y, z; padded with 0) and −V in all four lanes: the
/// factors of the internal force terms.
pub(crate) fn fill_stress_columns(sim: &Simulation<D3>, out: &mut Vec<[[f64; 4]; 4]>) {
    use rayon::prelude::*;
    let p = &sim.particles;
    out.resize(p.len(), [[0.0; 4]; 4]);
    (out.par_iter_mut(), p.stress.par_iter(), p.vol0.par_iter()).into_par_iter().with_min_len(crate::step::PARTICLE_CHUNK).for_each(|(o, s, &v0)| {
        let s: &Sym3 = s;
        *o = [[s.xx, s.xy, s.xz, 0.0], [s.xy, s.yy, s.yz, 0.0], [s.xz, s.yz, s.zz, 0.0], [-v0; 4]];
    });
}

/// The four lanes (m·S, (m·v)·S) of the active node `a` summed over its pairs, from the
/// factors of [`fill_mass_momentum`], and the number of terms: the loop [`node_mass`] and
/// [`node_momentum`] share.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn mass_momentum_sum<A: Add4>(sim: &Simulation<D3>, mv: &[[f64; 4]], a: usize, acc: &mut A) -> usize {
    let pairs = &sim.pairs;
    let (lo, hi) = (pairs.start[a] as usize, pairs.start[a + 1] as usize);
    let (items, owner) = (&pairs.items, &sim.scratch.item_particle);
    let end = items.len().min(owner.len());
    debug_assert!(hi <= end);
    let (s, mv) = (pairs.s.as_ptr(), mv.as_ptr());
    for j in lo..hi {
        let ahead = j + PREFETCH_AHEAD;
        if ahead < end {
            prefetch(mv.add(*owner.get_unchecked(ahead) as usize) as *const f64);
            prefetch(s.add(*items.get_unchecked(ahead) as usize));
        }
        let (item, pp) = (*items.get_unchecked(j) as usize, *owner.get_unchecked(j) as usize);
        debug_assert!(item < pairs.s.len() && pp == item / 27 && pp < sim.particles.len());
        acc.add(_mm256_mul_pd(_mm256_loadu_pd((*mv.add(pp)).as_ptr()), _mm256_broadcast_sd(&*s.add(item))));
    }
    hi - lo
}

/// How many of a node gather's pairs ahead of the one summed have their particle's data
/// prefetched. The node gathers run over the pairs by node, so each pair's particle data
/// (its factors, S, G: several MB in all) is a scattered read that the hardware
/// prefetchers cannot predict; its address is known from the incidence lists, which are
/// read in order (issue 14: ≈ 15 % of the 3D step's time). The pairs after a node's last
/// are the next node's, so the prefetches run on across nodes. Prefetching changes no
/// value.
const PREFETCH_AHEAD: usize = 16;

/// Prefetch the cache line holding `p` into all cache levels (a hint; no fault).
#[inline(always)]
unsafe fn prefetch(p: *const f64) {
    _mm_prefetch::<_MM_HINT_T0>(p as *const i8);
}

/// How many particles ahead of the one gathered [`velocity_gradient`] prefetches the shape
/// function gradients of (see [`prefetch_gradients`]).
const PARTICLES_AHEAD: usize = 2;

/// Prefetch the used part of particle `p`'s G stride (if there is such a particle). The
/// velocity gradient walks the particles in order, but each particle uses only its first
/// `count` of 27 slots (≈ 16 with uGIMP at 2 particles per cell), so the strides are read
/// with gaps that the hardware prefetchers do not run ahead of (issue 14).
#[inline(always)]
unsafe fn prefetch_gradients(sim: &Simulation<D3>, p: usize) {
    let pairs = &sim.pairs;
    if let Some(&n) = pairs.count.get(p) {
        let first = pairs.g.as_ptr().add(p * crate::shape::MAX_NODES_3D) as *const f64;
        // 3n doubles from `first`: the lines at 8-double steps and the last one.
        let len = 3 * n as usize;
        let mut off = 0;
        while off < len {
            prefetch(first.add(off));
            off += 8;
        }
        if len > 0 {
            prefetch(first.add(len - 1));
        }
    }
}

/// `node_mass::<Fast, false, false>` of the active node `a`, from the factors of
/// [`fill_mass_momentum`]: lanes (m·S, (m·v)·S). `Err`: the lanes `A` left open, for
/// [`node_mass_exact`].
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn node_mass<A: Sum4>(sim: &Simulation<D3>, mv: &[[f64; 4]], a: usize) -> Result<NodeMass<Vector3>, Uncertified> {
    let mut acc = A::new();
    let n = mass_momentum_sum(sim, mv, a, &mut acc);
    Ok(mass_out(n, A::lanes(n, 4, &acc)?))
}

/// [`node_mass`] completed: the lanes `u` left open summed exactly ([`ExactLanes`]).
#[cold]
#[inline(never)]
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn node_mass_exact(sim: &Simulation<D3>, mv: &[[f64; 4]], a: usize, u: Uncertified) -> NodeMass<Vector3> {
    let mut acc = ExactLanes::new(u);
    let n = mass_momentum_sum(sim, mv, a, &mut acc);
    mass_out(n, acc.finish())
}

#[inline(always)]
fn mass_out(n: usize, l: [f64; 4]) -> NodeMass<Vector3> {
    let mut out = NodeMass { present: if n == 0 { 0 } else { 1 }, ..Default::default() };
    out.mass[0] = l[0];
    out.mom[0] = Vector3::new(l[1], l[2], l[3]);
    out.volume = f64::NAN;
    out
}

/// `node_momentum::<Fast, false>` of the active node `a`: lanes (m·v)·S, from the factors
/// of [`fill_mass_momentum`] (the mass lane is formed and left unread). `Err`: the lanes `A` left open, for [`node_momentum_exact`].
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn node_momentum<A: Sum4>(sim: &Simulation<D3>, mv: &[[f64; 4]], a: usize) -> Result<[Vector3; MAX_FIELDS], Uncertified> {
    let mut acc = A::new();
    let n = mass_momentum_sum(sim, mv, a, &mut acc);
    let mut out = [Vector3::zeros(); MAX_FIELDS];
    if sim.nodes.present[sim.nodes.active[a] as usize] & 1 != 0 {
        let l = A::lanes(n, 4, &acc)?;
        out[0] = Vector3::new(l[1], l[2], l[3]);
    }
    Ok(out)
}

/// [`node_momentum`] completed: the lanes `u` left open summed exactly ([`ExactLanes`]).
#[cold]
#[inline(never)]
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn node_momentum_exact(sim: &Simulation<D3>, mv: &[[f64; 4]], a: usize, u: Uncertified) -> [Vector3; MAX_FIELDS] {
    let mut acc = ExactLanes::new(u);
    mass_momentum_sum(sim, mv, a, &mut acc);
    let l = acc.finish();
    let mut out = [Vector3::zeros(); MAX_FIELDS];
    out[0] = Vector3::new(l[1], l[2], l[3]);
    out
}

/// The terms of [`node_forces`] into `acc`; returns their number.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn forces_sum<A: Add4>(sim: &Simulation<D3>, cols: &[[[f64; 4]; 4]], a: usize, acc: &mut A) -> usize {
    let pairs = &sim.pairs;
    let (lo, hi) = (pairs.start[a] as usize, pairs.start[a + 1] as usize);
    let (items, owner) = (&pairs.items, &sim.scratch.item_particle);
    let end = items.len().min(owner.len());
    debug_assert!(hi <= end);
    let (g, cols) = (pairs.g.as_ptr() as *const f64, cols.as_ptr());
    for j in lo..hi {
        let ahead = j + PREFETCH_AHEAD;
        if ahead < end {
            let c = cols.add(*owner.get_unchecked(ahead) as usize) as *const f64;
            prefetch(c);
            prefetch(c.add(8));
            prefetch(g.add(3 * *items.get_unchecked(ahead) as usize));
        }
        let (item, pp) = (*items.get_unchecked(j) as usize, *owner.get_unchecked(j) as usize);
        debug_assert!(item < pairs.g.len() && pp == item / 27 && pp < sim.particles.len());
        let c = &*cols.add(pp);
        let gp = g.add(3 * item);
        let t = _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(_mm256_loadu_pd(c[0].as_ptr()), _mm256_broadcast_sd(&*gp)), _mm256_mul_pd(_mm256_loadu_pd(c[1].as_ptr()), _mm256_broadcast_sd(&*gp.add(1)))),
            _mm256_mul_pd(_mm256_loadu_pd(c[2].as_ptr()), _mm256_broadcast_sd(&*gp.add(2))),
        );
        acc.add(_mm256_mul_pd(_mm256_loadu_pd(c[3].as_ptr()), t));
    }
    hi - lo
}

/// `node_forces::<Fast, false>` of the active node `a` at a node without external force
/// terms: lanes (−V)·(σ·G), σ·G = (σ_x G_x + σ_y G_y) + σ_z G_z by columns, from the
/// factors of [`fill_stress_columns`]; the external force +0. `Err`: the lanes `A` left
/// open, for [`node_forces_exact`].
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn node_forces<A: Sum4>(sim: &Simulation<D3>, cols: &[[[f64; 4]; 4]], a: usize) -> Result<NodeForce<Vector3>, Uncertified> {
    let mut acc = A::new();
    let n = forces_sum(sim, cols, a, &mut acc);
    let mut out = NodeForce::default();
    if sim.nodes.present[sim.nodes.active[a] as usize] & 1 != 0 {
        let l = A::lanes(n, 3, &acc)?;
        out.fint[0] = Vector3::new(l[0], l[1], l[2]);
        out.fext[0] = Vector3::zeros();
    }
    Ok(out)
}

/// [`node_forces`] completed: the lanes `u` left open summed exactly ([`ExactLanes`]).
#[cold]
#[inline(never)]
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn node_forces_exact(sim: &Simulation<D3>, cols: &[[[f64; 4]; 4]], a: usize, u: Uncertified) -> NodeForce<Vector3> {
    let mut acc = ExactLanes::new(u);
    forces_sum(sim, cols, a, &mut acc);
    let l = acc.finish();
    let mut out = NodeForce::default();
    out.fint[0] = Vector3::new(l[0], l[1], l[2]);
    out.fext[0] = Vector3::zeros();
    out
}

#[derive(Clone, Copy)]
struct Acc4sc {
    s: __m256d,
    c: __m256d,
}

impl Acc4sc {
    #[inline(always)]
    unsafe fn new() -> Self {
        Acc4sc { s: _mm256_set1_pd(-0.0), c: _mm256_setzero_pd() }
    }

    #[inline(always)]
    unsafe fn add(&mut self, x: __m256d) {
        (self.s, self.c) = two_sum_step(self.s, self.c, x);
    }
}

/// One step of `FastSum::add`'s running sum on four lanes: TwoSum(s, x) = (s′, t) and
/// the compensation c + t, the same operations in the same order (shared by [`Acc4`]
/// and [`Acc4sc`]).
#[inline(always)]
unsafe fn two_sum_step(s0: __m256d, c: __m256d, x: __m256d) -> (__m256d, __m256d) {
    let s = _mm256_add_pd(s0, x);
    let bb = _mm256_sub_pd(s, s0);
    let t = _mm256_add_pd(_mm256_sub_pd(s0, _mm256_sub_pd(s, bb)), _mm256_sub_pd(x, bb));
    (s, _mm256_add_pd(c, t))
}

/// `velocity_gradient::<Fast, false>` of particle `i`: lanes v_a·G_b, row a in one vector.
///
/// The sums s and c are `FastSum`'s; its two certificates (see [`crate::exact::FastSum`])
/// are evaluated with a bound of Σ|x| and a lower bound of min |x| formed from the factors
/// of the terms x_k = fl(v_a(k)·G_b(k)) (n pairs k) instead of per term, which keeps the
/// three rows' accumulators in registers (issue 14). With V_a = max_k |v_a(k)|,
/// W_a = min_k |v_a(k)|, S_b = fl(Σ_k |G_b(k)|) (recursive sum) and M_b = min_k |G_b(k)|:
///
/// * a' = fl(V_a·S_b) bounds Σ|x_k| as the certificates need. Rounding to nearest is
///   monotone and |G_b(k)| ≤ S_b (each partial sum of non-negative terms is at least each
///   term), so |x_k| ≤ fl(V_a·|G_b(k)|) ≤ a' for every k; and with u = 2^−53,
///   A = Σ|x_k| ≤ (1+u)·V_a·Σ|G_b(k)|, S_b ≥ (1−γ_{n−1})·Σ|G_b(k)| (Higham §4.2), so
///   a' ≥ (1−u)²(1−γ_{n−1})/(1+u)·A when a' ≥ 2^−800 (no underflow; the certificates
///   require that range). `FastSum`'s proof needs db = fl(n²·(2^−104·a)) > 2δ with
///   δ ≤ n²u²A(1 + 10⁻⁵); here db ≥ 4n²u²a'(1−u) ≥ 3.9·n²u²A for n ≤ 2^20, so
///   both certificates keep their margins (`2·db < h − |t₂|` still implies δ < h − |t₂|).
/// * m' = fl(W_a·M_b) ≤ fl(|v_a(k)|·|G_b(k)|) = |x_k| for every k (monotone rounding), so
///   certificate 1's q > m·2^−53 ≥ m'·2^−53 holds, and m' ≥ 2^−900 makes every term normal.
/// * a' = 0 only if every term is ±0 (|x_k| ≤ a'), the case the certificates take as the
///   IEEE sum s.
/// * A non-finite term (a NaN or ∞ factor, or an overflowing product) would not show in
///   a' (`maxpd` does not keep a NaN), so the sums are certified only when s is finite:
///   s, the IEEE sum of the terms, is NaN or ±∞ whenever a term is.
///
/// So a certified lane is the correctly rounded sum, as with `FastSum`'s own Σ|x| and
/// min |x|; the bounds are looser, so a few more sums may fail and take the rerun.
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn velocity_gradient(sim: &Simulation<D3>, i: usize) -> Option<Tensor3> {
    let pairs = &sim.pairs;
    let k = pairs.of_particle(i);
    let vel = sim.nodes.fields[0].vel.as_ptr() as *const f64;
    let (node, g) = (pairs.node.as_ptr(), pairs.g.as_ptr() as *const f64);
    prefetch_gradients(sim, i + PARTICLES_AHEAD);
    let mut acc = [Acc4sc::new(); 3];
    let sign = _mm256_set1_pd(-0.0);
    let mut vmax = _mm256_setzero_pd();
    let mut gsum = _mm256_setzero_pd();
    for k in k.clone() {
        let n = *node.add(k) as usize;
        debug_assert!(n < sim.nodes.fields[0].vel.len());
        let gv = load3(g.add(3 * k));
        let v = vel.add(3 * n);
        acc[0].add(_mm256_mul_pd(_mm256_broadcast_sd(&*v), gv));
        acc[1].add(_mm256_mul_pd(_mm256_broadcast_sd(&*v.add(1)), gv));
        acc[2].add(_mm256_mul_pd(_mm256_broadcast_sd(&*v.add(2)), gv));
        let av = _mm256_andnot_pd(sign, load3(v));
        vmax = _mm256_max_pd(vmax, av);
        gsum = _mm256_add_pd(gsum, _mm256_andnot_pd(sign, gv));
    }
    let n = k.len();
    if n == 0 {
        return Some(Tensor3::zeros());
    }
    if n > 1 << 20 {
        return None;
    }
    let nf = n as f64;
    let n2 = _mm256_set1_pd(nf * nf);
    let zero = _mm256_setzero_pd();
    match certify_rows(&acc, vmax, gsum, [zero; 3], n2) {
        Some(t) => Some(t),
        None => velocity_gradient_min(sim, i, &acc, vmax, gsum, n2),
    }
}

/// The terms v_r ⊗ G of row r of [`velocity_gradient`] (lanes b = 0..2: v_r·G_b, the
/// products of the generic gather) into `acc`, for each row r that has one; returns the
/// number of pairs.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn velocity_gradient_rows<A: Add4>(sim: &Simulation<D3>, i: usize, acc: &mut [Option<A>; 3]) -> usize {
    let pairs = &sim.pairs;
    let vel = sim.nodes.fields[0].vel.as_ptr() as *const f64;
    let (node, g) = (pairs.node.as_ptr(), pairs.g.as_ptr() as *const f64);
    let k = pairs.of_particle(i);
    for k in k.clone() {
        let n = *node.add(k) as usize;
        debug_assert!(n < sim.nodes.fields[0].vel.len());
        let gv = load3(g.add(3 * k));
        let v = vel.add(3 * n);
        for (r, a) in acc.iter_mut().enumerate() {
            if let Some(a) = a {
                a.add(_mm256_mul_pd(_mm256_broadcast_sd(&*v.add(r)), gv));
            }
        }
    }
    k.len()
}

/// [`velocity_gradient`] when neither of its certifications holds: the rows with
/// three-level sums ([`Acc4x3`], certificates `certify` and `certify3` on Σ|x| and the
/// smallest non-zero |x| themselves), and the lanes those leave open summed exactly
/// ([`ExactLanes`]) — what the generic gather's rerun with `exact::Rerun` gives, the
/// correctly rounded sums, without its kept terms and three-level sums of all 12 lanes.
#[cold]
#[inline(never)]
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn velocity_gradient_exact(sim: &Simulation<D3>, i: usize) -> Tensor3 {
    let mut acc = [Some(Acc4x3::new()); 3];
    let n = velocity_gradient_rows(sim, i, &mut acc);
    let mut open: [Option<ExactLanes>; 3] = [None, None, None];
    let mut t = [[0.0; 4]; 3];
    for r in 0..3 {
        match Acc4x3::lanes(n, 3, acc[r].as_ref().unwrap()) {
            Ok(l) => t[r] = l,
            Err(u) => open[r] = Some(ExactLanes::new(u)),
        }
    }
    if open.iter().any(Option::is_some) {
        velocity_gradient_rows(sim, i, &mut open);
        for (tr, o) in t.iter_mut().zip(&open) {
            if let Some(o) = o {
                *tr = o.finish();
            }
        }
    }
    Tensor3::from_fn(|a, b| t[a][b])
}

/// [`velocity_gradient`]'s certificates with the bound a' = fl(V_a·S_b) per row a (`vmax`
/// holds V, `gsum` S) and the lower bounds m' of min |x| in `m` (one vector per row).
#[inline(always)]
unsafe fn certify_rows(acc: &[Acc4sc; 3], vmax: __m256d, gsum: __m256d, m: [__m256d; 3], n2: __m256d) -> Option<Tensor3> {
    let mut vx = [0.0; 4];
    _mm256_storeu_pd(vx.as_mut_ptr(), vmax);
    let (sign, finite) = (_mm256_set1_pd(-0.0), _mm256_set1_pd(f64::MAX));
    let mut t = [[0.0; 4]; 3];
    let mut ok = true;
    for r in 0..3 {
        let a = _mm256_mul_pd(_mm256_set1_pd(vx[r]), gsum);
        let (sum, mask) = certify4_parts(acc[r].s, acc[r].c, a, m[r], n2);
        let fin = _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LE_OQ>(_mm256_andnot_pd(sign, acc[r].s), finite));
        _mm256_storeu_pd(t[r].as_mut_ptr(), sum);
        ok &= mask & fin & 7 == 7;
    }
    ok.then(|| Tensor3::from_fn(|a, b| t[a][b]))
}

/// [`velocity_gradient`] when its first certification (m' = 0: certificate 2 only) failed
/// somewhere: certificate 1 needs min |x| (exact sums, e.g. of a few terms of similar
/// size), so a second pass over the pairs forms the lower bounds m' = fl(W_a·M_b).
#[cold]
#[inline(never)]
#[target_feature(enable = "avx2")]
unsafe fn velocity_gradient_min(sim: &Simulation<D3>, i: usize, acc: &[Acc4sc; 3], vmax: __m256d, gsum: __m256d, n2: __m256d) -> Option<Tensor3> {
    let pairs = &sim.pairs;
    let vel = sim.nodes.fields[0].vel.as_ptr() as *const f64;
    let (node, g) = (pairs.node.as_ptr(), pairs.g.as_ptr() as *const f64);
    let sign = _mm256_set1_pd(-0.0);
    let (mut vmin, mut gmin) = (_mm256_set1_pd(f64::INFINITY), _mm256_set1_pd(f64::INFINITY));
    for k in pairs.of_particle(i) {
        let n = *node.add(k) as usize;
        vmin = _mm256_min_pd(vmin, _mm256_andnot_pd(sign, load3(vel.add(3 * n))));
        gmin = _mm256_min_pd(gmin, _mm256_andnot_pd(sign, load3(g.add(3 * k))));
    }
    let mut wx = [0.0; 4];
    _mm256_storeu_pd(wx.as_mut_ptr(), vmin);
    certify_rows(acc, vmax, gsum, [0, 1, 2].map(|r| _mm256_mul_pd(_mm256_set1_pd(wx[r]), gmin)), n2)
}

/// `particle_increments::<Fast, false>` of particle `i`: lanes S·v and S·a.
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn particle_increments(sim: &Simulation<D3>, i: usize) -> Option<(Vector3, Vector3)> {
    let pairs = &sim.pairs;
    let k = pairs.of_particle(i);
    let fa = &sim.nodes.fields[0];
    let (vel, accel) = (fa.vel.as_ptr() as *const f64, fa.acc.as_ptr() as *const f64);
    let (node, s) = (pairs.node.as_ptr(), pairs.s.as_ptr());
    let mut acc = [Acc4::new(); 2];
    for k in k.clone() {
        let n = *node.add(k) as usize;
        debug_assert!(n < fa.vel.len() && n < fa.acc.len());
        let w = _mm256_broadcast_sd(&*s.add(k));
        acc[0].add(_mm256_mul_pd(w, load3(vel.add(3 * n))));
        acc[1].add(_mm256_mul_pd(w, load3(accel.add(3 * n))));
    }
    let [v, w] = Acc4::certified(k.len(), 3, &acc)?;
    Some((Vector3::new(v[0], v[1], v[2]), Vector3::new(w[0], w[1], w[2])))
}

/// The uGIMP weights of a 3D particle ([`crate::shape::weights_into_3d`] with
/// `ShapeKind::Ugimp`), its 1D part on the three axes at once: the candidate nodes of
/// `shape::axis_weights` (⌊(x ∓ l_p − x₀)/h⌋ with the neighbours of near-integer
/// quotients, clipped to the grid) and `shape::ugimp_1d` at each of them, its three
/// branches as selects (the same expressions on the same operands, so the same values),
/// then the first three non-zero weights per axis in node order, and the tensor product
/// by `shape::tensor_product_3d` itself. Integers are carried as doubles, exactly: the
/// quotients are checked to lie within ±2^30 (else, and when an axis has more than five
/// candidates, the scalar code runs), so ⌊q⌋ as a double is the integer the scalar code
/// computes and the candidates' indices are exact.
#[target_feature(enable = "avx2")]
#[inline]
pub(crate) unsafe fn weights_ugimp(
    grid: &crate::grid::Grid3,
    x: &Vector3,
    lp: &Vector3,
    node: &mut [u32; crate::shape::MAX_NODES_3D],
    s: &mut [f64; crate::shape::MAX_NODES_3D],
    g: &mut [Vector3; crate::shape::MAX_NODES_3D],
) -> usize {
    let v3 = |v: &Vector3, pad: f64| _mm256_setr_pd(v.x, v.y, v.z, pad);
    let (xv, x0, h, l) = (v3(x, 0.0), v3(&grid.origin, 0.0), v3(&grid.h, 1.0), v3(lp, 0.0));
    let cells = _mm256_setr_pd(grid.n[0] as f64, grid.n[1] as f64, grid.n[2] as f64, 0.0);
    let one = _mm256_set1_pd(1.0);
    // (x − reach − x₀)/h and (x + reach − x₀)/h, reach = l_p.
    let ql = _mm256_div_pd(_mm256_sub_pd(_mm256_sub_pd(xv, l), x0), h);
    let qh = _mm256_div_pd(_mm256_sub_pd(_mm256_add_pd(xv, l), x0), h);
    let lim = _mm256_set1_pd((1u64 << 30) as f64);
    let abs = |v: __m256d| _mm256_andnot_pd(_mm256_set1_pd(-0.0), v);
    let sane = _mm256_and_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(abs(ql), lim), _mm256_cmp_pd::<_CMP_LT_OQ>(abs(qh), lim));
    // lo = ⌊ql⌋, hi − 1 = ⌊qh⌋; first = (lo − 1 if ql − lo < EDGE else lo) ∨ 0, last = (hi + 1
    // if qh − (hi − 1) > 1 − EDGE else hi) ∧ n_cells, as `axis_weights` has them.
    let lo = _mm256_floor_pd(ql);
    let fq = _mm256_floor_pd(qh);
    let first = _mm256_max_pd(_mm256_blendv_pd(lo, _mm256_sub_pd(lo, one), _mm256_cmp_pd::<_CMP_LT_OQ>(_mm256_sub_pd(ql, lo), _mm256_set1_pd(crate::shape::EDGE))), _mm256_setzero_pd());
    let hi = _mm256_add_pd(fq, one);
    let last = _mm256_min_pd(_mm256_blendv_pd(hi, _mm256_add_pd(hi, one), _mm256_cmp_pd::<_CMP_GT_OQ>(_mm256_sub_pd(qh, fq), _mm256_set1_pd(1.0 - crate::shape::EDGE))), cells);
    let span = _mm256_sub_pd(last, first);
    let few = _mm256_cmp_pd::<_CMP_LE_OQ>(span, _mm256_set1_pd(4.0));
    if _mm256_movemask_pd(_mm256_and_pd(sane, few)) & 7 != 7 {
        return crate::shape::weights_into_3d(grid, crate::shape::ShapeKind::Ugimp, x, lp, node, s, g);
    }
    // Candidates per axis: last − first + 1 ≤ 5 (integers in [−2^31, 2^31) here).
    let mut firsts = [0i32; 4];
    _mm_storeu_si128(firsts.as_mut_ptr() as *mut __m128i, _mm256_cvttpd_epi32(first));
    let mut spans = [0i32; 4];
    _mm_storeu_si128(spans.as_mut_ptr() as *mut __m128i, _mm256_cvttpd_epi32(span));
    let candidates = (spans[0].max(spans[1]).max(spans[2]) + 1).max(0) as usize;
    // ugimp_1d's constants: 2h·l_p, h·l_p, 4h·l_p, h − l_p, h + l_p.
    let two_hl = _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(2.0), h), l);
    let hl = _mm256_mul_pd(h, l);
    let four_hl = _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(4.0), h), l);
    let (h_minus, h_plus) = (_mm256_sub_pd(h, l), _mm256_add_pd(h, l));
    let ll = _mm256_mul_pd(l, l);
    // −sgn/h = ±(1/h): (±1)/h rounds as 1/h does, with the sign.
    let inv_h = _mm256_div_pd(one, h);
    let zero = _mm256_setzero_pd();
    let mut sv = [[0.0; 4]; 5];
    let mut dv = [[0.0; 4]; 5];
    let mut keep = [0i32; 5];
    for j in 0..candidates {
        let i = _mm256_add_pd(first, _mm256_set1_pd(j as f64));
        let valid = _mm256_cmp_pd::<_CMP_LE_OQ>(i, last);
        // ξ = x − (x₀ + i·h).
        let xi = _mm256_sub_pd(xv, _mm256_add_pd(x0, _mm256_mul_pd(i, h)));
        let a = abs(xi);
        let negative = _mm256_cmp_pd::<_CMP_LT_OQ>(xi, zero);
        let neg_sgn = _mm256_blendv_pd(_mm256_set1_pd(-1.0), one, negative);
        // a < l_p: (1 − (a² + l_p²)/(2h·l_p), −ξ/(h·l_p)).
        let s1 = _mm256_sub_pd(one, _mm256_div_pd(_mm256_add_pd(_mm256_mul_pd(a, a), ll), two_hl));
        let d1 = _mm256_div_pd(_mm256_xor_pd(xi, _mm256_set1_pd(-0.0)), hl);
        // a ≤ h − l_p: (1 − a/h, −sgn/h).
        let s2 = _mm256_sub_pd(one, _mm256_div_pd(a, h));
        let d2 = _mm256_blendv_pd(_mm256_xor_pd(inv_h, _mm256_set1_pd(-0.0)), inv_h, negative);
        // a < h + l_p: d = h + l_p − a, (d²/(4h·l_p), −sgn·d/(2h·l_p)).
        let d = _mm256_sub_pd(h_plus, a);
        let s3 = _mm256_div_pd(_mm256_mul_pd(d, d), four_hl);
        let d3 = _mm256_div_pd(_mm256_mul_pd(neg_sgn, d), two_hl);
        let (b1, b2, b3) = (_mm256_cmp_pd::<_CMP_LT_OQ>(a, l), _mm256_cmp_pd::<_CMP_LE_OQ>(a, h_minus), _mm256_cmp_pd::<_CMP_LT_OQ>(a, h_plus));
        let sj = _mm256_blendv_pd(_mm256_blendv_pd(_mm256_and_pd(b3, s3), s2, b2), s1, b1);
        let dj = _mm256_blendv_pd(_mm256_blendv_pd(_mm256_and_pd(b3, d3), d2, b2), d1, b1);
        _mm256_storeu_pd(sv[j].as_mut_ptr(), sj);
        _mm256_storeu_pd(dv[j].as_mut_ptr(), dj);
        // `v.0 != 0.0` (true for NaN, as there).
        keep[j] = _mm256_movemask_pd(_mm256_and_pd(valid, _mm256_cmp_pd::<_CMP_NEQ_UQ>(sj, zero)));
    }
    let mut w = [[(0.0, 0.0); 3]; 3];
    let mut idx = [[0usize; 3]; 3];
    let mut k = [0usize; 3];
    for c in 0..3 {
        let first = firsts[c] as usize;
        for j in 0..candidates {
            if k[c] < 3 && keep[j] & (1 << c) != 0 {
                w[c][k[c]] = (sv[j][c], dv[j][c]);
                idx[c][k[c]] = first + j;
                k[c] += 1;
            }
        }
    }
    tensor_product(grid, &w, &idx, k, node, s, g)
}

/// `shape::tensor_product_3d` with each x-run of up to three nodes as one vector: the
/// same products in the same grouping, S = (Sx·Sy)·Sz and G = ((S'x·Sy)·Sz, (Sx·S'y)·Sz,
/// (Sx·Sy)·S'z), lane by lane, so the same bits (`tests::weights_ugimp_matches_the_scalar_weights`).
/// The run's S and its G (interleaved x, y, z per node by shuffles) are written with
/// whole-vector stores into padded local buffers (a lane past the run is overwritten by the
/// next run or never read), then copied out whole: AMD's masked
/// stores (`vmaskmovpd`) are microcoded and cost more than the tensor product itself.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn tensor_product(
    grid: &crate::grid::Grid3,
    w: &[[(f64, f64); 3]; 3],
    idx: &[[usize; 3]; 3],
    k: [usize; 3],
    node: &mut [u32; crate::shape::MAX_NODES_3D],
    s: &mut [f64; crate::shape::MAX_NODES_3D],
    g: &mut [Vector3; crate::shape::MAX_NODES_3D],
) -> usize {
    let (sy_stride, sz_stride) = (grid.n[0] + 1, (grid.n[0] + 1) * (grid.n[1] + 1));
    let (kx, ky, kz) = (k[0].min(3), k[1].min(3), k[2].min(3));
    if kx == 0 {
        return 0;
    }
    let sx = _mm256_setr_pd(w[0][0].0, w[0][1].0, w[0][2].0, 0.0);
    let dx = _mm256_setr_pd(w[0][0].1, w[0][1].1, w[0][2].1, 0.0);
    // Room for a whole vector past the last run (S: 27 + 3; G: 81 + 3).
    let mut sbuf = [0.0f64; crate::shape::MAX_NODES_3D + 3];
    let mut gbuf = [0.0f64; 3 * crate::shape::MAX_NODES_3D + 3];
    let (sp, gp) = (sbuf.as_mut_ptr(), gbuf.as_mut_ptr());
    let mut n = 0;
    for cz in 0..kz {
        let (sz, dz) = w[2][cz];
        let (sz, dz) = (_mm256_set1_pd(sz), _mm256_set1_pd(dz));
        let zbase = idx[2][cz] * sz_stride;
        for b in 0..ky {
            let (sy, dy) = w[1][b];
            let (sy, dy) = (_mm256_set1_pd(sy), _mm256_set1_pd(dy));
            let base = zbase + idx[1][b] * sy_stride;
            for a in 0..kx {
                node[n + a] = (base + idx[0][a]) as u32;
            }
            let sxy = _mm256_mul_pd(sx, sy);
            let gx = _mm256_mul_pd(_mm256_mul_pd(dx, sy), sz);
            let gy = _mm256_mul_pd(_mm256_mul_pd(sx, dy), sz);
            let gz = _mm256_mul_pd(sxy, dz);
            // n + kx ≤ 27 entries of S, 3(n + kx) ≤ 81 doubles of G: a vector stored at n
            // (S) or at 3n + 4j, j < 3 (G), ends inside the padded buffers.
            _mm256_storeu_pd(sp.add(n), _mm256_mul_pd(sxy, sz));
            let t0 = _mm256_unpacklo_pd(gx, gy); // x0 y0 x2 y2
            let t1 = _mm256_unpackhi_pd(gx, gy); // x1 y1 x3 y3
            let u = _mm256_unpacklo_pd(gz, t1); // z0 x1 z2 x3
            let v = _mm256_unpackhi_pd(t1, gz); // y1 z1 y3 z3
            let out = [
                _mm256_permute2f128_pd::<0x20>(t0, u), // x0 y0 z0 x1
                _mm256_permute2f128_pd::<0x30>(v, t0), // y1 z1 x2 y2
                _mm256_permute2f128_pd::<0x01>(gz, gz), // z2 …
            ];
            for (j, o) in out.iter().enumerate() {
                // Only vectors with a lane of the run (so the pointer stays inside the buffer).
                if 3 * kx > 4 * j {
                    _mm256_storeu_pd(gp.add(3 * n + 4 * j), *o);
                }
            }
            n += kx;
        }
    }
    // Whole strides (fixed sizes: inline vector moves, no call); entries past n are never read.
    s.copy_from_slice(&sbuf[..crate::shape::MAX_NODES_3D]);
    std::ptr::copy_nonoverlapping(gbuf.as_ptr(), g.as_mut_ptr() as *mut f64, 3 * crate::shape::MAX_NODES_3D);
    n
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::Grid3;
    use crate::shape::{weights_into_3d, ShapeKind, MAX_NODES_3D};

    /// [`weights_ugimp`] gives the bits of `shape::weights_into_3d` (uGIMP): random
    /// particles, particles on lattice positions and at the very edge of a support (the
    /// near-integer quotients of `axis_weights`), the grid's faces, several l_p.
    #[test]
    fn weights_ugimp_matches_the_scalar_weights() {
        if !crate::simd::enabled() || !std::arch::is_x86_feature_detected!("avx2") {
            return;
        }
        let grid = Grid3 { origin: Vector3::new(-1.0, -12.0, 0.0), h: Vector3::new(2.0, 2.0, 1.5), n: [50, 12, 8] };
        let mut seed = 0x9e3779b97f4a7c15u64;
        let mut uniform = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut cases = 0;
        for round in 0..40_000 {
            let frac = [0.25, 0.125, 1.0 / 6.0, 0.5][round % 4];
            let lp = Vector3::new(frac * grid.h.x, frac * grid.h.y, frac * grid.h.z);
            let mut x = Vector3::zeros();
            for c in 0..3 {
                let span = grid.h[c] * grid.n[c] as f64;
                let u = uniform();
                x[c] = match (round / 4) % 4 {
                    // Anywhere.
                    0 => grid.origin[c] + lp[c] + u * (span - 2.0 * lp[c]),
                    // On a lattice position of 2 (or 1/frac/2) particles per cell.
                    1 => grid.origin[c] + grid.h[c] * ((u * grid.n[c] as f64).floor() + frac),
                    // At the edge of a support: node ± (h + l_p), nudged by a few ulps.
                    2 => {
                        let i = 1.0 + (u * (grid.n[c] - 2) as f64).floor();
                        let e = grid.origin[c] + i * grid.h[c] + if u < 0.5 { grid.h[c] + lp[c] } else { -(grid.h[c] + lp[c]) };
                        let k = (uniform() * 7.0) as i64 - 3;
                        f64::from_bits((e.to_bits() as i64 + k) as u64)
                    }
                    // Against the grid's faces.
                    _ => if u < 0.5 { grid.origin[c] + lp[c] } else { grid.origin[c] + span - lp[c] },
                };
            }
            let (mut n1, mut s1, mut g1) = ([0u32; MAX_NODES_3D], [0.0; MAX_NODES_3D], [Vector3::zeros(); MAX_NODES_3D]);
            let (mut n2, mut s2, mut g2) = (n1, s1, g1);
            let k1 = weights_into_3d(&grid, ShapeKind::Ugimp, &x, &lp, &mut n1, &mut s1, &mut g1);
            // SAFETY: the CPU has AVX2 (checked above).
            let k2 = unsafe { weights_ugimp(&grid, &x, &lp, &mut n2, &mut s2, &mut g2) };
            assert_eq!(k1, k2, "x = {x:?}, l_p = {lp:?}");
            for j in 0..k1 {
                assert_eq!(n1[j], n2[j]);
                assert_eq!(s1[j].to_bits(), s2[j].to_bits(), "x = {x:?}, l_p = {lp:?}, node {j}");
                for c in 0..3 {
                    assert_eq!(g1[j][c].to_bits(), g2[j][c].to_bits(), "x = {x:?}, l_p = {lp:?}, node {j}");
                }
            }
            cases += 1;
        }
        assert_eq!(cases, 40_000);
    }
}
