//! The crack-tip zone (2D): a pair whose line meets the crack within a zone length z of
//! a tip is shared between the crossing field and field 0, in proportion to how far
//! behind the tip it meets the crack — the "transparency" of Organ, Fleming & Belytschko
//! (1996, Comput. Mech. 18:225–235) carried over from meshfree weights to CRAMP's fields.
//!
//! Why. CRAMP's rule (Nairn 2003 §2.1) is all-or-nothing per pair: a pair is in the
//! crossing field iff its line meets the crack. Seen from one node, the material in the
//! crossing field is the crack's "shadow", bounded by the crack and by the ray from the
//! node through the tip, so every split node near a tip also cuts the material *ahead*
//! of the tip along its own ray (the spurious discontinuity of the visibility criterion
//! that transparency removes). Which pairs are cut changes in steps as the tip, the
//! particles or the nodes move, so the crack the grid sees ends somewhere within a cell
//! of the tip, at a place that depends on where the tip sits in its cell: J and K of one
//! static crack moved by ±3–8 % with the tip's position (issue 22; docs/scene.md).
//!
//! The rule. A pair whose line meets the crack at arc distance s < z behind the tip
//! puts the fraction φ = s/z of its particle's mass, momentum and force into the
//! crossing field and 1 − φ into field 0, and moves with the two fields' velocities in
//! those shares; φ = 1 (CRAMP) for s ≥ z. On the ray through the tip φ = 0, the value
//! of the pairs that miss the crack, so the shadow's edge no longer cuts the material,
//! and a node's crossing field fills continuously as the tip, the particles and the
//! nodes move. (A zone centred on the tip, φ = ½ + s/z with the crack's continuation
//! cut by ½ − s′/z, was tried and is worse: the partly cut pairs ahead of the tip act
//! as crack, +8 … +12 % in K_I on the SENT below.)
//!
//! Nodes on the crack's line. A node lying on the crack (a crack along a node row) has
//! material across the crack on both sides, and one on the crack's straight
//! continuation ahead of the tip sees none across: CRAMP's rule splits every particle of
//! the first, including those ahead of the tip, and none of the second, including those
//! behind it, so such a crack ends at a node wherever its tip is (K_I of the SENT below
//! +28 % … −3 % as the tip crosses a cell). Such a node (within 10⁻³ of a cell of the
//! line: crack points moving in the centre-of-mass velocity leave the row by round-off)
//! takes each particle into the field of the particle's side in the share s_p/z, s_p the
//! arc distance behind the tip of the particle's own projection on the crack, and keeps
//! the rest of every particle in field 0 as material joined across the crack
//! ([`on_line`]; such a node may hold fields 0, 1 and 2 at once). SENT at h = 1 mm, tip
//! at a = 6 + f·h, f = 0.05 … 0.95 in steps of 0.05, 2×2 contour: crack on a node row
//! +27.8 … −3.4 % (spread 31 %) without the zone, −0.6 … +4.5 % (5.1 %) with a one-cell
//! zone; crack between node rows −2.9 … +1.0 % (3.9 %) with it. What is left: a field
//! that only a few shared pairs fill (the side fields of a node ahead of the tip just
//! after the tip passes a particle column) holds the unbalanced force of those
//! particles alone, so K jumps by ~4 % within 0.02 h of the tip passing a column.
//!
//! Only tips inside the material have a zone: a tip whose point z + l_p ahead is not
//! within 1.5 l_p of a particle (the start of an edge crack, a tip about to break
//! through) keeps CRAMP's rule, so a crack face at a free surface stays fully open.

use super::geometry::{orientation, Crossing, Side, Sign, Site};
use super::Crack;
use crate::dim::Vector;

/// One tip with a zone: its crack, the tip, and the arc distance from each crack point
/// within z of the tip.
#[derive(Clone, Debug)]
pub struct TipZone {
    pub crack: usize,
    /// The tip.
    pub tip: Vector,
    /// Is the tip the crack's first point?
    pub at_start: bool,
    /// Arc length from each crack point to the tip (0 at the tip), for the points the zone
    /// reaches, indexed by crack point (`f64::INFINITY` beyond the zone).
    pub arc: Vec<f64>,
}

/// The zones of this step: every crack end whose point z + l_p ahead (l_p the largest
/// particle half-width) lies within 1.5 half-widths of some particle. The arc distances
/// reach z + `walk` behind the tip, so that the nodes on the crack's line whose support
/// reaches into the zone are found ([`on_line`]).
pub fn zones(out: &mut Vec<TipZone>, cracks: &[Crack], z: f64, walk: f64, x: &[Vector], lp: &[Vector]) {
    // The entries (and their arc arrays) of the last step are reused: the step does not
    // allocate once the number of zones and crack points stop growing.
    let mut used = 0;
    if z > 0.0 {
        let lmax = lp.iter().fold(0.0f64, |m, l| m.max(l.x).max(l.y));
        for (c, crack) in cracks.iter().enumerate() {
            let pts = &crack.points;
            let n = pts.len();
            if n < 2 {
                continue;
            }
            for at_start in [true, false] {
                let (tip_index, prev) = if at_start { (0, 1) } else { (n - 1, n - 2) };
                let tip = pts[tip_index];
                let d = tip - pts[prev];
                let l = d.norm();
                if l == 0.0 {
                    continue;
                }
                // The domains of a lattice only touch, the crack runs along their edges and
                // the material moves: hence 1.5 half-widths; a point l_p or more outside the
                // body's edge is 2 l_p from the nearest particle.
                let probe = tip + d * ((z + lmax) / l);
                let inside = x.iter().zip(lp).any(|(xp, l)| (xp.x - probe.x).abs() <= 1.5 * l.x && (xp.y - probe.y).abs() <= 1.5 * l.y);
                if !inside {
                    continue;
                }
                if used == out.len() {
                    out.push(TipZone { crack: c, tip, at_start, arc: Vec::new() });
                }
                let zone = &mut out[used];
                used += 1;
                *zone = TipZone { crack: c, tip, at_start, arc: std::mem::take(&mut zone.arc) };
                let arc = &mut zone.arc;
                arc.clear();
                arc.resize(n, f64::INFINITY);
                arc[tip_index] = 0.0;
                // Walk from the tip along the crack until z + walk behind it.
                let (mut s, mut j) = (0.0, tip_index);
                while s < z + walk {
                    let next = if at_start { j + 1 } else { j.wrapping_sub(1) };
                    if next >= n {
                        break;
                    }
                    s += (pts[next] - pts[j]).norm();
                    arc[next] = s;
                    j = next;
                }
            }
        }
    }
    out.truncate(used);
}

/// The share φ = s/z of the pair's particle in the crossing field, for a pair whose line
/// crosses crack `zone.crack` (the exact crossing test's result `x`) at arc distance
/// s < z behind the tip. None beyond the zone, and for a node on the crack (see Limits).
pub fn share(zone: &TipZone, points: &[Vector], x: &Crossing, xp: Vector, xn: Vector, z: f64) -> Option<f64> {
    let on_crack = match x.site {
        Site::Vertex(j) => points[j] == xn,
        Site::Segment(i) => orientation(points[i], points[i + 1], xn) == Sign::Zero,
    };
    if on_crack {
        return None;
    }
    let s = match x.site {
        Site::Vertex(j) => zone.arc[j],
        Site::Segment(i) => {
            // The segment's end nearer the tip (along the crack) and its arc distance.
            let (near, far) = if zone.at_start { (i, i + 1) } else { (i + 1, i) };
            let a = zone.arc[near];
            if !a.is_finite() {
                return None;
            }
            a + (crossing_point(points[i], points[i + 1], xp, xn) - points[near]).norm().min((points[far] - points[near]).norm())
        }
    };
    (s < z).then(|| s / z)
}

/// The nearest point to `x` on the zone's part of the crack and on the crack's straight
/// continuation ahead of the tip: (squared distance, arc distance s behind the tip —
/// negative ahead of it —, segment). None if the zone has no segment.
fn project(zone: &TipZone, points: &[Vector], x: Vector) -> Option<(f64, f64, usize)> {
    let tip_index = if zone.at_start { 0 } else { points.len() - 1 };
    let mut best: Option<(f64, f64, usize)> = None;
    for i in 0..points.len().saturating_sub(1) {
        let (near, far) = if zone.at_start { (i, i + 1) } else { (i + 1, i) };
        let a = zone.arc[near];
        if !a.is_finite() {
            continue;
        }
        let d = points[far] - points[near];
        let l2 = d.norm_squared();
        if l2 == 0.0 {
            continue;
        }
        let t = (x - points[near]).dot(&d) / l2;
        // The tip's segment goes on beyond the tip (t < 0 there).
        let t = if near == tip_index { t.min(1.0) } else { t.clamp(0.0, 1.0) };
        let dist = (x - (points[near] + d * t)).norm_squared();
        if best.is_none_or(|(bd, _, _)| dist < bd) {
            best = Some((dist, a + t * l2.sqrt(), i));
        }
    }
    best
}

/// A node lying on the crack, or on its straight continuation ahead of the tip, within
/// `tol`: the side of the crack particle `xp` is on and its share φ = s_p/z in that
/// side's field (capped at 1), s_p the arc distance behind the tip of the particle's own
/// projection on the crack; 1 − φ goes to field 0, which such a node keeps for the
/// material joined across the crack. A particle ahead of the tip, or on the line, is
/// wholly in field 0. None if the node is not on the line (the crossing rule applies).
///
/// Why. A node on the crack has material across it on both sides and sees every
/// particle in its support across the crack, including those ahead of the tip (CRAMP's
/// rule splits them all), while a node on the continuation ahead of the tip sees none
/// across, including those behind it. So a crack along a node row ends at a node,
/// wherever its tip is: K_I moved from +15 % to −2.5 % as the tip crossed a cell
/// (issue 22). Sharing by where each particle lies along the crack makes the cut follow
/// the tip.
pub fn on_line(zone: &TipZone, points: &[Vector], xp: Vector, xn: Vector, z: f64, tol: f64) -> Option<(Side, f64)> {
    let (dn, _, _) = project(zone, points, xn)?;
    if dn > tol * tol {
        return None;
    }
    let (_, sp, i) = project(zone, points, xp)?;
    if sp <= 0.0 {
        return Some((Side::None, 1.0));
    }
    let side = match orientation(points[i], points[i + 1], xp) {
        Sign::Positive => Side::Above,
        Sign::Negative => Side::Below,
        Sign::Zero => return Some((Side::None, 1.0)),
    };
    Some((side, (sp / z).min(1.0)))
}

/// Is node `xn` on the line of a zone (see [`on_line`])?
pub fn node_on_line(zones: &[TipZone], cracks: &[Crack], xn: Vector, tol: f64) -> bool {
    zones.iter().any(|zn| project(zn, &cracks[zn.crack].points, xn).is_some_and(|(d, _, _)| d <= tol * tol))
}

/// The point where the line through a, b meets the line through p, q (rounded; the
/// caller knows they cross).
fn crossing_point(a: Vector, b: Vector, p: Vector, q: Vector) -> Vector {
    let d = b - a;
    let r = q - p;
    let den = d.x * r.y - d.y * r.x;
    if den == 0.0 {
        return a;
    }
    let t = ((p.x - a.x) * r.y - (p.y - a.y) * r.x) / den;
    a + d * t.clamp(0.0, 1.0)
}


#[cfg(test)]
mod tests {
    use super::*;
    use crate::crack::geometry::{crossing_detail, Extent};
    use crate::crack::ContactLaw;

    fn crack(points: Vec<Vector>) -> Crack {
        Crack::new(points, ContactLaw::None, 0.9, 0.95)
    }

    /// A straight crack y = 0.5 from x = −1 to the tip at x = 2.3 inside a lattice of
    /// particles: pairs crossing it s behind the tip get φ = s/z, none beyond z, none for a
    /// node on the crack; an edge tip outside the material gets no zone.
    #[test]
    fn shares_follow_the_distance_behind_the_tip() {
        let pts = vec![Vector::new(-1.0, 0.5), Vector::new(0.0, 0.5), Vector::new(1.0, 0.5), Vector::new(2.0, 0.5), Vector::new(2.3, 0.5)];
        let c = crack(pts.clone());
        let x: Vec<Vector> = (0..40).flat_map(|i| (0..8).map(move |j| Vector::new(0.25 + 0.5 * i as f64, -1.75 + 0.5 * j as f64))).collect();
        let lp = vec![Vector::new(0.25, 0.25); x.len()];
        let z = 1.0;
        let mut zones = Vec::new();
        super::zones(&mut zones, std::slice::from_ref(&c), z, 0.0, &x, &lp);
        // The start (x = −1) is outside the material (particles from x = 0): no zone.
        assert_eq!(zones.len(), 1);
        let zn = &zones[0];
        assert!(!zn.at_start && zn.tip == Vector::new(2.3, 0.5));
        let ext = Extent::of(&pts);
        let phi = |xp: Vector, xn: Vector| crossing_detail(&pts, &ext, xp, xn).and_then(|x| share(zn, &pts, &x, xp, xn, z));
        // Crossing at x = 2.0 (0.3 behind): φ = 0.3.
        let got = phi(Vector::new(2.0, 0.25), Vector::new(2.0, 1.0)).unwrap();
        assert!((got - 0.3).abs() < 1e-12, "{got}");
        // Crossing at x = 1.5 (0.8 behind): φ = 0.8; at x = 1.0 (1.3 behind): none (CRAMP).
        let got = phi(Vector::new(1.5, 0.25), Vector::new(1.5, 1.0)).unwrap();
        assert!((got - 0.8).abs() < 1e-12, "{got}");
        assert_eq!(phi(Vector::new(1.0, 0.25), Vector::new(1.0, 1.0)), None);
        // A slanted line crossing at x = 2.2: φ = 0.1.
        let got = phi(Vector::new(2.1, 0.25), Vector::new(2.4, 1.0)).unwrap();
        assert!((got - (2.3 - (2.1 + 0.3 * 0.25 / 0.75))).abs() < 1e-12, "{got}");
        // A node on the crack is not the crossing rule's ...
        assert_eq!(phi(Vector::new(2.0, 0.25), Vector::new(2.0, 0.5)), None);
        // ... but `on_line`'s: each particle by its own place along the crack, for nodes on
        // the crack and on its continuation ahead of the tip; field 0 ahead of the tip.
        let mut zs = Vec::new();
        super::zones(&mut zs, std::slice::from_ref(&c), z, 2.0, &x, &lp);
        let zn = &zs[0];
        let tol = 1e-3;
        for xn in [Vector::new(2.0, 0.5), Vector::new(3.0, 0.5 + 1e-9), Vector::new(1.0, 0.5)] {
            let got = on_line(zn, &pts, Vector::new(2.1, 0.75), xn, z, tol).unwrap();
            assert!(got.0 == Side::Above && (got.1 - 0.2).abs() < 1e-12, "{got:?}");
            let got = on_line(zn, &pts, Vector::new(1.6, 0.25), xn, z, tol).unwrap();
            assert!(got.0 == Side::Below && (got.1 - 0.7).abs() < 1e-12, "{got:?}");
            assert_eq!(on_line(zn, &pts, Vector::new(2.4, 0.25), xn, z, tol), Some((Side::None, 1.0)));
            // Far behind: CRAMP's split (share 1).
            assert_eq!(on_line(zn, &pts, Vector::new(0.6, 0.75), xn, z, tol), Some((Side::Above, 1.0)));
        }
        // A node off the line: the crossing rule.
        assert_eq!(on_line(zn, &pts, Vector::new(2.1, 0.25), Vector::new(2.0, 1.0), z, tol), None);
        assert!(node_on_line(std::slice::from_ref(zn), std::slice::from_ref(&c), Vector::new(3.0, 0.5), tol));
        assert!(!node_on_line(std::slice::from_ref(zn), std::slice::from_ref(&c), Vector::new(3.0, 0.6), tol));
    }
}
