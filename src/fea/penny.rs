//! J along a circular crack front that lies on a symmetry plane of the model: the penny
//! crack of an eighth (or quarter) model whose crack plane carries rollers on the ligament
//! only (`annulus` selection) and is free on the crack disc.
//!
//! **What front the FEA has.** The crack plane z = z0 is a grid plane. Its mesh nodes are
//! either held in z (ligament) or free (crack face). Across a face of a layer-0 element the
//! opening u_z is the bilinear interpolation of its four nodes, so it is non-zero on every
//! face with at least one free node and vanishes identically only on faces whose four
//! nodes are held. The FEA's crack is therefore the **opening region**, the union of the
//! faces touching a free node; its boundary (the discrete front) is a staircase of grid
//! edges through held nodes. This is the 2D rule (the crack meshed up to the first whole
//! node) on every grid line of the plane. A circle crosses the grid at every angle, so the
//! staircase steps by one cell at irregular intervals; it is no circle at the cell scale.
//!
//! **J with a radial virtual extension.** With [`super::crack3::domain_integral`] and the
//! nodal extension q_a = φ_a ψ(θ_a) e_r(a) (e_r the radial unit vector from the axis,
//! θ the polar angle in the plane), J̄ is the derivative of the discrete energy for moving
//! the staircase by q: J̄ = ∫ G q·ν ds along the discrete front, ν its outward normal in the
//! plane. Here
//!
//! * φ = 1 at the nodes within `cells` cells of the plane and whose distance from the axis
//!   differs from a by at most `cells` + ½ cells (so every staircase node, within √2 cells
//!   of r = a, is inside), 0 elsewhere: the usual one-cell ramp at the edge of the domain;
//! * ψ(θ) = max(0, 1 − |θ − θ_k|/Δ), a hat of half-width Δ about the station θ_k, cut
//!   where it leaves [0, π/2] (the x = 0 and y = 0 symmetry planes: q is
//!   tangent to them, and the mirrored half of the hat lies in the next quarter);
//! * q_z = 0: tangent to the crack plane, as the symmetry of the ligament requires
//!   (σ_xz = σ_yz = 0 and ∂u_z/∂x = ∂u_z/∂y = 0 there, so the ligament adds no boundary term).
//!
//! The model holds one half of the crack's thickness (z ≥ z0), so the whole-body energy
//! release for the mirrored extension is **twice** J̄ (symmetry factor 2 for the crack-plane
//! mirror; the x and y mirrors only extend the front into the other quarters, which the cut
//! hat accounts for in both J̄ and the length below). The area swept by the discrete front
//! per unit of the extension is D = ∫ ψ e_r·ν ds over the staircase edges (exactly, with q
//! linear along each edge: Σ L (q_A + q_B)/2 · ν). Hence
//!
//! G(θ_k) = 2 J̄ / D,   a_eff(θ_k) = D / ∫ψ dθ
//!
//! — a_eff is the ψ-weighted mean radius of the staircase (for a circle of radius a,
//! D = a ∫ψ dθ); it is the crack radius for the reference at that station, the radius the
//! discrete front actually has there, not a fitted value. With ψ ≡ 1 (Δ = ∞),
//! G is the front average and a_eff = 2D/π. Stations every Δ with hats of half-width Δ
//! form a partition of unity, so their J̄ add up to the average's.

use super::crack3::domain_integral;
use super::scene3::{FeaAnalysis3, SceneFea3};
use super::{FeaError, Result};
use crate::dim::Vector3;
use std::f64::consts::FRAC_PI_2;

/// J at one station of the front.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct FrontStation {
    /// Station angle θ_k (radians, 0 = the +x axis) and the hat half-width Δ (radians;
    /// infinite for the whole-front average).
    pub theta: f64,
    pub half_width: f64,
    /// Domain half-size in cells.
    pub cells: usize,
    /// 2 J̄ / D: the energy release rate of the whole body per unit crack area.
    pub g: f64,
    /// ψ-weighted mean radius of the discrete front, D / ∫ψ dθ.
    pub a_eff: f64,
    pub jbar: f64,
    pub swept: f64,
}

/// The discrete front of a crack on the symmetry plane z = `center.z` (a grid plane).
#[derive(Clone, Debug)]
pub struct DiscreteFront {
    /// Layer index of the crack plane.
    pub k0: usize,
    /// Staircase edges (mesh nodes A, B) with the unit outward normal (in the plane).
    pub edges: Vec<(usize, usize, Vector3)>,
    /// Area of the opening region (faces touching a free node).
    pub opening_area: f64,
    /// Area of the meshed cross-section at the crack plane (every layer-0 element face).
    pub section_area: f64,
}

/// The opening region and its staircase boundary (see the module doc).
pub fn discrete_front(fea: &SceneFea3, center: Vector3) -> Result<DiscreteFront> {
    let gm = &fea.grid_mesh;
    let g = &gm.grid;
    let s = (center.z - g.origin.z) / g.h.z;
    if (s - s.round()).abs() > 1e-9 || s.round() < 0.0 {
        return Err(FeaError::InvalidInput(format!("the crack plane z = {} is not a grid plane", center.z)));
    }
    let k0 = s.round() as usize;
    let prescribed = fea.bcs.prescribed();
    // Free crack-plane nodes: mesh nodes of the plane with u_z not prescribed.
    let free = |i: usize, j: usize| -> bool {
        let a = gm.grid_node[g.node_index(i, j, k0)];
        a != usize::MAX && prescribed[3 * a + 2].is_none()
    };
    let face = |i: isize, j: isize| -> Option<usize> { gm.element_at([i, j, k0 as isize]) };
    let opening = |i: isize, j: isize| -> bool {
        face(i, j).is_some() && [(0, 0), (1, 0), (0, 1), (1, 1)].iter().any(|&(di, dj)| free((i + di) as usize, (j + dj) as usize))
    };
    let (mut edges, mut n_open, mut n_section) = (Vec::new(), 0usize, 0usize);
    for j in 0..g.n[1] as isize {
        for i in 0..g.n[0] as isize {
            if face(i, j).is_none() {
                continue;
            }
            n_section += 1;
            if !opening(i, j) {
                continue;
            }
            n_open += 1;
            // The four edges of face (i, j): corner offsets and outward normal.
            for (a, b, di, dj) in [((1, 0), (1, 1), 1, 0), ((0, 1), (1, 1), 0, 1), ((0, 0), (0, 1), -1, 0), ((0, 0), (1, 0), 0, -1)] {
                // Against a held face: a front edge. Against no element (a symmetry plane
                // or the body's surface): not front (the MPM's rule for crack edges).
                if opening(i + di, j + dj) || face(i + di, j + dj).is_none() {
                    continue;
                }
                let node = |(oi, oj): (isize, isize)| gm.grid_node[g.node_index((i + oi) as usize, (j + oj) as usize, k0)];
                edges.push((node(a), node(b), Vector3::new(di as f64, dj as f64, 0.0)));
            }
        }
    }
    if n_open == 0 {
        return Err(FeaError::InvalidInput(format!("no free node on the crack plane z = {}: no crack", center.z)));
    }
    let cell_area = g.h.x * g.h.y;
    Ok(DiscreteFront { k0, edges, opening_area: n_open as f64 * cell_area, section_area: n_section as f64 * cell_area })
}

/// G along the front at the stations `thetas` (radians) with hats of half-width
/// `half_width` (radians; `f64::INFINITY`: the whole-front average), domains of `cells` cells
/// (see the module doc). `a` is the nominal crack radius (it only places the domain).
pub fn front_g(
    fea: &SceneFea3,
    analysis: &FeaAnalysis3,
    front: &DiscreteFront,
    center: Vector3,
    a: f64,
    thetas: &[f64],
    half_width: f64,
    cells: usize,
) -> Result<Vec<FrontStation>> {
    let gm = &fea.grid_mesh;
    let g = &gm.grid;
    let h = g.h.x;
    let nodes = &gm.mesh.nodes;
    let polar = |a: usize| -> (f64, f64, Vector3) {
        let d = nodes[a] - center;
        let rho = d.x.hypot(d.y);
        (rho, d.y.atan2(d.x), if rho > 0.0 { Vector3::new(d.x / rho, d.y / rho, 0.0) } else { Vector3::zeros() })
    };
    let reach = (cells as f64 + 0.5) * h;
    let phi = |node: usize| -> f64 {
        let (rho, _, _) = polar(node);
        let dz = nodes[node].z - center.z;
        if (rho - a).abs() <= reach && dz >= -1e-9 * h && dz <= cells as f64 * h * (1.0 + 1e-9) {
            1.0
        } else {
            0.0
        }
    };
    // Every staircase node must be inside φ = 1 (else the domain is too small for this front).
    for &(p, q, _) in &front.edges {
        for n in [p, q] {
            if phi(n) != 1.0 {
                return Err(FeaError::InvalidInput(format!(
                    "front node at ({}, {}, {}) lies outside the J domain of {cells} cell(s) around r = {a}",
                    nodes[n].x, nodes[n].y, nodes[n].z
                )));
            }
        }
    }
    // The domain must lie inside the body: every cell next to a node of φ = 1 holds
    // material, except beyond the symmetry planes through the centre (x, y or z below it).
    for (node, ijk) in gm.node_grid.iter().enumerate() {
        if phi(node) == 0.0 {
            continue;
        }
        for c in (0..8).map(|k| [0, 1, 2].map(|d| ijk[d] as isize - 1 + ((k >> d) & 1) as isize)) {
            let mid = Vector3::from_fn(|d, _| g.origin[d] + (c[d] as f64 + 0.5) * g.h[d]);
            if (0..3).all(|d| mid[d] > center[d]) && gm.element_at(c).is_none() {
                return Err(FeaError::InvalidInput(format!(
                    "the J domain of {cells} cell(s) leaves the body at cell {c:?}; use a smaller domain"
                )));
            }
        }
    }
    let mut out = Vec::new();
    for &theta in thetas {
        let psi = |t: f64| if half_width.is_infinite() { 1.0 } else { (1.0 - (t - theta).abs() / half_width).max(0.0) };
        let q = |node: usize| -> Vector3 {
            let f = phi(node);
            if f == 0.0 {
                return Vector3::zeros();
            }
            let (_, t, er) = polar(node);
            er * (f * psi(t))
        };
        let elements: Vec<usize> = (0..gm.mesh.elements.len())
            .filter(|&e| gm.mesh.elements[e].iter().any(|&n| q(n) != Vector3::zeros()))
            .collect();
        let jbar = domain_integral(gm, &analysis.solution, &elements, q)?;
        let swept: f64 = front.edges.iter().map(|&(p, r, nu)| (nodes[r] - nodes[p]).norm() * 0.5 * (q(p) + q(r)).dot(&nu)).sum();
        // ∫ψ dθ over [0, π/2].
        let psi_int = if half_width.is_infinite() {
            FRAC_PI_2
        } else {
            let m = 2000;
            let (lo, hi) = ((theta - half_width).max(0.0), (theta + half_width).min(FRAC_PI_2));
            let dt = (hi - lo) / m as f64;
            (0..m).map(|k| psi(lo + (k as f64 + 0.5) * dt) * dt).sum::<f64>()
        };
        out.push(FrontStation { theta, half_width, cells, g: 2.0 * jbar / swept, a_eff: swept / psi_int, jbar, swept });
    }
    Ok(out)
}
