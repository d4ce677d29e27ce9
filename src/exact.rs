//! Correctly rounded, order-independent summation.
//!
//! Every sum over particles into a node, and over nodes into a particle, goes through
//! [`ExactSum`]. The result is the exact sum of the terms rounded once to the nearest
//! f64 (ties to even), so it does not depend on the order of the terms. Three things
//! follow, and the verification suite relies on all three:
//!
//! * mirrored particles give mirrored sums to the bit (round-to-nearest is symmetric, so
//!   the sum of negated terms is the negated sum), which makes the crack-patch test of
//!   Nairn 2003 §3.1 exact;
//! * shuffling the particles does not change a single bit;
//! * any number of threads gives the same bits as one.
//!
//! A correctly rounded sum is unique, so *how* it is computed does not show in the bits.
//! [`ExactSum`] uses two algorithms:
//!
//! * **Fast path: a 128-bit fixed-point accumulator.** A finite non-zero double is
//!   x = ±M·2^(E−1075) with an integer significand M < 2^53 and E its biased exponent
//!   (E = 1 for subnormals, whose M has no implicit bit). While all non-zero terms have
//!   exponents in a window [base, top] with top − base ≤ [`SPAN`] = 64, at most
//!   [`MAX_TERMS`] = 1024 of them, and base ≥ 53, top ≤ 2000, the accumulator keeps the
//!   *exact* integer `acc` = Σ ±M_i·2^(E_i − base), so that the exact sum is
//!   acc·2^(base−1075). Proof that nothing is lost:
//!   - every term is an integer multiple of 2^(base−1075) (its ulp is 2^(E_i−1075) and
//!     E_i ≥ base), so acc is an integer;
//!   - |acc| ≤ Σ (2^53 − 1)·2^(E_i − base) < n·2^(53+SPAN) ≤ 2^10·2^117 = 2^127, so no
//!     partial sum overflows an i128 (the bound holds for every prefix, and when a new
//!     smaller term lowers `base`, acc is shifted left by the difference, which keeps
//!     the same bound with the new span);
//!   - the result is `(acc as f64) · 2^(base−1075)`. Rust's integer-to-float cast rounds
//!     to nearest, ties to even (the Reference, "numeric cast"), and multiplying by a
//!     power of two is exact and commutes with that rounding as long as the result is a
//!     normal number: it is, since |acc| ≥ 1 gives |result| ≥ 2^(base−1075) ≥ 2^−1022
//!     (base ≥ 53), and |result| ≤ 2^127·2^(2000−1075) is far from overflow. So the
//!     result is the exact sum correctly rounded.
//!
//!   An addition costs a few integer instructions and no data-dependent loop; the
//!   accumulator needs no memory beyond itself.
//! * **Fallback: a full-range fixed-point accumulator** (`Wide`): the exact sum as an
//!   integer in units of 2^−1074 (the ulp of every double), 68 signed 64-bit limbs
//!   holding 32-bit digits (carry-save), rounded once to nearest, ties to even, when read
//!   — overflowing to ±∞ like IEEE addition. Used when a term falls outside the window
//!   (terms over more than 64 binades, as ahead of a wave front, subnormal-range terms,
//!   huge terms, more than 1024 terms). On switching, the window's value is handed over
//!   exactly. Its size is fixed (no heap: the time step does not allocate, see
//!   `tests/no_alloc.rs`); an `ExactSum` that never leaves the window does not even
//!   initialise it. (Until issue 6 the fallback was Shewchuk's (1997) expansion with
//!   `math.fsum`'s final correction, whose partials live in a `Vec` — one allocation per
//!   fallback sum, and more than 64 partials for terms decaying over hundreds of
//!   binades. Both are correctly rounded, so the bits are the same; the tests compare
//!   them.)
//!
//! Signed zeros are reproduced too: an exact zero is −0 if every term was −0 (and
//! there was at least one), +0 otherwise, as IEEE addition in any order gives. A
//! non-finite term makes the result the (order-independent) IEEE sum of the non-finite
//! terms: NaN or ±∞, which the checked mode reports.
//!
//! The tests below check both paths against an independent big-integer reference
//! (random terms over many binades, cancellations, ties to even, subnormals, signed
//! zeros, and the switch between the paths).

use std::mem::MaybeUninit;

/// Widest exponent span of the fixed-point window (binades between the smallest and the
/// largest term's least significant bit).
pub const SPAN: i32 = 64;
/// Most terms the fixed-point window accepts (with [`SPAN`], |acc| < 2^127).
pub const MAX_TERMS: u32 = 1024;
/// Smallest biased exponent in the window: 2^(53−1075) = 2^−1022, so the result is normal.
const MIN_EXP: i32 = 53;
/// Largest biased exponent in the window (terms below 2^978): no overflow anywhere.
const MAX_EXP: i32 = 2000;

const SIGN_BIT: u64 = 1 << 63;
const FRAC_MASK: u64 = (1 << 52) - 1;
const IMPLICIT_BIT: u64 = 1 << 52;

/// 2^k for −1022 ≤ k ≤ 1023, exactly.
#[inline(always)]
const fn pow2(k: i32) -> f64 {
    debug_assert!(-1022 <= k && k <= 1023);
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// An exact accumulator: add terms in any order, read the correctly rounded sum.
///
/// Reuse one accumulator for many sums with [`ExactSum::clear`]. It never allocates: the
/// full-range fallback (see the module documentation) is stored inline, and initialised
/// only when a sum needs it.
#[derive(Clone, Debug)]
pub struct ExactSum {
    /// Fixed-point sum of the non-zero finite terms: exact value acc·2^(base−1075).
    acc: i128,
    /// Smallest biased exponent (≥ 1) of a non-zero term so far: the scale of `acc`.
    base: i32,
    /// Largest biased exponent of a non-zero term so far.
    top: i32,
    /// Non-zero finite terms in `acc`.
    n: u32,
    /// Finite terms seen (zeros included), for the sign of an exact zero.
    finite_terms: u32,
    /// Every finite term so far was −0.
    all_neg_zero: bool,
    /// The fixed-point window was left: `wide` holds the sum (`slow` ⇔ `wide.is_some()`).
    slow: bool,
    /// The full-range accumulator (fallback only; `None` costs no initialisation).
    wide: Option<Wide>,
    /// IEEE sum of the non-finite terms (0 when there are none): a NaN or infinity
    /// poisons the result visibly, and the checked mode reports it.
    special: f64,
}

impl Default for ExactSum {
    fn default() -> Self {
        Self::new()
    }
}

impl ExactSum {
    /// An empty accumulator (no allocation).
    #[inline]
    pub const fn new() -> Self {
        ExactSum { acc: 0, base: 0, top: 0, n: 0, finite_terms: 0, all_neg_zero: true, slow: false, wide: None, special: 0.0 }
    }

    /// Forget all terms (cheap), so one accumulator serves many sums.
    #[inline]
    pub fn clear(&mut self) {
        self.acc = 0;
        self.n = 0;
        self.finite_terms = 0;
        self.all_neg_zero = true;
        self.special = 0.0;
        if self.slow {
            self.slow = false;
            self.wide = None;
        }
    }

    /// Add one term.
    #[inline]
    pub fn add(&mut self, x: f64) {
        let bits = x.to_bits();
        let e = ((bits >> 52) & 0x7ff) as i32;
        if e == 0x7ff {
            self.special += x;
            return;
        }
        self.finite_terms += 1;
        self.all_neg_zero &= bits == SIGN_BIT;
        if bits & !SIGN_BIT == 0 {
            return; // ±0 adds nothing (its sign is tracked above)
        }
        if let Some(w) = self.wide.as_mut() {
            w.add_double(x);
            return;
        }
        // x = ±m·2^(e−1075) exactly, m < 2^53.
        let (m, e) = if e == 0 { (bits & FRAC_MASK, 1) } else { ((bits & FRAC_MASK) | IMPLICIT_BIT, e) };
        let (base, top) = if self.n == 0 { (e, e) } else { (self.base.min(e), self.top.max(e)) };
        if top - base > SPAN || self.n >= MAX_TERMS || base < MIN_EXP || top > MAX_EXP {
            self.spill().add_double(x);
            return;
        }
        if base < self.base && self.n > 0 {
            // A new smallest term: rescale. |acc| < n·2^(53+SPAN) still (see the module doc).
            self.acc <<= self.base - base;
        }
        let v = (m as i128) << (e - base);
        let neg = -((bits >> 63) as i128); // 0 or −1
        self.acc += (v ^ neg) - neg;
        self.base = base;
        self.top = top;
        self.n += 1;
    }

    /// Leave the fixed-point window: hand its exact value acc·2^(base−1075) to the wide
    /// accumulator, as three chunks of at most 43 bits of |acc| (< 2^127) at their
    /// positions (bit 0 of acc is bit base − 1 of the wide integer).
    #[cold]
    fn spill(&mut self) -> &mut Wide {
        self.slow = true;
        let (acc, base) = (self.acc, self.base);
        self.acc = 0;
        let w = self.wide.insert(Wide::new());
        if acc != 0 {
            let neg = acc < 0;
            let a = acc.unsigned_abs();
            const CHUNK: u32 = 43;
            for k in 0..3 {
                let c = ((a >> (CHUNK * k)) & ((1u128 << CHUNK) - 1)) as u64;
                if c != 0 {
                    w.add(neg, c, (base - 1) as u32 + CHUNK * k);
                }
            }
        }
        w
    }

    /// The correctly rounded sum of all terms added so far.
    #[inline]
    pub fn value(&self) -> f64 {
        if self.special != 0.0 || self.special.is_nan() {
            return self.special;
        }
        let v = match &self.wide {
            Some(w) => w.value(),
            None if self.acc == 0 => 0.0,
            // Exact: see the module documentation.
            None => return (self.acc as f64) * pow2(self.base - 1075),
        };
        if v == 0.0 {
            return if self.finite_terms > 0 && self.all_neg_zero { -0.0 } else { 0.0 };
        }
        v
    }
}

/// Limbs of `Wide`: digit k has weight 2^(32k) units of 2^−1074. A double's bits lie
/// at positions 0..2098, the chunks a spilled window hands over below 2000 − 1 + 3·43
/// < 32·67 (and their value below 2^2010), so limbs 0..67 hold every term.
const WIDE_LIMBS: usize = 68;
/// Terms between two carry normalisations of `Wide`: each changes a limb by less than
/// 2^32, so no limb exceeds 2^32 + 2^62 < 2^63.
const WIDE_BATCH: u32 = 1 << 30;

/// The exact sum of any finite doubles as an integer Σ limb[k]·2^(32k) in units of
/// 2^−1074, carry-save (limbs are signed and may leave [0, 2^32) between
/// normalisations), fixed size: the fallback of [`ExactSum`]. Only the limbs `lo..=hi`
/// that terms touched are non-zero; reading the sum visits only those (and one more).
#[derive(Clone, Debug)]
struct Wide {
    limb: [i64; WIDE_LIMBS],
    lo: usize,
    hi: usize,
    adds: u32,
}

impl Wide {
    fn new() -> Self {
        Wide { limb: [0; WIDE_LIMBS], lo: WIDE_LIMBS, hi: 0, adds: 0 }
    }

    /// Add the finite, non-zero double x = ±M·2^(E−1075) = ±M·2^(max(E,1)−1) units.
    #[inline]
    fn add_double(&mut self, x: f64) {
        let bits = x.to_bits();
        let e = ((bits >> 52) & 0x7ff) as u32;
        let (m, s) = if e == 0 { (bits & FRAC_MASK, 0) } else { ((bits & FRAC_MASK) | IMPLICIT_BIT, e - 1) };
        self.add(bits & SIGN_BIT != 0, m, s);
    }

    /// Add ±m·2^s units, m < 2^53, s < 32·66: the three 32-bit digits of m·2^(s mod 32)
    /// (< 2^85) to limbs s/32 .. s/32 + 2.
    #[inline]
    fn add(&mut self, neg: bool, m: u64, s: u32) {
        const DIGIT: u128 = 0xffff_ffff;
        let (q, r) = ((s / 32) as usize, s % 32);
        let v = (m as u128) << r;
        let d = [(v & DIGIT) as i64, ((v >> 32) & DIGIT) as i64, (v >> 64) as i64];
        for (l, d) in self.limb[q..q + 3].iter_mut().zip(d) {
            if neg {
                *l -= d;
            } else {
                *l += d;
            }
        }
        self.lo = self.lo.min(q);
        self.hi = self.hi.max(q + 2);
        self.adds += 1;
        if self.adds == WIDE_BATCH {
            carry(&mut self.limb, 0, WIDE_LIMBS - 1);
            (self.lo, self.hi, self.adds) = (0, WIDE_LIMBS - 1, 0);
        }
    }

    /// The exact sum rounded to nearest, ties to even (+0 for an exact zero; ±∞ beyond
    /// the largest double, as IEEE rounding gives).
    fn value(&self) -> f64 {
        if self.lo > self.hi {
            return 0.0;
        }
        // Carry the touched limbs into the next one, `top`, which keeps the sign: the
        // limbs below it are digits in [0, 2^32), worth less than one unit of `top`.
        let (lo, top) = (self.lo, (self.hi + 1).min(WIDE_LIMBS - 1));
        let mut l = self.limb;
        carry(&mut l, lo, top);
        let neg = l[top] < 0;
        if neg {
            l[lo..=top].iter_mut().for_each(|x| *x = -*x);
            carry(&mut l, lo, top);
        }
        let Some(t) = l[..=top].iter().rposition(|&x| x != 0) else { return 0.0 };
        // The top three limbs (zeros below limb 0): w < 2^127 (limb t < 2^63, the ones
        // below are digits), and the integer has b = 32(t − 2) + bit length of w bits.
        let get = |k: Option<usize>| k.map_or(0, |k| l[k] as u128);
        let w = (get(Some(t)) << 64) | (get(t.checked_sub(1)) << 32) | get(t.checked_sub(2));
        let bw = 128 - w.leading_zeros() as i64;
        let b = 32 * (t as i64 - 2) + bw;
        let magnitude = if b <= 53 {
            // An integer below 2^53 (t ≤ 1): exact, times 2^−1074 exactly.
            let v = ((l[1] as u64) << 32) | l[0] as u64;
            v as f64 * f64::from_bits(1)
        } else {
            // 53 bits, the rounding bit, and whether anything below it is non-zero
            // (bw ≥ 65 here, so the shift is at least 11).
            let sh = (bw - 54) as u32;
            let top = (w >> sh) as u64;
            let sticky = w & ((1u128 << sh) - 1) != 0 || l[..t.saturating_sub(2)].iter().any(|&x| x != 0);
            let mut mant = top >> 1;
            if top & 1 == 1 && (sticky || mant & 1 == 1) {
                mant += 1;
            }
            // mant·2^(b−53) units with mant in [2^52, 2^53]: biased exponent b − 52.
            let mut biased = b - 52;
            if mant == 1 << 53 {
                mant >>= 1;
                biased += 1;
            }
            if biased >= 0x7ff {
                f64::INFINITY
            } else {
                f64::from_bits(((biased as u64) << 52) | (mant & FRAC_MASK))
            }
        };
        if neg {
            -magnitude
        } else {
            magnitude
        }
    }
}

/// Propagate the carries of limbs `lo..top` into `top`: each of them into [0, 2^32),
/// `top` keeps the sign (same value).
#[inline]
fn carry(l: &mut [i64; WIDE_LIMBS], lo: usize, top: usize) {
    for k in lo..top {
        let c = l[k] >> 32;
        l[k] -= c << 32;
        l[k + 1] += c;
    }
}

/// Something that sums N quantities term by term (the N components a gather produces
/// per particle/node pair): [`ExactSums`] (always correctly rounded) or [`FastSum`]
/// (correctly rounded when it can prove it). The hot gathers are written once, generic
/// over this trait, run with [`FastSum`], and rerun with [`ExactSums`] in the rare case
/// that the fast sum cannot certify a result — so every result is the correctly rounded
/// sum either way, to the bit.
pub trait Accumulator<const N: usize>: Default {
    fn add(&mut self, x: [f64; N]);
    /// The correctly rounded sums, or None if this accumulator cannot guarantee them.
    fn certified(&self) -> Option<[f64; N]>;
}

/// N independent [`ExactSum`]s.
#[derive(Clone, Debug)]
pub struct ExactSums<const N: usize>(pub [ExactSum; N]);

impl<const N: usize> Default for ExactSums<N> {
    fn default() -> Self {
        ExactSums(std::array::from_fn(|_| ExactSum::new()))
    }
}

impl<const N: usize> Accumulator<N> for ExactSums<N> {
    #[inline]
    fn add(&mut self, x: [f64; N]) {
        for (s, x) in self.0.iter_mut().zip(x) {
            s.add(x);
        }
    }
    #[inline]
    fn certified(&self) -> Option<[f64; N]> {
        Some(std::array::from_fn(|k| self.0[k].value()))
    }
}

/// Terms a [`Rerun`] keeps (a 3D uGIMP node has up to 125 pairs at 2 particles per cell
/// and direction, 216 at 3; a 2D node up to 36).
const RERUN_TERMS: usize = 256;

/// The accumulator of a gather's rerun ([`Exact`]), when its [`FastSum`] could not
/// certify every lane: the fast sums of every lane again, one more level of compensation
/// ([`FastSum3`]), and the terms themselves. At the end each lane takes the first of: the
/// fast sum's certificates (`certify`), the three-level certificates (`certify3`), the
/// exact sum of its kept terms ([`ExactSum`]). The lanes the fast sum cannot certify are
/// nearly always sums that cancel to zero or to the round-off of their terms (the nodes
/// on the mirror planes of a symmetric scene); the third level certifies those without
/// the exact sum, which costs several times more per term. Every certified value and the
/// exact sum are the correctly rounded sum, so which one a lane used does not show in the
/// bits. Past [`RERUN_TERMS`] terms every lane is summed exactly. Fixed size, no
/// allocation.
#[derive(Clone)]
pub struct Rerun<const N: usize> {
    fast: FastSum3<N>,
    /// Terms kept so far: `terms[..len]` are written.
    len: usize,
    /// Not initialised beyond `len`: zeroing this (8 KB for four lanes) for every
    /// accumulator of every rerun cost more than the exact sums it saves.
    terms: [MaybeUninit<[f64; N]>; RERUN_TERMS],
    /// Every lane's exact sum, once the terms outnumber `terms`.
    spilled: Option<ExactSums<N>>,
}

impl<const N: usize> Default for Rerun<N> {
    #[inline]
    fn default() -> Self {
        Rerun { fast: FastSum3::default(), len: 0, terms: [MaybeUninit::uninit(); RERUN_TERMS], spilled: None }
    }
}

impl<const N: usize> Rerun<N> {
    /// The terms kept so far.
    #[inline]
    fn kept(&self) -> &[[f64; N]] {
        // SAFETY: `add` writes terms[k] before it makes len greater than k, and nothing
        // else changes `terms` or `len`; MaybeUninit<T> has the layout of T.
        unsafe { std::slice::from_raw_parts(self.terms.as_ptr().cast::<[f64; N]>(), self.len) }
    }
}

impl<const N: usize> Accumulator<N> for Rerun<N> {
    #[inline(always)]
    fn add(&mut self, x: [f64; N]) {
        self.fast.add(x);
        if let Some(exact) = self.spilled.as_mut() {
            exact.add(x);
        } else if self.len < RERUN_TERMS {
            self.terms[self.len].write(x);
            self.len += 1;
        } else {
            self.spill(x);
        }
    }

    fn certified(&self) -> Option<[f64; N]> {
        if let Some(exact) = &self.spilled {
            return exact.certified();
        }
        let (f, terms) = (&self.fast, self.kept());
        // f.m is the smallest non-zero |x|, which both certificates accept (see FastSum).
        Some(std::array::from_fn(|k| {
            certify(f.s[k], f.c[k], f.a[k], f.m[k], f.n)
                .or_else(|| certify3(f.s[k], f.c[k], f.d[k], f.a[k], f.m[k], f.n))
                .unwrap_or_else(|| sum_iter(terms.iter().map(|t| t[k])))
        }))
    }
}

impl<const N: usize> Rerun<N> {
    /// More terms than `terms` holds: from now on every lane is summed exactly.
    #[cold]
    #[inline(never)]
    fn spill(&mut self, x: [f64; N]) {
        let mut exact = ExactSums::default();
        self.kept().iter().chain([&x]).for_each(|&t| exact.add(t));
        self.spilled = Some(exact);
    }
}

/// [`FastSum`] with one more level of compensation: the errors t_i of the running sum s
/// are themselves summed with TwoSum into c (the same c as [`FastSum`]'s, to the bit),
/// and the errors e_i of that sum in plain floating point into d. Then the exact sum is
/// T = s + c + Σe_i, and the error of s + c + d is of order n³u³Σ|x| instead of n²u²Σ|x|
/// (see `certify3`). Used only in a gather's rerun ([`Rerun`]).
#[derive(Clone, Copy, Debug)]
pub struct FastSum3<const N: usize> {
    s: [f64; N],
    c: [f64; N],
    d: [f64; N],
    a: [f64; N],
    m: [f64; N],
    n: u32,
}

impl<const N: usize> Default for FastSum3<N> {
    #[inline]
    fn default() -> Self {
        FastSum3 { s: [-0.0; N], c: [0.0; N], d: [0.0; N], a: [0.0; N], m: [f64::INFINITY; N], n: 0 }
    }
}

impl<const N: usize> Accumulator<N> for FastSum3<N> {
    #[inline(always)]
    fn add(&mut self, x: [f64; N]) {
        for k in 0..N {
            let (s0, x) = (self.s[k], x[k]);
            let s = s0 + x;
            let bb = s - s0;
            let t = (s0 - (s - bb)) + (x - bb);
            self.s[k] = s;
            let c0 = self.c[k];
            let c = c0 + t;
            let bc = c - c0;
            self.d[k] += (c0 - (c - bc)) + (t - bc);
            self.c[k] = c;
            let ax = x.abs();
            self.a[k] += ax;
            // The smallest non-zero |x|: a zero term is a multiple of every power of two,
            // so it does not lower q (the smallest ulp among the non-zero terms) and need
            // not disable certificate 1 here (the zeros of clamped nodes and of gradient
            // components at a node's coordinate would).
            self.m[k] = if ax < self.m[k] && ax != 0.0 { ax } else { self.m[k] };
        }
        self.n += 1;
    }

    /// Each lane by the certificates of [`FastSum`] (on the same s and c) or else those of
    /// `certify3`; None if some lane passes neither (the gather then runs with [`Exact`]).
    fn certified(&self) -> Option<[f64; N]> {
        let mut out = [0.0; N];
        for (k, o) in out.iter_mut().enumerate() {
            *o = certify(self.s[k], self.c[k], self.a[k], self.m[k], self.n).or_else(|| certify3(self.s[k], self.c[k], self.d[k], self.a[k], self.m[k], self.n))?;
        }
        Some(out)
    }
}

/// A compensated sum that certifies correct rounding: the fast path of the gathers.
///
/// Per term, Knuth's TwoSum (error-free: s + x = s' + t exactly, for all finite inputs
/// barring overflow, subnormals included) updates the running sum s and its error t; the
/// errors are summed in plain floating point into c, Σ|x| into a, and the smallest |x|
/// is kept in m: a dozen flops, no branches. Then the exact sum is
/// T = s + Σt_i, and (Higham, Accuracy and Stability, §4.2 and §4.3, γ_k = ku/(1−ku),
/// u = 2^−53):
///
/// * |t_i| ≤ u|s_i| and |s_i| ≤ (1+u)^i A with A = Σ|x_i|, so Σ|t_i| ≤ n u (1+u)^n A;
/// * the recursive sum c of the t_i has |c − Σt_i| ≤ γ_{n−1} Σ|t_i|;
/// * the computed a ≥ (1 − γ_{n−1}) A.
///
/// Hence for n ≤ 2^20 the error δ := |T − (s + c)| ≤ n² u² a (1 + 10⁻⁵) < 2 n² u² a, and
/// the computed bound `db` = fl(n²·(2^−104·a)) ≥ 4n²u²a(1−u) > δ (n² and 2^−104·a are
/// exact when a ≥ 2^−800, so there is one rounding). r = fl(s + c) is then certified to
/// be the correctly rounded T in either of two ways:
///
/// 1. **δ = 0.** All terms, s, every t_i and every partial sum of c are multiples of
///    q = the smallest ulp among the terms (a rounded sum of multiples of a power of two
///    q is again one), so T − (s + c) is a multiple of q. With all terms normal, the
///    smallest term's ulp exceeds m·2^−53, and ulps grow with magnitude, so q > m·2^−53.
///    (A zero term gives m = 0 and this certificate is not used. Zero terms are
///    multiples of every q, so the argument holds as well with m the smallest non-zero
///    |x|, which the reruns' [`FastSum3`] tracks; the fast sum saves that test.)
///    If db < m·2^−53 (exact, m ≥ 2^−900), then |T − (s + c)| < q forces T = s + c, and
///    r = fl(s + c) is the correctly rounded T by IEEE addition itself — ties to even
///    included, and an exact zero comes out +0 as it must with non-zero terms (c is never
///    −0, so s + c is not −0 + −0). This covers the frequent exact ties of a few terms of
///    similar size, and the exact cancellations of mirror-symmetric scenes.
/// 2. **T is strictly nearer r than any other double.** With TwoSum once more,
///    s + c = r + t₂ exactly, so |T − r| ≤ |t₂| + δ. If |r| ≥ 2^−900, its neighbours are
///    U = ulp(r) away, or U/2 towards zero when |r| is a power of two; with h = U/2, or
///    U/4 at a power of two, |T − r| < h is enough. The test `2·db < fl(h − |t₂|)`
///    implies δ < h − |t₂| (the subtraction rounds up by at most a factor 1 + u).
///
/// Otherwise (None) the gather is redone with [`ExactSum`]: non-finite terms, Σ|x|
/// outside [2^−800, 2^1000] (so nothing underflows or overflows), more than 2^20 terms,
/// and sums that are both inexact at the last bit and within δ of a rounding boundary
/// — rare unless the terms span more than ~10¹² in magnitude.
///
/// All-zero sums are certified: s starts at −0, so s is the IEEE sum of the zeros (−0
/// only if every term is −0), as for [`ExactSum`]; no terms give +0.
///
/// The N lanes are independent sums sharing the term count; the lane-wise operations
/// on `[f64; N]` let the compiler use SIMD registers for them.
#[derive(Clone, Copy, Debug)]
pub struct FastSum<const N: usize> {
    s: [f64; N],
    c: [f64; N],
    a: [f64; N],
    m: [f64; N],
    n: u32,
}

impl<const N: usize> Default for FastSum<N> {
    #[inline]
    fn default() -> Self {
        FastSum { s: [-0.0; N], c: [0.0; N], a: [0.0; N], m: [f64::INFINITY; N], n: 0 }
    }
}

impl<const N: usize> Accumulator<N> for FastSum<N> {
    #[inline(always)]
    fn add(&mut self, x: [f64; N]) {
        for k in 0..N {
            let (s0, x) = (self.s[k], x[k]);
            let s = s0 + x;
            let bb = s - s0;
            let t = (s0 - (s - bb)) + (x - bb);
            self.s[k] = s;
            self.c[k] += t;
            let ax = x.abs();
            self.a[k] += ax;
            // A zero term makes m = 0, which only disables certificate 1. Written as a
            // select, not a conditional store, so it compiles to one minpd (which keeps m
            // when ax is NaN, as this comparison does).
            self.m[k] = if ax < self.m[k] { ax } else { self.m[k] };
        }
        self.n += 1;
    }

    /// Both certificates of `certify` for all lanes at once, without branches (the same
    /// tests on the same values, so the same verdicts; the half gap of `half_gap` is built
    /// from r's bits, which vectorises): one branch on the conjunction, and the rerun
    /// (None) if any lane fails both.
    #[inline(always)]
    fn certified(&self) -> Option<[f64; N]> {
        let n = self.n;
        if n == 0 {
            return Some([0.0; N]);
        }
        if n > 1 << 20 {
            return None;
        }
        let nf = n as f64;
        let n2 = nf * nf;
        let mut out = [0.0; N];
        let mut ok = true;
        for (k, o) in out.iter_mut().enumerate() {
            let (s, c, a, m) = (self.s[k], self.c[k], self.a[k], self.m[k]);
            let db = n2 * (pow2(-104) * a);
            let (r, t2) = two_sum(s, c);
            let in_range = (a >= pow2(-800)) & (a <= pow2(1000));
            // 1. δ = 0.
            let exact = (m >= pow2(-900)) & (db < m * pow2(-53));
            // 2. Inside the rounding interval: h = 2^(k−53), or 2^(k−54) at a power of two,
            // for 2^k ≤ |r| (the exponent field minus 53 or 54; only used when |r| ≥ 2^−900,
            // so it does not underflow).
            let bits = r.to_bits() & !SIGN_BIT;
            let drop = if bits & FRAC_MASK == 0 { 54u64 << 52 } else { 53u64 << 52 };
            let h = f64::from_bits((bits & !FRAC_MASK).wrapping_sub(drop));
            let inside = (bits >= pow2(-900).to_bits()) & (2.0 * db < h - t2.abs());
            // All terms ±0: their IEEE sum s.
            let zeros = a == 0.0;
            *o = if zeros { s } else { r };
            ok &= zeros | (in_range & (exact | inside));
        }
        ok.then_some(out)
    }
}

/// The summation lanes of one gather in a dimension-generic form: `[f64; N]` with its fast
/// and exact accumulators. The generic time step names its lanes through
/// [`crate::dim::Space`] (`MassLanes` = 1 + DIM, `TensorLanes` = DIM², …), because stable
/// Rust cannot write `[f64; DIM + 1]` for a generic dimension.
pub trait Lanes: Copy + Default + Send + Sync + std::ops::Index<usize, Output = f64> + std::ops::IndexMut<usize> + 'static {
    type Fast: LaneSum<Self>;
    type Fast3: LaneSum<Self>;
    type Exact: LaneSum<Self>;
}

/// An [`Accumulator`] seen through its lane array type.
pub trait LaneSum<L>: Default {
    fn add_lanes(&mut self, x: L);
    fn certified_lanes(&self) -> Option<L>;
}

impl<const N: usize, A: Accumulator<N>> LaneSum<[f64; N]> for A {
    #[inline(always)]
    fn add_lanes(&mut self, x: [f64; N]) {
        self.add(x)
    }
    #[inline(always)]
    fn certified_lanes(&self) -> Option<[f64; N]> {
        self.certified()
    }
}

impl<const N: usize> Lanes for [f64; N]
where
    [f64; N]: Default,
{
    type Fast = FastSum<N>;
    type Fast3 = FastSum3<N>;
    type Exact = Rerun<N>;
}

/// Which accumulator a gather runs with: [`Fast`] first, [`Exact`] when the fast one
/// cannot certify its sums.
pub trait SumKind {
    type Of<L: Lanes>: LaneSum<L>;
}

/// [`FastSum`] lanes.
pub struct Fast;
/// [`Rerun`] lanes: [`ExactSum`] where [`FastSum`] cannot certify.
pub struct Exact;
/// [`FastSum3`] lanes: for the gathers that needed [`Exact`] in the last steps (the nodes
/// on a mirror plane), which these certify without keeping the terms.
pub struct Fast3;

impl SumKind for Fast3 {
    type Of<L: Lanes> = L::Fast3;
}

impl SumKind for Fast {
    type Of<L: Lanes> = L::Fast;
}

impl SumKind for Exact {
    type Of<L: Lanes> = L::Exact;
}

/// The certificate of [`FastSum`] for one lane (see there for the proof).
#[inline]
pub(crate) fn certify(s: f64, c: f64, a: f64, m: f64, n: u32) -> Option<f64> {
    if n == 0 {
        return Some(0.0);
    }
    if a == 0.0 {
        return Some(s); // all terms ±0: the IEEE sum of the zeros
    }
    // Also rejects NaN and infinite a (non-finite terms).
    if !(a >= pow2(-800) && a <= pow2(1000)) || n > 1 << 20 {
        return None;
    }
    let nf = n as f64;
    let db = nf * nf * (pow2(-104) * a);
    let r = s + c;
    // 1. δ = 0: r is the IEEE (correctly rounded) sum of the exact value s + c.
    if m >= pow2(-900) && db < m * pow2(-53) {
        return Some(r);
    }
    // 2. T strictly inside r's rounding interval.
    let bb = r - s;
    let t2 = (s - (r - bb)) + (c - bb);
    let bits = r.to_bits() & !SIGN_BIT;
    if bits < pow2(-900).to_bits() {
        return None; // zero or tiny: leave it to the exact sum
    }
    // U = ulp(r) = 2^(k−52) for 2^k ≤ |r| < 2^(k+1); h = U/2, or U/4 at a power of two.
    let k = (bits >> 52) as i32 - 1023;
    let h = if bits & FRAC_MASK == 0 { pow2(k - 54) } else { pow2(k - 53) };
    (2.0 * db < h - t2.abs()).then_some(r)
}

/// TwoSum: (a + b rounded, its error), a + b = sum + err exactly (Knuth).
#[inline(always)]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// Half the distance from r (|r| ≥ 2^−900) to its nearest neighbour: U/2 with U = ulp(r),
/// U/4 when |r| is a power of two (its neighbour towards zero is U/2 away).
#[inline(always)]
fn half_gap(r: f64) -> f64 {
    let bits = r.to_bits() & !SIGN_BIT;
    let k = (bits >> 52) as i32 - 1023;
    if bits & FRAC_MASK == 0 {
        pow2(k - 54)
    } else {
        pow2(k - 53)
    }
}

/// The certificates of [`FastSum3`] for one lane, when those of [`FastSum`] (`certify`,
/// on the same s and c) fail.
///
/// Error bound. TwoSum is error-free, so T = s + Σt_i = s + c + Σe_i exactly. With
/// |e_i| ≤ u|c_i|, |c_i| ≤ (1+u)^i Σ_{j≤i}|t_j|, |t_j| ≤ u|s_j| and |s_j| ≤ (1+u)^j A
/// (A = Σ|x_i|), Σ|e_i| ≤ n²u²(1+u)^{2n} A; the recursive sum d has
/// |d − Σe_i| ≤ γ_{n−1} Σ|e_i|, and the computed a ≥ (1 − γ_{n−1}) A. For n ≤ 2^16 this
/// gives δ₃ := |T − (s + c + d)| < n³u³a(1 + 10⁻⁹) < 2n³u³a ≤ db₃ := fl(n³·(2^−158·a))
/// (n³ ≤ 2^48 and 2^−158·a are exact for a ≥ 2^−800, so db₃ ≥ 2n³u³a(1 − u)).
///
/// With (r₁, e₁) = TwoSum(s, c), (z, e_z) = TwoSum(e₁, d), (r, t₂) = TwoSum(r₁, z):
/// s + c + d = r + t₂ + e_z exactly, so |T − r| ≤ |t₂| + |e_z| + δ₃.
///
/// 1. **Exact.** Here m is the smallest *non-zero* |x| (zero terms are multiples of every
///    power of two). If m ≥ 2^−900 and db₃ < m·2^−53, then δ₃ < q (the smallest ulp among
///    the non-zero terms, > m·2^−53, see [`FastSum`]); s, c, d and every t_i, e_i are
///    multiples of q (a rounded sum of multiples of q is one), so T = s + c + d exactly.
///    If then e_z = 0, T = r₁ + z exactly, and r = fl(r₁ + z) is the correctly rounded
///    sum by IEEE addition itself (ties to even included); an exact zero comes out +0
///    (c is never −0, so neither are r₁ and r), as it must with a non-zero term (a > 0).
/// 2. **Inside the rounding interval.** If |r| ≥ 2^−900 and |t₂| + |e_z| + δ₃ < h (half
///    the gap to r's nearest neighbour, [`half_gap`]), r is the nearest double to T. The
///    test `fl(w·(1 + 2^−50)) < h` with w = fl(fl(|t₂| + |e_z|) + db₃) implies it: the
///    two additions of non-negative numbers lose at most a factor (1 − u)², the product
///    at most (1 − u), and (1 + 2^−50)(1 − u) > (1 − u)^−2.
///
/// Otherwise None: the exact sum decides (non-finite terms, Σ|x| outside [2^−800, 2^1000],
/// more than 2^16 terms, or a sum within δ₃ of a rounding boundary).
#[inline]
pub(crate) fn certify3(s: f64, c: f64, d: f64, a: f64, m: f64, n: u32) -> Option<f64> {
    if n == 0 || a == 0.0 {
        return certify(s, c, a, m, n);
    }
    if !(a >= pow2(-800) && a <= pow2(1000)) || n > 1 << 16 {
        return None;
    }
    let nf = n as f64;
    let db3 = (nf * nf * nf) * (pow2(-158) * a);
    let (r1, e1) = two_sum(s, c);
    let (z, ez) = two_sum(e1, d);
    let (r, t2) = two_sum(r1, z);
    // 1. T = s + c + d = r₁ + z exactly, and r = fl(r₁ + z).
    if m >= pow2(-900) && db3 < m * pow2(-53) && ez == 0.0 {
        return Some(r);
    }
    // 2. T strictly inside r's rounding interval.
    if (r.to_bits() & !SIGN_BIT) < pow2(-900).to_bits() {
        return None;
    }
    let w = (t2.abs() + ez.abs()) + db3;
    (w * (1.0 + pow2(-50)) < half_gap(r)).then_some(r)
}

/// Correctly rounded sum of a slice.
pub fn sum(terms: &[f64]) -> f64 {
    let mut s = ExactSum::new();
    for &t in terms {
        s.add(t);
    }
    s.value()
}

/// Correctly rounded sum of an iterator.
pub fn sum_iter<I: IntoIterator<Item = f64>>(terms: I) -> f64 {
    let mut s = ExactSum::new();
    for t in terms {
        s.add(t);
    }
    s.value()
}

/// Correctly rounded sum of a cloneable iterator, the same bits as [`sum_iter`], faster:
/// a [`FastSum`] pass, and an [`ExactSum`] pass over a second copy of the iterator only
/// if the fast one cannot certify its result.
pub fn sum_fast<I: Iterator<Item = f64> + Clone>(terms: I) -> f64 {
    let mut fast = FastSum::<1>::default();
    for t in terms.clone() {
        fast.add([t]);
    }
    if let Some([v]) = fast.certified() {
        return v;
    }
    let mut s = ExactSum::new();
    for t in terms {
        s.add(t);
    }
    s.value()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tiny deterministic generator so the tests need no rand crate.
    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        let m = ((*seed >> 11) as f64) / ((1u64 << 53) as f64);
        let e = ((*seed >> 3) % 40) as i32 - 20;
        (m - 0.5) * 2f64.powi(e)
    }

    fn next(seed: &mut u64) -> u64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        *seed ^ (*seed >> 29)
    }

    /// A random double with a random significand, sign and biased exponent in `exps`.
    fn random_double(seed: &mut u64, exps: std::ops::Range<u64>) -> f64 {
        let r = next(seed);
        let e = exps.start + (next(seed) % (exps.end - exps.start));
        f64::from_bits((r & SIGN_BIT) | (e << 52) | (next(seed) & FRAC_MASK))
    }

    /// The fallback cramp used before the wide accumulator (issue 6), kept to compare
    /// with: Shewchuk's `grow_expansion` with zero elimination (Python's `msum`): add `x`
    /// to the non-overlapping partials, keeping their sum exact.
    fn shewchuk_add(partials: &mut Vec<f64>, mut x: f64) {
        let mut i = 0;
        for j in 0..partials.len() {
            let mut y = partials[j];
            if x.abs() < y.abs() {
                std::mem::swap(&mut x, &mut y);
            }
            let hi = x + y;
            let lo = y - (hi - x);
            if lo != 0.0 {
                partials[i] = lo;
                i += 1;
            }
            x = hi;
        }
        partials.truncate(i);
        partials.push(x);
    }

    /// The correctly rounded sum of non-overlapping partials (increasing magnitude), with
    /// `math.fsum`'s round-half-even correction.
    fn shewchuk_value(p: &[f64]) -> f64 {
        let mut n = p.len();
        if n == 0 {
            return 0.0;
        }
        n -= 1;
        let mut hi = p[n];
        let mut lo = 0.0;
        while n > 0 {
            let x = hi;
            n -= 1;
            let y = p[n];
            hi = x + y;
            let yr = hi - x;
            lo = y - yr;
            if lo != 0.0 {
                break;
            }
        }
        // Round half to even across the remaining partials.
        if n > 0 && ((lo < 0.0 && p[n - 1] < 0.0) || (lo > 0.0 && p[n - 1] > 0.0)) {
            let y = lo * 2.0;
            let x = hi + y;
            let yr = x - hi;
            if y == yr {
                hi = x;
            }
        }
        hi
    }

    /// The summation cramp used before the fixed-point fast path (every finite term,
    /// zeros included, through Shewchuk's expansion): the fast path must agree to the bit.
    fn shewchuk_sum(terms: &[f64]) -> f64 {
        let mut special = 0.0;
        let mut partials = Vec::new();
        for &t in terms {
            if t.is_finite() {
                shewchuk_add(&mut partials, t);
            } else {
                special += t;
            }
        }
        if special != 0.0 || special.is_nan() {
            return special;
        }
        shewchuk_value(&partials)
    }

    /// Independent reference: the exact sum in a 2240-bit two's-complement fixed-point
    /// integer (bit 0 = 2^−1074, the ulp of every double), rounded to nearest, ties to
    /// even, by hand. Finite terms only; the sign of an exact zero is not decided here.
    fn reference_sum(terms: &[f64]) -> f64 {
        const LIMBS: usize = 35;
        let mut acc = [0u64; LIMBS];
        for &t in terms {
            assert!(t.is_finite());
            let bits = t.to_bits();
            let e = ((bits >> 52) & 0x7ff) as usize;
            let m = if e == 0 { bits & FRAC_MASK } else { (bits & FRAC_MASK) | IMPLICIT_BIT };
            let shift = e.max(1) - 1; // value = m·2^(shift) in units of 2^−1074
            // term as a LIMBS-word integer
            let mut w = [0u64; LIMBS];
            let (q, r) = (shift / 64, shift % 64);
            w[q] = m << r;
            if r > 0 && q + 1 < LIMBS {
                w[q + 1] = m >> (64 - r);
            }
            if bits & SIGN_BIT != 0 {
                // two's complement negation
                let mut carry = 1u64;
                for x in w.iter_mut() {
                    let (s, c) = (!*x).overflowing_add(carry);
                    *x = s;
                    carry = c as u64;
                }
            }
            let mut carry = 0u64;
            for k in 0..LIMBS {
                let (s1, c1) = acc[k].overflowing_add(w[k]);
                let (s2, c2) = s1.overflowing_add(carry);
                acc[k] = s2;
                carry = (c1 || c2) as u64;
            }
        }
        let negative = acc[LIMBS - 1] >> 63 == 1;
        if negative {
            let mut carry = 1u64;
            for x in acc.iter_mut() {
                let (s, c) = (!*x).overflowing_add(carry);
                *x = s;
                carry = c as u64;
            }
        }
        let bit = |i: usize| (acc[i / 64] >> (i % 64)) & 1;
        let Some(h) = (0..LIMBS * 64).rev().find(|&i| bit(i) == 1) else { return 0.0 };
        let magnitude = if h < 53 {
            // Exactly representable: an integer < 2^53 times 2^−1074.
            let q = (0..=h).fold(0u64, |q, i| q | (bit(i) << i));
            q as f64 * f64::from_bits(1) // 2^−1074; the product is exact
        } else {
            let lsb = h - 52;
            let mut q = (lsb..=h).fold(0u64, |q, i| q | (bit(i) << (i - lsb)));
            let half = bit(lsb - 1) == 1;
            let sticky = (0..lsb - 1).any(|i| bit(i) == 1);
            if half && (sticky || q & 1 == 1) {
                q += 1;
            }
            // q·2^(lsb−1074), q ≤ 2^53: exact (the result is normal, q·2^k is a double).
            let k = lsb as i32 - 1074;
            let (a, b) = (k / 2, k - k / 2);
            q as f64 * 2f64.powi(a) * 2f64.powi(b)
        };
        if negative {
            -magnitude
        } else {
            magnitude
        }
    }

    /// New sum, old sum and the reference agree to the bit (zeros: the new and old sums
    /// agree in sign, the reference in value); also for the reversed order.
    fn check(terms: &[f64]) {
        let new = sum(terms);
        if let Some(f) = fast1(terms) {
            assert_eq!(f.to_bits(), new.to_bits(), "certified fast sum {f:e} vs exact {new:e} for {terms:?}");
        }
        let old = shewchuk_sum(terms);
        assert_eq!(new.to_bits(), old.to_bits(), "fast {new:e} vs expansion {old:e} for {terms:?}");
        let mut rev = terms.to_vec();
        rev.reverse();
        assert_eq!(sum(&rev).to_bits(), new.to_bits(), "order dependence for {terms:?}");
        if terms.iter().all(|t| t.is_finite()) {
            let r = reference_sum(terms);
            assert_eq!(new, r, "fast {new:e} vs reference {r:e} for {terms:?}");
            assert_eq!(new.to_bits() & !SIGN_BIT == 0, r == 0.0);
            if new != 0.0 {
                assert_eq!(new.to_bits(), r.to_bits());
            }
        }
    }

    #[test]
    fn catastrophic_cancellation_is_exact() {
        assert_eq!(sum(&[1e100, 1.0, -1e100]), 1.0);
        assert_eq!(sum(&[0.1, 0.2, -0.3]), 2.7755575615628914e-17); // exact value of the doubles
        assert_eq!(sum(&[]), 0.0);
        check(&[1e100, 1.0, -1e100]);
        check(&[0.1, 0.2, -0.3]);
    }

    #[test]
    fn result_is_independent_of_order() {
        let mut seed = 7;
        let mut v: Vec<f64> = (0..200).map(|_| lcg(&mut seed)).collect();
        let a = sum(&v);
        v.reverse();
        assert_eq!(sum(&v).to_bits(), a.to_bits());
        for k in 0..50 {
            v.rotate_left(k % 7 + 1);
            v.swap(k, 199 - k);
            assert_eq!(sum(&v).to_bits(), a.to_bits());
        }
    }

    #[test]
    fn negated_terms_give_the_negated_sum_to_the_bit() {
        let mut seed = 11;
        let v: Vec<f64> = (0..64).map(|_| lcg(&mut seed)).collect();
        let neg: Vec<f64> = v.iter().rev().map(|x| -x).collect();
        assert_eq!(sum(&neg).to_bits(), (-sum(&v)).to_bits());
    }

    #[test]
    fn matches_a_wide_integer_reference() {
        // Terms that are integers times 2^-30 sum exactly in i128; compare with the f64 rounding of that.
        let mut seed = 3;
        for _ in 0..200 {
            let mut acc: i128 = 0;
            let mut terms = Vec::new();
            for _ in 0..30 {
                let k = ((lcg(&mut seed) * 1e6) as i64) as i128 * (1i128 << 40);
                acc += k;
                terms.push(k as f64 * 2f64.powi(-30));
            }
            let reference = acc as f64 * 2f64.powi(-30); // i128 → f64 is correctly rounded
            assert_eq!(sum(&terms).to_bits(), reference.to_bits());
        }
    }

    #[test]
    fn random_terms_in_the_fixed_point_window_match_the_reference() {
        // Node-sum-like: 1 to 40 terms within 60 binades of each other, random signs.
        let mut seed = 2024;
        for case in 0..20_000 {
            let n = 1 + (next(&mut seed) % 40) as usize;
            let lo = 900 + next(&mut seed) % 200;
            let terms: Vec<f64> = (0..n).map(|_| random_double(&mut seed, lo..lo + 60)).collect();
            check(&terms);
            if case % 4 == 0 {
                // and with exact cancellation of a random subset
                let mut t = terms.clone();
                t.extend(terms.iter().step_by(2).map(|x| -x));
                check(&t);
            }
        }
    }

    #[test]
    fn random_terms_over_many_binades_match_the_reference() {
        // Exponents anywhere from the subnormals to 2^1000: exercises the fallback and the switch.
        let mut seed = 99;
        for _ in 0..5_000 {
            let n = 1 + (next(&mut seed) % 30) as usize;
            let a = next(&mut seed) % 2000;
            let b = (a + 1 + next(&mut seed) % 300).min(2023);
            let terms: Vec<f64> = (0..n).map(|_| random_double(&mut seed, a..b)).collect();
            check(&terms);
        }
    }

    #[test]
    fn cancellation_leaving_a_tiny_remainder() {
        let mut seed = 5;
        for _ in 0..2_000 {
            let big = random_double(&mut seed, 1000..1100);
            let small = random_double(&mut seed, 900..1060);
            let other = random_double(&mut seed, 950..1050);
            check(&[big, other, small, -big, -other]);
            check(&[big, -big]);
            check(&[big, small, -big, -small]);
        }
    }

    #[test]
    fn ties_round_to_even_at_many_exponents() {
        let mut seed = 17;
        for k in (-1000..1000).step_by(7) {
            let one = 2f64.powi(k);
            let half_ulp = 2f64.powi(k - 53);
            // exactly half way: to even (down from an even significand, up from an odd one)
            check(&[one, half_ulp]);
            check(&[one + 2.0 * half_ulp, half_ulp]);
            check(&[-one, -half_ulp]);
            // half way plus or minus a tiny amount, which must break the tie
            let tiny = half_ulp * 2f64.powi(-40);
            check(&[one, half_ulp, tiny]);
            check(&[one, half_ulp, -tiny]);
            check(&[one + 2.0 * half_ulp, half_ulp, -tiny]);
            // random significands split into a tie
            let x = random_double(&mut seed, 1000..1040);
            let h = f64::from_bits(x.to_bits() & (0xfff << 52)) * 2f64.powi(-53);
            check(&[x, h]);
            check(&[x, h, -h * 2f64.powi(-30)]);
        }
        assert_eq!(sum(&[1.0, 2f64.powi(-53)]), 1.0);
        assert_eq!(sum(&[1.0, 2f64.powi(-53), 2f64.powi(-100)]), 1.0 + f64::EPSILON);
    }

    #[test]
    fn subnormal_and_tiny_terms() {
        let mut seed = 23;
        for _ in 0..2_000 {
            let n = 1 + (next(&mut seed) % 10) as usize;
            let terms: Vec<f64> = (0..n).map(|_| random_double(&mut seed, 0..80)).collect();
            check(&terms);
        }
        check(&[f64::from_bits(1), f64::from_bits(1), -f64::from_bits(3)]);
        check(&[f64::MIN_POSITIVE, -f64::from_bits(1)]);
    }

    #[test]
    fn signed_zeros_follow_ieee_addition() {
        assert_eq!(sum(&[-0.0]).to_bits(), (-0.0f64).to_bits());
        assert_eq!(sum(&[-0.0, -0.0]).to_bits(), (-0.0f64).to_bits());
        assert_eq!(sum(&[-0.0, 0.0]).to_bits(), 0);
        assert_eq!(sum(&[1.5, -0.0, -1.5]).to_bits(), 0);
        assert_eq!(sum(&[-1.5, 1.5, -0.0]).to_bits(), 0);
        for t in [&[-0.0][..], &[-0.0, -0.0], &[0.0, -0.0], &[-0.0, 0.0], &[2.0, -2.0, -0.0], &[-0.0, 1e-300, -1e-300], &[]] {
            check(t);
        }
    }

    #[test]
    fn many_terms_leave_the_window_exactly() {
        // More than MAX_TERMS terms, and a span that grows past SPAN after many terms.
        let mut seed = 31;
        let terms: Vec<f64> = (0..3000).map(|_| random_double(&mut seed, 1000..1050)).collect();
        check(&terms);
        let mut t: Vec<f64> = (0..500).map(|_| random_double(&mut seed, 1000..1060)).collect();
        t.push(random_double(&mut seed, 1200..1201));
        t.extend((0..500).map(|_| random_double(&mut seed, 1000..1060)));
        check(&t);
        let mut t: Vec<f64> = (0..500).map(|_| random_double(&mut seed, 1000..1060)).collect();
        t.push(random_double(&mut seed, 800..801));
        check(&t);
    }

    #[test]
    fn geometrically_decaying_terms_over_many_binades() {
        // Found by the impact test: geometrically decaying terms needed > 64 partials of
        // the old Shewchuk fallback (the wide accumulator has a fixed size).
        let mut s = ExactSum::new();
        let mut terms = Vec::new();
        for k in (0..200).rev() {
            s.add(3f64.powi(-k));
            terms.push(3f64.powi(-k));
        }
        terms.reverse();
        assert_eq!(s.value().to_bits(), sum(&terms).to_bits());
        assert_eq!(s.value(), 1.5); // Σ 3^-k = 1.5 to within far less than an ulp
        check(&terms);
    }

    #[test]
    fn the_fallback_rounds_at_the_ends_of_the_range_like_ieee_addition() {
        let max = f64::MAX;
        let half_ulp = 2f64.powi(970); // half an ulp of f64::MAX
        // Exact sums beyond the largest double round to ±∞, as IEEE addition does.
        assert_eq!(sum(&[max, max]), f64::INFINITY);
        assert_eq!(sum(&[-max, -max, 1.0]), f64::NEG_INFINITY);
        assert_eq!(sum(&[max, half_ulp]), f64::INFINITY); // a tie; MAX's significand is odd
        assert_eq!(sum(&[max, half_ulp, -1.0]), max);
        // An intermediate overflow of a running sum does not matter: the sum is exact.
        assert_eq!(sum(&[max, max, -max]), max);
        assert_eq!(sum(&[max, max, -max, -max, 1e-300]), 1e-300);
        // The smallest subnormals, and the whole range in one sum.
        let tiny = f64::from_bits(1);
        assert_eq!(sum(&[tiny, tiny, tiny]).to_bits(), 3);
        assert_eq!(sum(&[max, tiny, -max]), tiny);
        assert_eq!(sum(&[1.0, tiny, -1.0, 2f64.powi(-1022), -tiny]), 2f64.powi(-1022));
    }

    #[test]
    fn the_fallback_matches_the_reference_over_the_whole_range() {
        // Many terms anywhere from the subnormals to near f64::MAX (sums that stay finite:
        // at most 30 terms below 2^1018), with exact cancellation of a subset.
        let mut seed = 4242;
        for case in 0..5_000 {
            let n = 1 + (next(&mut seed) % 30) as usize;
            let mut terms: Vec<f64> = (0..n).map(|_| random_double(&mut seed, 0..2041)).collect();
            if case % 3 == 0 {
                terms.extend(terms.clone().iter().step_by(2).map(|x| -x));
            }
            check(&terms);
        }
        // More terms than the window takes, over 300 binades.
        let terms: Vec<f64> = (0..5000).map(|_| random_double(&mut seed, 700..1000)).collect();
        check(&terms);
    }

    #[test]
    fn the_fallback_is_exact_across_its_carry_normalisation() {
        // The wide accumulator normalises its carries every WIDE_BATCH terms; start it
        // just before that point so the normalisation happens in the middle of each sum.
        let mut seed = 808;
        for case in 0..2_000 {
            let n = 2 + (next(&mut seed) % 20) as usize;
            let (a, b) = if case % 2 == 0 { (0, 2040) } else { (1000, 1100) };
            let mut terms: Vec<f64> = (0..n).map(|_| random_double(&mut seed, a..b)).collect();
            terms.extend(terms.clone().iter().step_by(3).map(|x| -x));
            let mut w = Wide::new();
            w.adds = WIDE_BATCH - 1 - (next(&mut seed) % n as u64) as u32;
            terms.iter().filter(|t| **t != 0.0).for_each(|&t| w.add_double(t));
            assert_eq!(w.value().to_bits(), reference_sum(&terms).to_bits(), "{terms:?}");
        }
    }

    /// The one-lane fast sum, if certified.
    fn fast1(terms: &[f64]) -> Option<f64> {
        let mut f = FastSum::<1>::default();
        terms.iter().for_each(|&t| f.add([t]));
        f.certified().map(|v| v[0])
    }

    /// Fraction of sums the fast path certifies.
    fn certified_fraction(cases: &[Vec<f64>]) -> f64 {
        let ok = cases
            .iter()
            .filter(|t| fast1(t).is_some())
            .count();
        ok as f64 / cases.len() as f64
    }

    #[test]
    fn fast_sum_certifies_ordinary_sums_and_never_a_wrong_one() {
        let mut seed = 77;
        // Node-sum-like terms without systematic cancellation: nearly always certified.
        let cases: Vec<Vec<f64>> = (0..20_000)
            .map(|_| {
                let n = 1 + (next(&mut seed) % 40) as usize;
                (0..n).map(|_| random_double(&mut seed, 1000..1030)).collect()
            })
            .collect();
        for t in &cases {
            check(t);
        }
        let f = certified_fraction(&cases);
        assert!(f > 0.99, "certified only {f}"); // measured 0.998 (random signs: some cancel)
        // Near-ties: one term exactly half an ulp of another, nudged by ±2^-k: the fast
        // path must either decline or agree with the exact sum (check() asserts it).
        for k in 0..120 {
            for sign in [1.0, -1.0] {
                let one = 1.0 + 2f64.powi(-20);
                let half = 2f64.powi(-53);
                check(&[one, half, sign * 2f64.powi(-53 - k)]);
                check(&[one, half * 3.0, sign * 2f64.powi(-53 - k), 0.25, -0.25]);
                check(&[1.0, -half / 2.0, sign * 2f64.powi(-55 - k)]); // power of two, towards zero
            }
        }
        // Exact cancellation and exact ties of few terms are certified (δ = 0), with IEEE
        // signs; all-zero sums too.
        assert_eq!(fast1(&[1.5, -1.5]).map(f64::to_bits), Some(0));
        assert_eq!(fast1(&[1.5, -1.5, -0.0]), None); // a zero term disables certificate 1
        for t in [[1.0 + f64::EPSILON, 1.0], [1.0 + 3.0 * f64::EPSILON, 1.0], [-3.0, -(1.0 + f64::EPSILON)]] {
            assert_ne!((t[0] + t[1]) - t[0], t[1], "a tie: the plain sum rounds");
            assert_eq!(fast1(&t).map(f64::to_bits), Some(sum(&t).to_bits()), "{t:?}");
        }
        // Two terms of similar size: half of their exact sums are ties; all certified.
        let pairs: Vec<Vec<f64>> = (0..10_000).map(|_| vec![random_double(&mut seed, 1020..1022), random_double(&mut seed, 1020..1022)]).collect();
        pairs.iter().for_each(|t| check(t));
        assert_eq!(certified_fraction(&pairs), 1.0);
        // A term far below the others defeats both certificates only near a tie.
        for k in [60, 80, 200] {
            check(&[1.0, 2f64.powi(-53), 2f64.powi(-k)]);
            check(&[1.0, 2f64.powi(-53), -(2f64.powi(-k))]);
        }
        assert_eq!(fast1(&[-0.0, -0.0]).map(f64::to_bits), Some((-0.0f64).to_bits()));
        assert_eq!(fast1(&[]).map(f64::to_bits), Some(0));
        // Lanes are independent.
        let mut f = FastSum::<3>::default();
        for t in [[1.0, -0.0, 0.1], [2f64.powi(-30), -0.0, 0.2], [-0.5, -0.0, 0.3]] {
            f.add(t);
        }
        let v = f.certified().unwrap();
        assert_eq!(v.map(f64::to_bits), [sum(&[1.0, 2f64.powi(-30), -0.5]), -0.0, sum(&[0.1, 0.2, 0.3])].map(f64::to_bits));
        // ... and one lane that cannot be certified (cancellation to 2^-61 of the terms) fails the whole.
        let mut f = FastSum::<2>::default();
        for t in [[1.0, 1.0], [2f64.powi(-60), 1.0], [-1.0, 1.0]] {
            f.add(t);
        }
        assert_eq!(f.certified(), None);
    }

    #[test]
    fn the_rerun_matches_the_exact_sums_lane_by_lane() {
        // Three lanes: ordinary terms (the fast sum certifies them), ± pairs of large terms
        // that cancel exactly, and with an odd count a last tiny term (the fast sum
        // cannot certify that: the exact sum steps in), and −0s; with fewer and more
        // terms than the rerun keeps.
        let mut seed = 55;
        for n in [0, 1, 2, 7, 40, RERUN_TERMS - 1, RERUN_TERMS, RERUN_TERMS + 1, 3 * RERUN_TERMS] {
            let mut terms: Vec<[f64; 3]> = Vec::new();
            for i in 0..n {
                let cancelling = if i + 1 == n && n % 2 == 1 { random_double(&mut seed, 700..720) } else if i % 2 == 0 { random_double(&mut seed, 1000..1010) } else { -terms[i - 1][1] };
                terms.push([random_double(&mut seed, 1000..1030), cancelling, -0.0]);
            }
            let (mut rerun, mut exact, mut fast) = (Rerun::<3>::default(), ExactSums::<3>::default(), FastSum::<3>::default());
            for &t in &terms {
                rerun.add(t);
                exact.add(t);
                fast.add(t);
            }
            if n >= 7 && n % 2 == 1 {
                assert!(fast.certified().is_none(), "{n} terms: the test needs a lane the fast sum cannot certify");
            }
            let (r, e) = (rerun.certified().unwrap(), exact.certified().unwrap());
            assert_eq!(r.map(f64::to_bits), e.map(f64::to_bits), "{n} terms");
        }
    }

    #[test]
    fn the_three_level_certificates_match_the_exact_sum() {
        // Mirror-plane sums: ± pairs of terms over up to 60 binades (exact zeros), the same
        // with one term perturbed by a few ulps (a residual of the order of the round-off
        // of the terms), and plain sums; shuffled. Whatever certify3 certifies is the
        // exact sum, to the bit; and it certifies nearly all of the zeros and residuals
        // the two-level certificates cannot.
        let mut seed = 4711;
        let (mut hard, mut certified3) = (0, 0);
        for case in 0..20_000 {
            let n = 2 + (next(&mut seed) % 60) as usize;
            let lo = 960 + next(&mut seed) % 40;
            let mut terms: Vec<f64> = (0..n).map(|_| random_double(&mut seed, lo..lo + 60)).collect();
            match case % 3 {
                0 => terms.extend(terms.clone().iter().map(|x| -x)),
                1 => {
                    terms.extend(terms.clone().iter().map(|x| -x));
                    let k = (next(&mut seed) % terms.len() as u64) as usize;
                    terms[k] = f64::from_bits(terms[k].to_bits() + 1 + next(&mut seed) % 8);
                }
                _ => {}
            }
            for k in (1..terms.len()).rev() {
                terms.swap(k, (next(&mut seed) % (k as u64 + 1)) as usize);
            }
            let mut f = FastSum3::<1>::default();
            terms.iter().for_each(|&t| f.add([t]));
            let exact = sum(&terms);
            if certify(f.s[0], f.c[0], f.a[0], f.m[0], f.n).is_none() {
                hard += 1;
                if let Some(v) = certify3(f.s[0], f.c[0], f.d[0], f.a[0], f.m[0], f.n) {
                    certified3 += 1;
                    assert_eq!(v.to_bits(), exact.to_bits(), "{terms:?}");
                }
            }
            let mut r = Rerun::<1>::default();
            terms.iter().for_each(|&t| r.add([t]));
            assert_eq!(r.certified().unwrap()[0].to_bits(), exact.to_bits(), "{terms:?}");
        }
        assert!(hard > 5_000, "{hard} sums the two-level certificates cannot certify");
        assert!(certified3 as f64 > 0.99 * hard as f64, "certify3 certified {certified3} of {hard}");
    }

    #[test]
    fn clear_returns_to_the_fast_path() {
        let mut s = ExactSum::new();
        s.add(1.0);
        s.add(1e-300);
        assert!(s.slow);
        s.clear();
        s.add(0.25);
        s.add(0.5);
        assert!(!s.slow);
        assert_eq!(s.value(), 0.75);
    }

    #[test]
    fn non_finite_terms_poison_the_sum() {
        assert!(sum(&[1.0, f64::NAN, 2.0]).is_nan());
        assert_eq!(sum(&[1.0, f64::INFINITY]), f64::INFINITY);
        assert!(sum(&[f64::INFINITY, 1.0, f64::NEG_INFINITY]).is_nan());
        check(&[1.0, f64::NEG_INFINITY, 1e-300]);
    }

    #[test]
    fn half_way_cases_round_to_even() {
        // 1 + 2^-53 is exactly half way between 1 and the next double: ties to even gives 1.
        assert_eq!(sum(&[1.0, 2f64.powi(-53)]), 1.0);
        // ... and adding a tiny positive term breaks the tie upward.
        assert_eq!(sum(&[1.0, 2f64.powi(-53), 2f64.powi(-100)]), 1.0 + f64::EPSILON);
    }
}
