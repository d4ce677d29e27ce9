//! Crack geometry: the signed-area line-crossing algorithm of CRAMP
//! (Nairn 2003, appendix "Line Crossing Algorithm", eq. 33 and subtasks 1–4),
//! segment tangents/normals (Nairn 2003 §2.2) and segment–segment intersection.
//!
//! All functions are pure functions of a slice of crack points (the crack's massless
//! particles, in order from the crack's start to its end), so the time step can call
//! them without owning a crack type.
//!
//! # Exactness
//!
//! Every decision (sign of a signed area) is made with an **exact** orientation
//! predicate ([`orientation`]): a floating-point filter with a proven error bound
//! (Shewchuk 1997, "Adaptive precision floating-point arithmetic and fast robust
//! geometric predicates", bound `ccwerrboundA`), falling back to an exact expansion
//! sum of the six products of eq. 33 (error-free `TwoProduct` via `mul_add`,
//! `TwoSum`, Shewchuk's `grow_expansion_zeroelim`). Consequences:
//!
//! * a node lying exactly on a crack gives an exactly zero area, whatever the crack's
//!   orientation (not only for horizontal cracks);
//! * mirroring all points about y = 0 (or any exact symmetry: x ↦ −x, 90° rotations)
//!   maps every sign exactly, so mirrored particles get mirrored classifications to the
//!   bit (the crack-patch test), and rotating a configuration by 90° or 180° never
//!   changes a classification.
//!
//! Precondition of the exact fallback: products of coordinates neither overflow nor
//! underflow (|x| between ~1e-150 and ~1e150, or exactly 0), always true for grids
//! in SI or mm units.
//!
//! # Conventions
//!
//! * "Above" a segment x3 → x4 is its **left** side (counter-clockwise), so a crack
//!   running left to right along y = 0 has "above" at y > 0. This is what the paper's
//!   sign patterns imply: for x3 = (−1,0), x4 = (1,0), particle (0,1), node (0,−1), the
//!   areas (123),(124),(341),(342) are (−,+,+,−), the paper's "particle above" case.
//! * [`Side::Above`] means the line from particle to node crosses the crack and the
//!   particle is above (velocity field 1); [`Side::Below`] → field 2 (Nairn 2003, §2.1
//!   and appendix Task 2).

use crate::dim::Vector;

// ---------------------------------------------------------------------------------
// Signed areas (eq. 33) and the exact orientation predicate
// ---------------------------------------------------------------------------------

/// The signed area of eq. 33 (Nairn 2003, appendix), which is twice the area of the
/// triangle (x1, x2, x3): `x1(y2−y3) + x2(y3−y1) + x3(y1−y2)`.
///
/// Positive when x1 → x2 → x3 is counter-clockwise, negative when clockwise, zero when
/// collinear. Evaluated in plain floating point (its *sign* may be wrong for nearly
/// collinear points; use [`orientation`] for decisions). The expression is odd under
/// y ↦ −y to the bit (every term changes sign exactly).
#[inline]
pub fn signed_area(x1: Vector, x2: Vector, x3: Vector) -> f64 {
    x1.x * (x2.y - x3.y) + x2.x * (x3.y - x1.y) + x3.x * (x1.y - x2.y)
}

/// The sign of a signed area, written "+", "−" and "0" in the paper.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Sign {
    Negative,
    Zero,
    Positive,
}

impl Sign {
    #[inline]
    fn of(v: f64) -> Sign {
        if v > 0.0 {
            Sign::Positive
        } else if v < 0.0 {
            Sign::Negative
        } else {
            // ±0.0, and NaN (non-finite input) is treated as collinear: no crossing.
            Sign::Zero
        }
    }

    #[inline]
    fn flip(self) -> Sign {
        match self {
            Sign::Negative => Sign::Positive,
            Sign::Zero => Sign::Zero,
            Sign::Positive => Sign::Negative,
        }
    }
}

/// Error-free sum (Knuth's TwoSum): a + b = s + e exactly.
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    (s, e)
}

/// Error-free product: a·b = p + e exactly (fused multiply-add; no underflow assumed).
#[inline]
fn two_product(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// Shewchuk's `grow_expansion_zeroelim`, in place: adds `b` to the nonoverlapping,
/// increasing-magnitude expansion `e[..*len]`.
#[inline]
fn grow_expansion(e: &mut [f64; 16], len: &mut usize, b: f64) {
    let mut q = b;
    let mut h = 0;
    for i in 0..*len {
        let (s, err) = two_sum(q, e[i]);
        q = s;
        if err != 0.0 {
            e[h] = err; // h <= i: e[i] has already been read
            h += 1;
        }
    }
    if q != 0.0 || h == 0 {
        e[h] = q;
        h += 1;
    }
    *len = h;
}

/// Exact sign of eq. 33 by expansion arithmetic (the slow path of [`orientation`]).
fn orientation_exact(a: Vector, b: Vector, c: Vector) -> Sign {
    // x1 y2 − x1 y3 + x2 y3 − x2 y1 + x3 y1 − x3 y2, each product split exactly.
    let terms = [
        (a.x, b.y),
        (-a.x, c.y),
        (b.x, c.y),
        (-b.x, a.y),
        (c.x, a.y),
        (-c.x, b.y),
    ];
    let mut e = [0.0f64; 16];
    let mut len = 0usize;
    for (u, v) in terms {
        let (p, err) = two_product(u, v);
        grow_expansion(&mut e, &mut len, err);
        grow_expansion(&mut e, &mut len, p);
    }
    // Nonoverlapping expansion: the sign is that of its most significant component.
    Sign::of(e[len - 1])
}

/// Exact sign (−1, 0, +1) of Σ a_k b_k over eight products (expansion arithmetic, as
/// [`orientation`]'s slow path): the tie-breaking determinants of the 3D crack crossing
/// test (`crack::crossing3`). Same precondition (no overflow or underflow of products).
pub(crate) fn sign_of_products(terms: &[(f64, f64); 8]) -> i8 {
    let mut e = [0.0f64; 16];
    let mut len = 0usize;
    for &(u, v) in terms {
        let (p, err) = two_product(u, v);
        grow_expansion(&mut e, &mut len, err);
        grow_expansion(&mut e, &mut len, p);
    }
    match Sign::of(e[len - 1]) {
        Sign::Negative => -1,
        Sign::Zero => 0,
        Sign::Positive => 1,
    }
}

/// The exact sign of the signed area of eq. 33 (Nairn 2003): `Positive` if
/// x1 → x2 → x3 turns counter-clockwise, `Negative` if clockwise, `Zero` iff the three
/// points are exactly collinear.
///
/// Fast path: Shewchuk's `orient2d` filter (error bound (3 + 16ε)ε, ε = 2⁻⁵³);
/// otherwise an exact expansion sum. Symmetric to the bit under any exact isometry of
/// the coordinates (mirror about an axis, 90° rotations), because the result is exact.
pub fn orientation(x1: Vector, x2: Vector, x3: Vector) -> Sign {
    const EPS: f64 = f64::EPSILON * 0.5; // 2^-53
    const CCW_ERRBOUND_A: f64 = (3.0 + 16.0 * EPS) * EPS;
    let detleft = (x1.x - x3.x) * (x2.y - x3.y);
    let detright = (x1.y - x3.y) * (x2.x - x3.x);
    let det = detleft - detright;
    let detsum = if detleft > 0.0 {
        if detright <= 0.0 {
            return Sign::of(det);
        }
        detleft + detright
    } else if detleft < 0.0 {
        if detright >= 0.0 {
            return Sign::of(det);
        }
        -detleft - detright
    } else {
        return Sign::of(det);
    };
    let bound = CCW_ERRBOUND_A * detsum;
    if det >= bound || -det >= bound {
        // (det == bound == 0 is impossible here: detsum > 0)
        return Sign::of(det);
    }
    if !det.is_finite() {
        return Sign::Zero;
    }
    orientation_exact(x1, x2, x3)
}

// ---------------------------------------------------------------------------------
// Subtask 1: crack extent
// ---------------------------------------------------------------------------------

/// Axis-aligned bounding box of a crack's points (Nairn 2003, appendix, Subtask 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extent {
    pub min: Vector,
    pub max: Vector,
}

impl Extent {
    /// The empty extent (overlaps nothing).
    pub const EMPTY: Extent = Extent {
        min: Vector::new(f64::INFINITY, f64::INFINITY),
        max: Vector::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
    };

    /// Bounding box of `points` (the empty extent for an empty slice).
    pub fn of(points: &[Vector]) -> Extent {
        let mut e = Extent::EMPTY;
        for &p in points {
            e.include(p);
        }
        e
    }

    /// Grow the box to contain `p`.
    #[inline]
    pub fn include(&mut self, p: Vector) {
        self.min.x = self.min.x.min(p.x);
        self.min.y = self.min.y.min(p.y);
        self.max.x = self.max.x.max(p.x);
        self.max.y = self.max.y.max(p.y);
    }

    /// Subtask 1: does the rectangle spanned by particle `xp` and node `xn` intersect
    /// this extent? Closed test (touching counts), so a node exactly on the crack's
    /// bounding box is never screened out. Exact (comparisons only).
    #[inline]
    pub fn overlaps_rect(&self, xp: Vector, xn: Vector) -> bool {
        !(xp.x.max(xn.x) < self.min.x
            || xp.x.min(xn.x) > self.max.x
            || xp.y.max(xn.y) < self.min.y
            || xp.y.min(xn.y) > self.max.y)
    }
}

/// The bounding boxes of a polyline's segments, grouped in chunks of consecutive
/// segments with a box each, to find the segments near a box without testing them all
/// (the line-crossing test and the side tests near a long crack). Rebuilt from the
/// crack's points whenever they move; the buffers are kept.
#[derive(Clone, Debug, Default)]
pub struct SegmentIndex {
    chunk: usize,
    chunks: Vec<Extent>,
    segs: Vec<Extent>,
}

impl SegmentIndex {
    /// The index of the polyline `points` (segment i joins points i and i + 1).
    pub fn of(points: &[Vector]) -> Self {
        let mut s = SegmentIndex::default();
        s.rebuild(points);
        s
    }

    /// Rebuild for `points`, reusing the buffers.
    pub fn rebuild(&mut self, points: &[Vector]) {
        let n = points.len().saturating_sub(1);
        // About √n chunks of about √n segments: both levels cost O(√n) per query.
        self.chunk = ((n as f64).sqrt().ceil() as usize).max(8);
        self.segs.clear();
        self.segs.extend(points.windows(2).map(Extent::of));
        self.chunks.clear();
        self.chunks.extend(self.segs.chunks(self.chunk).map(|c| {
            let mut e = Extent::EMPTY;
            for s in c {
                e.include(s.min);
                e.include(s.max);
            }
            e
        }));
    }

    /// The segments whose closed bounding box meets the closed box [lo, hi], ascending.
    /// Exact (comparisons only).
    #[inline]
    pub fn near(&self, lo: Vector, hi: Vector) -> impl Iterator<Item = usize> + Clone + '_ {
        let meets = move |e: &Extent| !(hi.x < e.min.x || lo.x > e.max.x || hi.y < e.min.y || lo.y > e.max.y);
        let chunk = self.chunk;
        self.chunks.iter().enumerate().filter(move |(_, e)| meets(e)).flat_map(move |(c, _)| {
            let start = c * chunk;
            let end = (start + chunk).min(self.segs.len());
            (start..end).filter(move |&i| meets(&self.segs[i]))
        })
    }
}

// ---------------------------------------------------------------------------------
// Subtasks 2–3: one segment, the paper's eight sign patterns
// ---------------------------------------------------------------------------------

/// Result of the line-crossing test: does the line from a particle to a node cross the
/// crack, and on which side is the particle (Nairn 2003, appendix Task 2: field 1 for
/// above, field 2 for below, field 0 for no crossing).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Side {
    /// No crossing: the particle uses velocity field 0 at this node.
    #[default]
    None,
    /// Crossing, particle above the crack (left of its direction): field 1.
    Above,
    /// Crossing, particle below the crack (right of its direction): field 2.
    Below,
}

impl Side {
    /// The mirror-image classification (Above ↔ Below).
    pub fn flip(self) -> Side {
        match self {
            Side::None => Side::None,
            Side::Above => Side::Below,
            Side::Below => Side::Above,
        }
    }
}

/// Which of the paper's accepted sign patterns a segment matched (Subtask 3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Pattern {
    /// (−++−) / (+−−+): the line properly crosses the segment.
    Proper,
    /// (−++0) / (+−−0): the node lies on the segment, strictly between its ends.
    NodeOnSegment,
    /// (0++0) / (0−−0): the node is the segment's start point x3.
    NodeAtStart,
    /// (−0+0) / (+0−0): the node is the segment's end point x4.
    NodeAtEnd,
}

fn side_of(s: Sign) -> Side {
    match s {
        Sign::Positive => Side::Above,
        Sign::Negative => Side::Below,
        Sign::Zero => Side::None,
    }
}

/// Subtasks 2–3 for one segment, exactly as in the paper: signs of the areas (123),
/// (124), (341), (342) with 1 = particle `xp`, 2 = node `xn`, 3, 4 = segment ends.
///
/// Particle above for (−++−), (−++0), (0++0), (−0+0); below for (+−−+), (+−−0),
/// (0−−0), (+0−0); every other combination is "no crossing of this segment" (`None`).
/// (341),(342) are not evaluated when (123),(124) have the same strict sign.
///
/// This is the per-segment rule only; [`crossing`] aggregates segments (Subtask 4)
/// and treats crack vertices specially (see there).
pub fn segment_pattern(xp: Vector, xn: Vector, x3: Vector, x4: Vector) -> Option<(Side, Pattern)> {
    use Sign::{Negative as N, Positive as P, Zero as Z};
    let a = orientation(xp, xn, x3);
    let b = orientation(xp, xn, x4);
    if a == b && a != Z {
        return None; // (++..) or (−−..): the line cannot cross the segment
    }
    let c = orientation(x3, x4, xp);
    let d = orientation(x3, x4, xn);
    match (a, b, c, d) {
        (N, P, P, N) => Some((Side::Above, Pattern::Proper)),
        (N, P, P, Z) => Some((Side::Above, Pattern::NodeOnSegment)),
        (Z, P, P, Z) => Some((Side::Above, Pattern::NodeAtStart)),
        (N, Z, P, Z) => Some((Side::Above, Pattern::NodeAtEnd)),
        (P, N, N, P) => Some((Side::Below, Pattern::Proper)),
        (P, N, N, Z) => Some((Side::Below, Pattern::NodeOnSegment)),
        (Z, N, N, Z) => Some((Side::Below, Pattern::NodeAtStart)),
        (P, Z, N, Z) => Some((Side::Below, Pattern::NodeAtEnd)),
        _ => None,
    }
}

// ---------------------------------------------------------------------------------
// Subtask 4: a whole crack
// ---------------------------------------------------------------------------------

/// Where the deciding crossing happened.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Site {
    /// On the interior of segment `i` (points `i` → `i+1`).
    Segment(usize),
    /// At crack point `j` (a vertex or a tip).
    Vertex(usize),
}

/// Full result of [`crossing_detail`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// Side of the particle relative to the crack at the deciding crossing.
    pub side: Side,
    /// Number of crossings counted (odd; even counts return no crossing).
    pub count: usize,
    /// The deciding crossing: the one nearest the node along particle → node.
    pub site: Site,
}

/// Is `v`, known to be collinear with `a` and `b`, strictly between them?
/// Exact (coordinate comparisons only).
#[inline]
fn strictly_between(a: Vector, b: Vector, v: Vector) -> bool {
    if a.x != b.x {
        (a.x < v.x && v.x < b.x) || (b.x < v.x && v.x < a.x)
    } else if a.y != b.y {
        (a.y < v.y && v.y < b.y) || (b.y < v.y && v.y < a.y)
    } else {
        false
    }
}

/// Is `p` on the closed segment [a, b]? Exact.
#[inline]
fn on_segment(a: Vector, b: Vector, p: Vector) -> bool {
    p == a || p == b || (orientation(a, b, p) == Sign::Zero && strictly_between(a, b, p))
}

/// Side of `p` relative to the crack locally at an interior vertex `v` with
/// neighbours `a` (before) and `b` (after): "above" is the open wedge swept
/// counter-clockwise from ray v→b to ray v→a (the left of travel a → v → b).
/// `None` if `p` lies on either adjacent segment, or the crack folds back (a, b on
/// the same ray from v).
fn wedge_side(a: Vector, v: Vector, b: Vector, p: Vector) -> Side {
    if on_segment(a, v, p) || on_segment(v, b, p) {
        return Side::None;
    }
    let s1 = orientation(a, v, p);
    let s2 = orientation(v, b, p);
    match orientation(a, v, b) {
        // left turn: above is the convex wedge, the intersection of both left sides
        Sign::Positive => {
            if s1 == Sign::Positive && s2 == Sign::Positive {
                Side::Above
            } else {
                Side::Below
            }
        }
        // right turn: below is the convex wedge
        Sign::Negative => {
            if s1 == Sign::Negative && s2 == Sign::Negative {
                Side::Below
            } else {
                Side::Above
            }
        }
        // collinear: straight through (s1 == s2) or folded back (degenerate)
        Sign::Zero => {
            if strictly_between(a, b, v) {
                side_of(s1)
            } else {
                Side::None
            }
        }
    }
}

/// [`crossing`] with the count and the deciding site (for the crack normal saved at a
/// node, Nairn 2003 §2.2: "the normal to that crack segment is saved for that node").
///
/// Algorithm (Nairn 2003 appendix, Subtasks 1–4), with the vertex rules the paper
/// leaves open made explicit:
///
/// 1. **Extent**: if the particle–node rectangle misses `extent`, no crossing.
/// 2. **Segments** whose two ends are strictly on opposite sides of the line L from
///    particle to node: the paper's patterns (−++−)/(+−−+) (proper crossing) and
///    (−++0)/(+−−0) (node on the segment) each count one crossing with the paper's
///    sense. (341),(342) are skipped when (123),(124) have the same strict sign.
/// 3. **Crack points lying exactly on L** (the paper's zero areas at x3 or x4). A point
///    shared by two segments must count once, not twice: with the paper's per-segment
///    patterns a node exactly at an interior crack point matches (−0+0) on one segment
///    and (0++0) on the next, an even count, i.e. *no* crossing for a node lying on the
///    crack; and a line through an interior crack point matches none of the listed
///    patterns. So:
///    * node exactly at a crack **tip**: one crossing with the paper's sense
///      ((0++0)/(0−−0) at the start, (−0+0)/(+0−0) at the end, which reduce to the side
///      of the particle relative to the tip segment);
///    * node exactly at an **interior** crack point: one crossing; the sense is the
///      particle's side of the crack locally at that point (wedge rule; equal to the
///      paper's sense whenever both adjacent segments agree, e.g. a straight crack);
///    * L passing through an **interior** crack point strictly between particle and
///      node: crack points on L are perturbed symbolically to the left of L; this counts
///      one crossing iff the neighbouring points are on opposite (perturbed) sides of L
///      (the crack passes through L), none if it only touches L; the sense is the
///      paper's sense on the perturbed segment that crosses;
///    * L passing through a **tip** strictly between particle and node: no crossing (the
///      paper's (0++−)-type patterns are not in its list; a line grazing a tip does not
///      separate the particle from the node);
///    * particle exactly on the crack: ignored, as in the paper.
/// 4. **Parity** (Subtask 4): only an odd number of crossings is a crossing. The sense
///    is that of the crossing **nearest the node** along particle → node (a node on the
///    crack is nearest of all). Rationale: every particle separated from the node is
///    then classified by the side of the crack surface adjacent to the node, so all
///    particles across the crack from a node land in the same field. (NairnMPM toggles
///    and keeps the sense of the last crossing in crack order; the two agree whenever
///    all crossings have the same sense.) Near-ties in position are broken by the
///    earlier crossing in crack order.
/// 5. **Node on the crack**: such a node lies on neither side, so parity says nothing
///    (a node "on the same side" as the particle does not exist): every particle whose
///    line meets the crack is across it, on the side of the crossing **nearest the
///    particle** — the side of the crack surface the particle itself faces. With one
///    crossing (the node itself; any straight crack) this is rule 4's answer. It
///    differs where the crack kinks: a node on the straight part, near the kink, sees
///    the material beyond the kinked segment by a line that touches the crack at the
///    node and crosses the kinked segment (an even count), and parity would give that
///    material field 0 next to fields 1 and 2 — a third field for a single crack
///    (issue 22: a notch on a grid line stopped a few steps after it kinked). That
///    material is joined to the particles on the same side of the kinked segment, and
///    here it gets their field.
///
/// Zero-length segments (repeated points) are skipped.
pub fn crossing_detail(points: &[Vector], extent: &Extent, xp: Vector, xn: Vector) -> Option<Crossing> {
    crossing_over(points, extent, 0..points.len().saturating_sub(1), xp, xn)
}

/// [`crossing_detail`] testing only the segments that `index` (built from `points`) finds
/// near the particle–node rectangle — the same result, since only a segment that meets the
/// closed segment particle → node is ever counted, and only a crack point on it (the end
/// of such a segment) decides a touching case.
#[inline]
pub fn crossing_detail_indexed(points: &[Vector], extent: &Extent, index: &SegmentIndex, xp: Vector, xn: Vector) -> Option<Crossing> {
    if points.len() < 2 || !extent.overlaps_rect(xp, xn) {
        return None;
    }
    crossing_over(points, extent, index.near(xp.inf(&xn), xp.sup(&xn)), xp, xn)
}

/// [`crossing_detail`] over the segments `segs` (segment i joins points i and i + 1),
/// in ascending order: they must include every segment that meets the closed segment
/// particle → node. Each segment's verdict depends on that segment alone, and the
/// crack points that can decide a touching case are ends of such segments, so testing a
/// superset of them in crack order gives the result of testing all.
fn crossing_over<I: Iterator<Item = usize> + Clone>(points: &[Vector], extent: &Extent, segs: I, xp: Vector, xn: Vector) -> Option<Crossing> {
    if points.len() < 2 || !extent.overlaps_rect(xp, xn) {
        return None;
    }
    let mut count = 0usize;
    // best = (rank, t, side, site); rank 1 = node on crack, rank 0 = at parameter t
    let mut best: Option<(u8, f64, Side, Site)> = None;
    // The crossing nearest the particle (smallest t; the node itself is t = 1): its side
    // decides when the node lies on the crack (rule 5 of `crossing_detail`).
    let mut nearest_particle: Option<(f64, Side)> = None;
    let mut record = |rank: u8, t: f64, side: Side, site: Site| {
        count += 1;
        let better = match best {
            None => true,
            Some((r, bt, _, _)) => rank > r || (rank == r && t > bt),
        };
        if better {
            best = Some((rank, t, side, site));
        }
        if nearest_particle.is_none_or(|(bt, _)| t < bt) {
            nearest_particle = Some((t, side));
        }
    };

    // --- segments whose ends are strictly on opposite sides of L
    let mut any_on_line = false;
    // The orientation of the last segment's far end, reused when the next segment starts there.
    let mut o_prev: Option<(usize, Sign)> = None;
    for i in segs.clone() {
        let (x3, x4) = (points[i], points[i + 1]);
        let a = match o_prev {
            Some((j, o)) if j == i => o,
            _ => {
                let o = orientation(xp, xn, x3);
                any_on_line |= o == Sign::Zero;
                o
            }
        };
        let b = orientation(xp, xn, x4);
        o_prev = Some((i + 1, b));
        if b == Sign::Zero {
            any_on_line = true;
        }
        if a == Sign::Zero || b == Sign::Zero || a == b || x3 == x4 {
            continue;
        }
        let c = orientation(x3, x4, xp);
        let d = orientation(x3, x4, xn);
        if c == Sign::Zero || c == b.flip() {
            // particle on the segment's line (ignored), or the sense is inconsistent:
            // not one of the paper's patterns
            continue;
        }
        // here c == b: the paper's (−++·)/(+−−·) families
        if d == c.flip() {
            // (−++−) or (+−−+): proper crossing at parameter t along particle → node
            let a1 = signed_area(x3, x4, xp);
            let a2 = signed_area(x3, x4, xn);
            let mut t = a1 / (a1 - a2);
            if !t.is_finite() {
                t = 0.5;
            }
            record(0, t.clamp(0.0, 1.0), side_of(c), Site::Segment(i));
        } else if d == Sign::Zero {
            // (−++0) or (+−−0): node on the segment interior
            record(1, 1.0, side_of(c), Site::Segment(i));
        }
    }

    // --- crack points exactly on L (rare: only evaluated when one exists), the ends of
    // the tested segments in ascending order, each once
    if any_on_line {
        let mut last = usize::MAX;
        for j in segs.flat_map(|i| [i, i + 1]) {
            if j == last {
                continue;
            }
            last = j;
            let v = points[j];
            if j > 0 && points[j - 1] == v {
                continue; // repeated point, handled at its first copy
            }
            if v == xp || orientation(xp, xn, v) != Sign::Zero {
                continue;
            }
            let prev = points[..j].iter().rev().copied().find(|&q| q != v);
            let next = points[j + 1..].iter().copied().find(|&q| q != v);
            if v == xn {
                let side = match (prev, next) {
                    (None, Some(b)) => side_of(orientation(v, b, xp)), // (0++0)/(0−−0)
                    (Some(a), None) => side_of(orientation(a, v, xp)), // (−0+0)/(+0−0)
                    (Some(a), Some(b)) => wedge_side(a, v, b, xp),
                    (None, None) => Side::None,
                };
                if side != Side::None {
                    record(1, 1.0, side, Site::Vertex(j));
                }
            } else if strictly_between(xp, xn, v) {
                if let (Some(a), Some(b)) = (prev, next) {
                    // Symbolic perturbation: every crack point on L is moved to the
                    // left (+) of L. The crack then crosses L once, near v, iff exactly
                    // one neighbour is strictly right (−) of L, on the segment joining
                    // it to v; the sense is the paper's sense for that segment, whose
                    // area with the particle is nonzero (its far end is off L).
                    let a_neg = orientation(xp, xn, a) == Sign::Negative;
                    let b_neg = orientation(xp, xn, b) == Sign::Negative;
                    let side = match (a_neg, b_neg) {
                        (true, false) => side_of(orientation(a, v, xp)),
                        (false, true) => side_of(orientation(v, b, xp)),
                        // touches L (no crossing, or two that cancel)
                        _ => Side::None,
                    };
                    if side != Side::None {
                        let d = xn - xp;
                        let mut t = (v - xp).dot(&d) / d.dot(&d);
                        if !t.is_finite() {
                            t = 0.5;
                        }
                        record(0, t.clamp(0.0, 1.0), side, Site::Vertex(j));
                    }
                }
            }
        }
    }

    match (best, nearest_particle) {
        // Node on the crack: always a crossing, on the particle's own side (rule 5).
        (Some((1, _, _, site)), Some((_, side))) => Some(Crossing { side, count, site }),
        (Some((_, _, side, site)), _) if count % 2 == 1 => Some(Crossing { side, count, site }),
        _ => None,
    }
}

/// The CRAMP line-crossing test (Nairn 2003, appendix, Subtasks 1–4): does the line
/// from particle `xp` to node `xn` cross the crack through `points` (with bounding box
/// `extent`, see [`Extent::of`]), and is the particle above (field 1) or below
/// (field 2) the crack relative to the node? See [`crossing_detail`] for the exact
/// rules at crack points and for mixed senses.
#[inline]
pub fn crossing(points: &[Vector], extent: &Extent, xp: Vector, xn: Vector) -> Side {
    crossing_detail(points, extent, xp, xn).map_or(Side::None, |c| c.side)
}

// ---------------------------------------------------------------------------------
// Segment tangent and normal (Nairn 2003 §2.2)
// ---------------------------------------------------------------------------------

/// Unit tangent of the segment x3 → x4, along the crack direction. `None` for a
/// zero-length or non-finite segment.
pub fn segment_tangent(x3: Vector, x4: Vector) -> Option<Vector> {
    let d = x4 - x3;
    let len = d.x.hypot(d.y);
    if len > 0.0 && len.is_finite() {
        Some(d / len)
    } else {
        None
    }
}

/// Unit normal of the segment x3 → x4 directed **from above the crack to below**
/// (Nairn 2003 §2.2, the contact normal): the tangent (tx, ty) turned clockwise,
/// n = (ty, −tx). For a crack along +x this is (0, −1). Mirror about y = 0 maps it to
/// the mirror of the normal to the bit. `None` for a zero-length segment.
pub fn segment_normal(x3: Vector, x4: Vector) -> Option<Vector> {
    segment_tangent(x3, x4).map(|t| Vector::new(t.y, -t.x))
}

// ---------------------------------------------------------------------------------
// Segment–segment intersection
// ---------------------------------------------------------------------------------

/// Intersection of the closed segments p → q and a → b: returns `(s, t)` with the
/// crossing point p + s(q − p) = a + t(b − a), s, t ∈ [0, 1], or `None` if they do not
/// meet. Used for J contours crossing a crack and for checking that growth never
/// crosses an existing crack.
///
/// The meet/no-meet decision is exact ([`orientation`]); touching at an endpoint
/// counts, and then the parameter of that endpoint is exactly 0 or 1. The parameters
/// themselves are ratios of signed areas (eq. 33), s = A(a,b,p)/(A(a,b,p) − A(a,b,q)),
/// accurate to rounding. Degenerate cases return `None`: a zero-length segment, and
/// collinear segments (no unique crossing point, even when they overlap).
pub fn segment_intersection(p: Vector, q: Vector, a: Vector, b: Vector) -> Option<(f64, f64)> {
    if p == q || a == b {
        return None;
    }
    let o1 = orientation(p, q, a);
    let o2 = orientation(p, q, b);
    if o1 == Sign::Zero && o2 == Sign::Zero {
        return None; // collinear
    }
    if o1 == o2 {
        return None;
    }
    let o3 = orientation(a, b, p);
    let o4 = orientation(a, b, q);
    if o3 == o4 {
        return None; // both nonzero and equal (both zero would mean collinear)
    }
    let ratio = |u: f64, v: f64| {
        let r = u / (u - v);
        if r.is_finite() {
            r.clamp(0.0, 1.0)
        } else {
            0.5
        }
    };
    let s = match (o3, o4) {
        (Sign::Zero, _) => 0.0,
        (_, Sign::Zero) => 1.0,
        _ => ratio(signed_area(a, b, p), signed_area(a, b, q)),
    };
    let t = match (o1, o2) {
        (Sign::Zero, _) => 0.0,
        (_, Sign::Zero) => 1.0,
        _ => ratio(signed_area(p, q, a), signed_area(p, q, b)),
    };
    Some((s, t))
}

// ---------------------------------------------------------------------------------

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vector {
        Vector::new(x, y)
    }

    fn cross(points: &[Vector], xp: Vector, xn: Vector) -> Side {
        crossing(points, &Extent::of(points), xp, xn)
    }

    fn mirror(p: Vector) -> Vector {
        v(p.x, -p.y)
    }

    fn rot90(p: Vector) -> Vector {
        v(-p.y, p.x)
    }

    fn rot180(p: Vector) -> Vector {
        v(-p.x, -p.y)
    }

    /// Tiny deterministic generator (SplitMix64).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        }
        /// integer in [-m, m]
        fn int(&mut self, m: i64) -> i64 {
            (self.next() % (2 * m as u64 + 1)) as i64 - m
        }
        fn unit(&mut self) -> f64 {
            (self.next() >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn signed_area_eq33_values() {
        // ccw unit right triangle: area 1/2, eq. 33 gives twice that
        assert_eq!(signed_area(v(0., 0.), v(1., 0.), v(0., 1.)), 1.0);
        assert_eq!(signed_area(v(0., 0.), v(0., 1.), v(1., 0.)), -1.0);
        assert_eq!(signed_area(v(0., 0.), v(1., 1.), v(2., 2.)), 0.0);
        assert_eq!(orientation(v(0., 0.), v(1., 0.), v(0., 1.)), Sign::Positive);
        assert_eq!(orientation(v(0., 0.), v(0., 1.), v(1., 0.)), Sign::Negative);
        assert_eq!(orientation(v(0., 0.), v(1., 1.), v(2., 2.)), Sign::Zero);
        // mirror about y = 0 negates eq. 33 to the bit
        let (a, b, c) = (v(0.1, 0.7), v(-0.3, 0.2), v(0.55, -0.9));
        assert_eq!(
            signed_area(mirror(a), mirror(b), mirror(c)).to_bits(),
            (-signed_area(a, b, c)).to_bits()
        );
    }

    /// The exact predicate against independent integer arithmetic (i128) on dyadic
    /// coordinates k·2⁻³⁰, including exactly-collinear and nearly-collinear triples
    /// where the naive formula is wrong.
    #[test]
    fn orientation_is_exact_against_integer_arithmetic() {
        let scale = (2.0f64).powi(-30);
        let mut rng = Rng(12345);
        let mut naive_wrong = 0;
        for k in 0..200_000 {
            let (ax, ay) = (rng.int(1 << 40), rng.int(1 << 40));
            // b, c on a lattice line through a (exactly collinear), c possibly nudged
            // by one unit: nearly collinear with large coordinates.
            let (dx, dy) = (rng.int(1 << 20), rng.int(1 << 20));
            let (kb, kc) = (rng.int(1 << 10), rng.int(1 << 10));
            let (bx, by) = (ax + kb * dx, ay + kb * dy);
            let (cx, cy) = if k % 4 == 3 {
                (rng.int(1 << 40), rng.int(1 << 40))
            } else {
                (ax + kc * dx + rng.int(1) * (k % 2) as i64, ay + kc * dy + rng.int(1))
            };
            let exact = (ax as i128) * (by as i128 - cy as i128)
                + (bx as i128) * (cy as i128 - ay as i128)
                + (cx as i128) * (ay as i128 - by as i128);
            let want = match exact.signum() {
                1 => Sign::Positive,
                -1 => Sign::Negative,
                _ => Sign::Zero,
            };
            let f = |x: i64, y: i64| v(x as f64 * scale, y as f64 * scale);
            let (a, b, c) = (f(ax, ay), f(bx, by), f(cx, cy));
            assert_eq!(orientation(a, b, c), want, "case {k}");
            assert_eq!(orientation(b, c, a), want);
            assert_eq!(orientation(b, a, c), want.flip());
            if Sign::of(signed_area(a, b, c)) != want {
                naive_wrong += 1;
            }
        }
        // the filter + exact path matters: the plain formula fails on some of these
        assert!(naive_wrong > 0, "test set does not exercise near-degenerate cases");
    }

    // ---- the paper's convention and its eight patterns ----

    #[test]
    fn paper_convention_particle_above_crack_along_x() {
        let (x3, x4) = (v(-1., 0.), v(1., 0.));
        let (xp, xn) = (v(0., 1.), v(0., -1.));
        let signs = [
            orientation(xp, xn, x3),
            orientation(xp, xn, x4),
            orientation(x3, x4, xp),
            orientation(x3, x4, xn),
        ];
        use Sign::*;
        assert_eq!(signs, [Negative, Positive, Positive, Negative]); // (−++−)
        assert_eq!(segment_pattern(xp, xn, x3, x4), Some((Side::Above, Pattern::Proper)));
        assert_eq!(cross(&[x3, x4], xp, xn), Side::Above);
        assert_eq!(cross(&[x3, x4], xn, xp), Side::Below);
        // reversing the crack direction swaps above and below
        assert_eq!(cross(&[x4, x3], xp, xn), Side::Below);
    }

    #[test]
    fn every_sign_pattern_of_subtask_3() {
        let (x3, x4) = (v(-1., 0.), v(1., 0.));
        let up = v(0.25, 1.0);
        let down = mirror(up);
        // (particle, node, expected)
        let cases = [
            (up, v(0.1, -1.0), Some((Side::Above, Pattern::Proper))), // (−++−)
            (up, v(0.3, 0.0), Some((Side::Above, Pattern::NodeOnSegment))), // (−++0)
            (up, x3, Some((Side::Above, Pattern::NodeAtStart))), // (0++0)
            (up, x4, Some((Side::Above, Pattern::NodeAtEnd))), // (−0+0)
            (down, v(0.1, 1.0), Some((Side::Below, Pattern::Proper))), // (+−−+)
            (down, v(0.3, 0.0), Some((Side::Below, Pattern::NodeOnSegment))), // (+−−0)
            (down, x3, Some((Side::Below, Pattern::NodeAtStart))), // (0−−0)
            (down, x4, Some((Side::Below, Pattern::NodeAtEnd))), // (+0−0)
        ];
        use Sign::*;
        let expect_signs = [
            [Negative, Positive, Positive, Negative],
            [Negative, Positive, Positive, Zero],
            [Zero, Positive, Positive, Zero],
            [Negative, Zero, Positive, Zero],
            [Positive, Negative, Negative, Positive],
            [Positive, Negative, Negative, Zero],
            [Zero, Negative, Negative, Zero],
            [Positive, Zero, Negative, Zero],
        ];
        for (k, ((xp, xn, want), signs)) in cases.iter().zip(expect_signs).enumerate() {
            let got = [
                orientation(*xp, *xn, x3),
                orientation(*xp, *xn, x4),
                orientation(x3, x4, *xp),
                orientation(x3, x4, *xn),
            ];
            assert_eq!(got, signs, "case {k}");
            assert_eq!(segment_pattern(*xp, *xn, x3, x4), *want, "case {k}");
            assert_eq!(cross(&[x3, x4], *xp, *xn), want.unwrap().0, "case {k}");
        }
        // other combinations: no crossing of the segment
        assert_eq!(segment_pattern(up, v(0.3, 0.5), x3, x4), None); // same side
        assert_eq!(segment_pattern(up, v(3.0, -1.0), x3, x4), None); // passes beyond x4
        assert_eq!(segment_pattern(v(0.0, 0.0), down, x3, x4), None); // particle on crack
        assert_eq!(segment_pattern(v(-2., 0.), v(2., 0.), x3, x4), None); // collinear
        // line through x4 strictly between particle and node: (−0+−), not listed
        assert_eq!(segment_pattern(v(0., 1.), v(2., -1.), x3, x4), None);
    }

    /// Node exactly on a segment, at a segment's start and at its end, for a particle
    /// above and the mirrored particle below; single-segment and multi-segment cracks.
    #[test]
    fn node_on_crack_classified_and_mirror_exact() {
        let crack = [v(-1., 0.), v(0., 0.), v(0.5, 0.), v(1.25, 0.)];
        let ext = Extent::of(&crack);
        let particles = [v(0.2, 0.3), v(-0.7, 0.05), v(1.0, 0.9), v(-1.3, 0.4), v(1.6, 0.2)];
        let nodes_on_crack = [
            v(0.25, 0.),  // interior of a segment
            v(-1., 0.),   // start tip (start of the first segment)
            v(0., 0.),    // interior point: end of segment 0 and start of segment 1
            v(0.5, 0.),   // interior point
            v(1.25, 0.),  // end tip (end of the last segment)
        ];
        for xp in particles {
            for xn in nodes_on_crack {
                let above = crossing(&crack, &ext, xp, xn);
                let below = crossing(&crack, &ext, mirror(xp), mirror(xn));
                assert_eq!(above, Side::Above, "{xp:?} -> {xn:?}");
                assert_eq!(below, Side::Below, "{xp:?} -> {xn:?}");
            }
        }
        // the single-segment versions are exactly the paper's patterns
        let seg = [v(-1., 0.), v(1., 0.)];
        for (xn, pat) in [
            (v(0.25, 0.), Pattern::NodeOnSegment),
            (v(-1., 0.), Pattern::NodeAtStart),
            (v(1., 0.), Pattern::NodeAtEnd),
        ] {
            let xp = v(0.3, 0.7);
            assert_eq!(segment_pattern(xp, xn, seg[0], seg[1]), Some((Side::Above, pat)));
            assert_eq!(segment_pattern(mirror(xp), xn, seg[0], seg[1]), Some((Side::Below, pat)));
            assert_eq!(cross(&seg, xp, xn), Side::Above);
            assert_eq!(cross(&seg, mirror(xp), xn), Side::Below);
        }
        // a node at an interior crack point is ONE crossing (the paper's literal
        // per-segment count would be two, i.e. no crossing)
        let d = crossing_detail(&crack, &ext, v(0.2, 0.3), v(0., 0.)).unwrap();
        assert_eq!((d.side, d.count, d.site), (Side::Above, 1, Site::Vertex(1)));
        // a particle exactly on the crack is ignored
        assert_eq!(cross(&crack, v(0.25, 0.), v(0.25, -1.)), Side::None);
    }

    /// The crack-patch situation: a crack on y = 0, particles and nodes mirrored about
    /// it; the classification of a mirrored pair must be the exact mirror, including
    /// nodes on the crack and lines through crack points.
    #[test]
    fn mirror_symmetry_is_exact_on_a_grid() {
        let dx = 0.1;
        // crack points at half-cells and on nodes, ending mid-cell
        let crack: Vec<Vector> = [-0.05, 0.1, 0.25, 0.3, 0.45, 0.55].iter().map(|&x| v(x, 0.0)).collect();
        let ext = Extent::of(&crack);
        let mut n_cross = 0;
        for i in -2..=9 {
            for j in -3..=3 {
                let xn = v(i as f64 * dx, j as f64 * dx);
                for pi in -4..=16 {
                    for pj in [-5, -3, -1, 1, 3, 5] {
                        let xp = v(pi as f64 * 0.25 * dx + 0.0125, pj as f64 * 0.25 * dx);
                        let s = crossing(&crack, &ext, xp, xn);
                        let m = crossing(&crack, &ext, mirror(xp), mirror(xn));
                        assert_eq!(m, s.flip(), "{xp:?} {xn:?}");
                        if s != Side::None {
                            n_cross += 1;
                            // on this straight crack the sense is the particle's side
                            assert_eq!(s, if xp.y > 0.0 { Side::Above } else { Side::Below });
                        }
                    }
                }
            }
        }
        assert!(n_cross > 100);
    }

    // ---- subtask 4: several segments ----

    #[test]
    fn zig_zag_odd_and_even_crossings() {
        // zig-zag between y = -1 and y = 1, running left to right
        let crack = [v(0., -1.), v(1., 1.), v(2., -1.), v(3., 1.), v(4., -1.)];
        let ext = Extent::of(&crack);
        // horizontal line at y = 0 from x=-1: crosses 1, 2, 3, 4 segments
        let xp = v(-1.0, 0.0);
        let want = [(0.7, 1usize), (1.7, 2), (2.7, 3), (3.7, 4)];
        for (x, n) in want {
            let got = crossing_detail(&crack, &ext, xp, v(x, 0.0));
            if n % 2 == 1 {
                let c = got.unwrap();
                assert_eq!(c.count, n);
            } else {
                assert!(got.is_none(), "even count {n} must not cross");
            }
        }
        // sense: segment 0 goes up-right, particle at x=-1 is on its left → above
        assert_eq!(crossing(&crack, &ext, xp, v(0.7, 0.0)), Side::Above);
        // three crossings: senses (above, below, above); the nearest the node decides
        let c = crossing_detail(&crack, &ext, xp, v(2.7, 0.0)).unwrap();
        assert_eq!((c.side, c.site), (Side::Above, Site::Segment(2)));
    }

    #[test]
    fn odd_count_with_mixed_senses_uses_crossing_nearest_node() {
        // A crack that crosses the particle-node line three times where the senses
        // differ: a "C" shape. Line from (0,0) to (10,0).
        // segment 0: (1,-1)→(1,1)   particle at x=0 is left of upward travel → Above
        // segment 1: (1,1)→(5,1)    no crossing
        // segment 2: (5,1)→(5,-1)   particle left? travel down, left is +x → particle Below
        // segment 3: (5,-1)→(8,-1)
        // segment 4: (8,-1)→(8,1)   travel up, left is -x → particle Above
        let crack = [v(1., -1.), v(1., 1.), v(5., 1.), v(5., -1.), v(8., -1.), v(8., 1.)];
        let ext = Extent::of(&crack);
        let (xp, xn) = (v(0., 0.), v(10., 0.));
        let c = crossing_detail(&crack, &ext, xp, xn).unwrap();
        assert_eq!((c.count, c.side, c.site), (3, Side::Above, Site::Segment(4)));
        // node between segment 2 and 4: two crossings → none
        assert_eq!(cross(&crack, xp, v(6.5, 0.)), Side::None);
        // from the other end: nearest-to-node crossing is segment 0; particle at x=10
        // is right of its upward travel → Below
        let c = crossing_detail(&crack, &ext, xn, xp).unwrap();
        assert_eq!((c.count, c.side, c.site), (3, Side::Below, Site::Segment(0)));
    }

    #[test]
    fn line_through_an_interior_crack_point() {
        // straight crack with an interior point at the origin
        let crack = [v(-1., 0.), v(0., 0.), v(1., 0.)];
        // transversal, passing exactly through the shared point: one crossing
        let d = crossing_detail(&crack, &Extent::of(&crack), v(-0.5, 0.5), v(0.5, -0.5)).unwrap();
        assert_eq!((d.side, d.count, d.site), (Side::Above, 1, Site::Vertex(1)));
        assert_eq!(cross(&crack, v(-0.5, -0.5), v(0.5, 0.5)), Side::Below);
        // a "V" crack touching the line at its interior point: no crossing
        let v_crack = [v(-1., 1.), v(0., 0.), v(1., 1.)];
        assert_eq!(cross(&v_crack, v(-1., 0.), v(1., 0.)), Side::None);
        // a crack running along the line for one segment and leaving on the other side
        let s_crack = [v(-1., 1.), v(-0.5, 0.), v(0.5, 0.), v(1., -1.)];
        assert_eq!(cross(&s_crack, v(-2., 0.), v(2., 0.)), Side::Below);
        // ... or returning to the same side: no crossing
        let u_crack = [v(-1., 1.), v(-0.5, 0.), v(0.5, 0.), v(1., 1.)];
        assert_eq!(cross(&u_crack, v(-2., 0.), v(2., 0.)), Side::None);
    }

    #[test]
    fn node_at_a_kink_uses_the_local_wedge() {
        // left turn at the origin: (-1,0) → (0,0) → (1,1). Above = angles (45°, 180°).
        let crack = [v(-1., 0.), v(0., 0.), v(1., 1.)];
        let node = v(0., 0.);
        let at = |deg: f64| {
            let r = deg.to_radians();
            v(0.5 * r.cos(), 0.5 * r.sin())
        };
        for (deg, want) in [
            (100.0, Side::Above),
            (60.0, Side::Above),
            (170.0, Side::Above),
            (30.0, Side::Below), // above segment 0's line, but under segment 1
            (200.0, Side::Below),
            (300.0, Side::Below),
        ] {
            assert_eq!(cross(&crack, at(deg), node), want, "{deg}°");
            // mirrored configuration: right turn, sides swap
            let m: Vec<Vector> = crack.iter().map(|&p| mirror(p)).collect();
            assert_eq!(cross(&m, mirror(at(deg)), node), want.flip(), "mirror {deg}°");
        }
    }

    #[test]
    fn crack_tips() {
        let crack = [v(0., 0.), v(1., 0.), v(2., 0.)];
        // passing beyond either tip: no crossing
        assert_eq!(cross(&crack, v(2.5, 1.), v(2.5, -1.)), Side::None);
        assert_eq!(cross(&crack, v(-0.1, 1.), v(-0.2, -1.)), Side::None);
        assert_eq!(cross(&crack, v(1.9, 1.), v(2.2, -1.)), Side::None); // beyond tip, inside extent in x
        // just inside a tip: crossing
        assert_eq!(cross(&crack, v(1.9, 1.), v(1.95, -1.)), Side::Above);
        // grazing exactly through a tip: no crossing (paper's list)
        assert_eq!(cross(&crack, v(1., 1.), v(3., -1.)), Side::None);
        assert_eq!(cross(&crack, v(-1., 1.), v(1., -1.)), Side::None);
        // node exactly at a tip: crossing with the particle's side (paper: 0++0, −0+0)
        assert_eq!(cross(&crack, v(2.5, 0.5), v(2., 0.)), Side::Above);
        assert_eq!(cross(&crack, v(-0.5, -0.5), v(0., 0.)), Side::Below);
    }

    #[test]
    fn extent_screening() {
        let crack = [v(0., 0.), v(1., 0.2), v(2., -0.1)];
        let ext = Extent::of(&crack);
        assert_eq!(ext.min, v(0., -0.1));
        assert_eq!(ext.max, v(2., 0.2));
        // far pair: rectangle misses the extent, never a crossing
        assert!(!ext.overlaps_rect(v(10., 10.), v(11., -10.)));
        assert!(!ext.overlaps_rect(v(10., 10.), v(11., 12.)));
        assert!(!ext.overlaps_rect(v(-3., 1.), v(-2.5, -1.)));
        assert_eq!(cross(&crack, v(10., 1.), v(10.5, -1.)), Side::None);
        // touching the extent counts (closed test)
        assert!(!ext.overlaps_rect(v(2., 0.2000001), v(3., 1.5)));
        assert!(ext.overlaps_rect(v(2., 0.2), v(3., 1.5)));
        // a stale extent that misses the crack screens it out (Subtask 1 is trusted)
        assert_eq!(crossing(&crack, &Extent::of(&[v(5., 5.)]), v(0.5, 1.), v(0.5, -1.)), Side::None);
        assert_eq!(crossing(&crack, &ext, v(0.5, 1.), v(0.5, -1.)), Side::Above);
        // empty extent and degenerate cracks
        assert!(!Extent::EMPTY.overlaps_rect(v(0., 0.), v(1., 1.)));
        assert_eq!(cross(&[], v(0., 1.), v(0., -1.)), Side::None);
        assert_eq!(cross(&[v(0., 0.)], v(0., 1.), v(0., -1.)), Side::None);
    }

    /// Rotating every point by 90°, 180°, 270° leaves every classification unchanged
    /// (rotation preserves left/right), checked exhaustively on random configurations
    /// and on the exact-degenerate ones of the other tests.
    #[test]
    fn orientation_invariance_under_rotation() {
        let mut rng = Rng(777);
        let mut configs: Vec<(Vec<Vector>, Vector, Vector)> = Vec::new();
        for _ in 0..3000 {
            let n = 2 + (rng.next() % 6) as usize;
            let crack: Vec<Vector> = (0..n).map(|_| v(rng.unit() * 4. - 2., rng.unit() * 4. - 2.)).collect();
            configs.push((crack, v(rng.unit() * 4. - 2., rng.unit() * 4. - 2.), v(rng.unit() * 4. - 2., rng.unit() * 4. - 2.)));
        }
        // grid-aligned degenerate configurations (nodes on crack points and segments)
        let zig = vec![v(0., -1.), v(1., 1.), v(2., -1.), v(3., 1.)];
        for i in -2..=8 {
            for j in -2..=2 {
                for (pi, pj) in [(1, 3), (-1, -3), (5, 1), (3, -1)] {
                    configs.push((zig.clone(), v(pi as f64 * 0.25, pj as f64 * 0.25), v(i as f64 * 0.5, j as f64 * 0.5)));
                }
            }
        }
        let mut seen = [0usize; 3];
        for (crack, xp, xn) in &configs {
            let s = cross(crack, *xp, *xn);
            seen[s as usize] += 1;
            let mut c = crack.clone();
            let (mut p, mut n) = (*xp, *xn);
            for _ in 0..3 {
                c.iter_mut().for_each(|q| *q = rot90(*q));
                p = rot90(p);
                n = rot90(n);
                assert_eq!(cross(&c, p, n), s);
            }
            let c180: Vec<Vector> = crack.iter().map(|&q| rot180(q)).collect();
            assert_eq!(cross(&c180, rot180(*xp), rot180(*xn)), s);
        }
        assert!(seen.iter().all(|&k| k > 100), "{seen:?}");
    }

    /// Parity cross-check against an independent brute force: for random generic
    /// configurations the crossing exists iff the number of proper segment
    /// intersections (via `segment_intersection`) is odd.
    #[test]
    fn parity_matches_segment_intersections() {
        let mut rng = Rng(4242);
        for _ in 0..5000 {
            let n = 2 + (rng.next() % 7) as usize;
            let crack: Vec<Vector> = (0..n).map(|_| v(rng.unit(), rng.unit())).collect();
            let (xp, xn) = (v(rng.unit(), rng.unit()), v(rng.unit(), rng.unit()));
            let k = crack
                .windows(2)
                .filter(|w| segment_intersection(xp, xn, w[0], w[1]).is_some())
                .count();
            assert_eq!(cross(&crack, xp, xn) != Side::None, k % 2 == 1);
        }
    }

    /// The indexed crossing test gives the full result (side, count and deciding site) for
    /// random polylines and for polylines and pairs on a small integer lattice, where
    /// crack points on the particle–node line, nodes on the crack, repeated points and
    /// collinear segments are frequent; long polylines use several index chunks.
    #[test]
    fn indexed_crossing_equals_the_full_scan() {
        let mut rng = Rng(77);
        for trial in 0..20000 {
            let lattice = trial % 2 == 0;
            let n = 2 + (rng.next() % if trial % 10 == 0 { 200 } else { 12 }) as usize;
            let pt = |rng: &mut Rng| if lattice { v(rng.int(4) as f64 * 0.5, rng.int(4) as f64 * 0.5) } else { v(rng.unit() * 4.0 - 2.0, rng.unit() * 4.0 - 2.0) };
            let crack: Vec<Vector> = (0..n).map(|_| pt(&mut rng)).collect();
            let ext = Extent::of(&crack);
            let index = SegmentIndex::of(&crack);
            for _ in 0..10 {
                let (xp, xn) = (pt(&mut rng), pt(&mut rng));
                assert_eq!(
                    crossing_detail_indexed(&crack, &ext, &index, xp, xn),
                    crossing_detail(&crack, &ext, xp, xn),
                    "crack {crack:?}, particle {xp:?}, node {xn:?}"
                );
            }
        }
    }

    #[test]
    fn segment_index_finds_exactly_the_segments_whose_box_meets_the_query() {
        let mut rng = Rng(5);
        for _ in 0..2000 {
            let n = 2 + (rng.next() % 300) as usize;
            let crack: Vec<Vector> = (0..n).map(|_| v(rng.unit() * 10.0, rng.unit() * 10.0)).collect();
            let index = SegmentIndex::of(&crack);
            let (a, b) = (v(rng.unit() * 10.0, rng.unit() * 10.0), v(rng.unit() * 10.0, rng.unit() * 10.0));
            let (lo, hi) = (a.inf(&b), a.sup(&b));
            let want: Vec<usize> = (0..n - 1)
                .filter(|&i| {
                    let e = Extent::of(&crack[i..i + 2]);
                    !(hi.x < e.min.x || lo.x > e.max.x || hi.y < e.min.y || lo.y > e.max.y)
                })
                .collect();
            assert_eq!(index.near(lo, hi).collect::<Vec<_>>(), want);
        }
    }

    // ---- tangent, normal, intersections ----

    #[test]
    fn segment_normal_points_from_above_to_below() {
        let n = segment_normal(v(-1., 0.), v(1., 0.)).unwrap();
        assert_eq!(n, v(0., -1.));
        assert_eq!(segment_tangent(v(-1., 0.), v(1., 0.)).unwrap(), v(1., 0.));
        // for any segment: n is unit, ⟂ t, and points to the "below" (right) side
        let (a, b) = (v(0.3, -0.2), v(-1.1, 0.9));
        let (t, n) = (segment_tangent(a, b).unwrap(), segment_normal(a, b).unwrap());
        assert!((n.norm() - 1.0).abs() < 1e-15 && n.dot(&t).abs() < 1e-15);
        let mid = (a + b) * 0.5;
        assert_eq!(orientation(a, b, mid - n), Sign::Positive); // above = behind the normal
        assert_eq!(orientation(a, b, mid + n), Sign::Negative);
        assert_eq!(segment_normal(a, a), None);
        assert_eq!(segment_tangent(a, a), None);
    }

    #[test]
    fn segment_intersection_cases() {
        // proper crossing
        let (s, t) = segment_intersection(v(0., -1.), v(0., 3.), v(-1., 0.), v(3., 0.)).unwrap();
        assert!((s - 0.25).abs() < 1e-15 && (t - 0.25).abs() < 1e-15);
        // touching at an endpoint: exact parameters
        assert_eq!(segment_intersection(v(0., 0.), v(1., 1.), v(1., 1.), v(2., 0.)), Some((1.0, 0.0)));
        assert_eq!(segment_intersection(v(0., 1.), v(2., 1.), v(1., 1.), v(1., 3.)), Some((0.5, 0.0)));
        // T-junction: a's end lies on p-q interior
        let (s, t) = segment_intersection(v(0., 0.), v(4., 0.), v(1., 2.), v(1., 0.)).unwrap();
        assert_eq!((s, t), (0.25, 1.0));
        // disjoint, parallel, collinear, degenerate
        assert_eq!(segment_intersection(v(0., 0.), v(1., 0.), v(2., -1.), v(2., 1.)), None);
        assert_eq!(segment_intersection(v(0., 0.), v(1., 0.), v(0., 1.), v(1., 1.)), None);
        assert_eq!(segment_intersection(v(0., 0.), v(2., 0.), v(1., 0.), v(3., 0.)), None);
        assert_eq!(segment_intersection(v(0., 0.), v(0., 0.), v(-1., 0.), v(1., 0.)), None);
        // lines cross but outside segment b
        assert_eq!(segment_intersection(v(0., -1.), v(0., 1.), v(1., 0.), v(2., 0.)), None);
        // consistency on random segments: both parametrisations give the same point
        let mut rng = Rng(99);
        let mut hits = 0;
        for _ in 0..20000 {
            let (p, q, a, b) = (
                v(rng.unit(), rng.unit()),
                v(rng.unit(), rng.unit()),
                v(rng.unit(), rng.unit()),
                v(rng.unit(), rng.unit()),
            );
            if let Some((s, t)) = segment_intersection(p, q, a, b) {
                hits += 1;
                assert!((0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t));
                let (x1, x2) = (p + (q - p) * s, a + (b - a) * t);
                assert!((x1 - x2).norm() < 1e-9, "{p:?} {q:?} {a:?} {b:?}");
                // symmetric in the argument order
                let (t2, s2) = segment_intersection(a, b, p, q).unwrap();
                assert!((s - s2).abs() < 1e-9 && (t - t2).abs() < 1e-9);
            } else {
                assert!(segment_intersection(a, b, p, q).is_none());
            }
        }
        assert!(hits > 1000);
    }

    /// A node on the straight part of a crack next to a kink (a notch on a grid line
    /// that has grown a segment at −60°, issue 22): every particle it sees across the
    /// crack, including those beyond the kinked segment whose lines touch the crack at
    /// the node and cross the kinked segment, is classified by its own side — two
    /// fields, 1 above and 2 below, never field 0 next to them.
    #[test]
    fn node_on_a_kinked_crack_sees_each_particle_on_its_own_side() {
        let (s, c) = (60f64.to_radians().sin(), 60f64.to_radians().cos());
        let kink = [v(-3.0, 0.0), v(0.5, 0.0), v(0.5 + 0.5 * c, -0.5 * s)];
        let node = v(0.0, 0.0);
        // Above the straight part, in the wedge below both segments, and beyond the
        // kinked segment (joined to the material above round the kink).
        assert_eq!(cross(&kink, v(-0.25, 0.25), node), Side::Above);
        assert_eq!(cross(&kink, v(-0.25, -0.25), node), Side::Below);
        assert_eq!(cross(&kink, v(0.75, -0.25), node), Side::Above);
        assert_eq!(cross(&kink, v(0.75, -0.75), node), Side::Below);
        // Its mirror image about y = 0 classifies the mirrored particles mirrored.
        let mirrored: Vec<Vector> = kink.iter().map(|&p| mirror(p)).collect();
        assert_eq!(cross(&mirrored, v(0.75, 0.25), node), Side::Below);
        // A node just off the crack keeps the parity rule: beyond the kinked segment is
        // its own side (field 0) seen from above, across it seen from below.
        assert_eq!(cross(&kink, v(0.75, -0.25), v(0.0, 1e-9)), Side::None);
        assert_eq!(cross(&kink, v(0.75, -0.25), v(0.0, -1e-9)), Side::Above);
    }
}
