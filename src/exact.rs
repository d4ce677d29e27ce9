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
//! The algorithm is Shewchuk's (1997) expansion of non-overlapping partials with the
//! final round-half-even correction used by Python's `math.fsum` (Hettinger's recipe),
//! which is correctly rounded for finite inputs. With a few terms per node the
//! expansion holds one to three partials, so an addition costs a handful of flops.

/// An exact accumulator: add terms in any order, read the correctly rounded sum.
///
/// The partials live in a `Vec` that grows as needed: non-overlapping partials need not
/// use 53 bits each, so terms spread over many binades (velocities decaying ahead of a
/// wave front, say) can need hundreds of them. Accumulators are reused with
/// [`ExactSum::clear`], which keeps the allocation, so the hot loops allocate once.
#[derive(Clone, Debug, Default)]
pub struct ExactSum {
    partials: Vec<f64>,
    /// Sum of the non-finite terms (0 when there are none): a NaN or infinity poisons the
    /// result visibly, and the checked mode reports it.
    special: f64,
}

impl ExactSum {
    #[inline]
    pub fn new() -> Self {
        ExactSum { partials: Vec::with_capacity(8), special: 0.0 }
    }

    /// Forget all terms (cheap: the allocation is kept), so one accumulator serves many sums.
    #[inline]
    pub fn clear(&mut self) {
        self.partials.clear();
        self.special = 0.0;
    }

    /// Add one term.
    #[inline]
    pub fn add(&mut self, mut x: f64) {
        if !x.is_finite() {
            self.special += x;
            return;
        }
        let mut i = 0;
        for j in 0..self.partials.len() {
            let mut y = self.partials[j];
            if x.abs() < y.abs() {
                std::mem::swap(&mut x, &mut y);
            }
            let hi = x + y;
            let lo = y - (hi - x);
            if lo != 0.0 {
                self.partials[i] = lo;
                i += 1;
            }
            x = hi;
        }
        self.partials.truncate(i);
        self.partials.push(x);
    }

    /// The correctly rounded sum of all terms added so far.
    #[inline]
    pub fn value(&self) -> f64 {
        if self.special != 0.0 || self.special.is_nan() {
            return self.special;
        }
        let p = &self.partials[..];
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

    #[test]
    fn catastrophic_cancellation_is_exact() {
        assert_eq!(sum(&[1e100, 1.0, -1e100]), 1.0);
        assert_eq!(sum(&[0.1, 0.2, -0.3]), 2.7755575615628914e-17); // exact value of the doubles
        assert_eq!(sum(&[]), 0.0);
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
    fn terms_over_many_binades_need_many_partials() {
        // Found by the impact test: geometrically decaying terms need > 64 partials.
        let mut s = ExactSum::new();
        let mut terms = Vec::new();
        for k in (0..200).rev() {
            s.add(3f64.powi(-k));
            terms.push(3f64.powi(-k));
        }
        terms.reverse();
        assert_eq!(s.value().to_bits(), sum(&terms).to_bits());
        assert_eq!(s.value(), 1.5); // Σ 3^-k = 1.5 to within far less than an ulp
    }

    #[test]
    fn non_finite_terms_poison_the_sum() {
        assert!(sum(&[1.0, f64::NAN, 2.0]).is_nan());
        assert_eq!(sum(&[1.0, f64::INFINITY]), f64::INFINITY);
    }

    #[test]
    fn half_way_cases_round_to_even() {
        // 1 + 2^-53 is exactly half way between 1 and the next double: ties to even gives 1.
        assert_eq!(sum(&[1.0, 2f64.powi(-53)]), 1.0);
        // ... and adding a tiny positive term breaks the tie upward.
        assert_eq!(sum(&[1.0, 2f64.powi(-53), 2f64.powi(-100)]), 1.0 + f64::EPSILON);
    }
}
