//! MPM versus FEA on a 3D scene with a crack: the stress normal to the crack plane along
//! the grid line through a front node, normal to the front — the 3D form of
//! [`super::compare`] (Nairn 2003 §3.1, Fig. 2), with the same two nodal recoveries:
//!
//! * **MPM**: the particle stresses of the damped run extrapolated to the node per velocity
//!   field, σ_{i,k} = Σ_p m_p σ_p S_ip δ_{k,ν(p,i)} / Σ_p m_p S_ip δ_{k,ν(p,i)} (Guo & Nairn
//!   2004 eq. 11, exact sums), the field of the particles on the + side of the crack plane
//!   (the upper face behind the front; the single field ahead of it).
//! * **FEA**: the hex8 stress field sampled at the initial positions of the same particles
//!   and averaged with the same weights m_p S_ip (eq. 11 applied to the FEA field), so both
//!   sides go through the same recovery; the FEA's own nodal-averaged stress (of the node
//!   copy on the + side) is reported beside it.
//!
//! The front node (the first node the MPM leaves whole, where the FEA's crack ends) is the
//! singular point: listed, excluded from the maximum difference.

use super::hex8;
use super::scene3::SceneFea3;
use super::solve3::Solution3;
use crate::dim::{Sym3, Vector3, D3};
use crate::exact::ExactSum;
use crate::simulation::Simulation;
use anyhow::{bail, Context};
use serde::Serialize;
use std::fmt::Write as _;

/// One grid node of the line.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LineRow3 {
    /// Signed distance from the front node along e1 (negative: behind the front, on the crack face).
    pub s: f64,
    pub position: [f64; 3],
    pub mpm: f64,
    pub fea_eq11: f64,
    pub fea_nodal: f64,
    pub is_front: bool,
    pub on_crack_face: bool,
}

/// The line and its summary numbers (relative differences are over the peak |σ| of the
/// FEA eq. 11 curve, front node included).
#[derive(Clone, Debug, Serialize)]
pub struct LineComparison3 {
    pub rows: Vec<LineRow3>,
    pub front_position: [f64; 3],
    pub peak: f64,
    pub max_diff: f64,
    pub max_diff_at: [f64; 3],
    pub front_diff: f64,
}

/// The stress at point `x` inside the material from the displacements of the element
/// holding it (strain B(ξ) u_e, stress D ε).
pub fn fea_stress_at_3d(fea: &SceneFea3, sol: &Solution3, x: Vector3) -> Option<Sym3> {
    let gm = &fea.grid_mesh;
    let g = &gm.grid;
    let c: [isize; 3] = std::array::from_fn(|d| ((x[d] - g.origin[d]) / g.h[d]).floor() as isize);
    let e = gm.element_at(c)?;
    let xi: [f64; 3] = std::array::from_fn(|d| 2.0 * (x[d] - (g.origin[d] + (c[d] as f64 + 0.5) * g.h[d])) / g.h[d]);
    let p = hex8::point_data(&gm.mesh.element_coords(e), xi).ok()?;
    let u = gm.mesh.elements[e].map(|a| sol.displacement[a]);
    Some(hex8::stress(&fea.materials[fea.element_body[e]], &hex8::strain(&p.grad_n, &u)))
}

/// Compare σ_nn (n the crack-plane normal) along the grid line through front node `front`
/// of meshed crack `crack`, normal to the front (see the module doc).
pub fn compare_ahead_of_front(sim: &Simulation<D3>, fea: &SceneFea3, sol: &Solution3, crack: usize, front: usize) -> anyhow::Result<LineComparison3> {
    let mc = fea.cracks.get(crack).with_context(|| format!("the FEA has no crack {crack}"))?;
    let f = mc.front.get(front).with_context(|| format!("crack {crack} has no front node {front}"))?;
    let e1 = f.direction.with_context(|| "the front turns at that node (no grid direction normal to it)")?;
    let gm = &fea.grid_mesh;
    let g = &gm.grid;
    if sim.grid.n != g.n || sim.grid.origin != g.origin || sim.grid.h != g.h {
        bail!("the MPM run and the FEA are not on the same grid");
    }
    let n = mc.axis;
    let a1 = (0..3).find(|&k| e1[k] != 0.0).unwrap_or(0);
    let comp = |s: &Sym3| [s.xx, s.yy, s.zz][n];
    let (p, pairs) = (&sim.particles, &sim.pairs);
    let stride = <D3 as crate::dim::Space>::MAX_NODES;
    let mut rows = Vec::new();
    for i in 0..=g.n[a1] {
        let mut ijk = f.grid_node;
        ijk[a1] = i;
        let gi = g.node_index(ijk[0], ijk[1], ijk[2]);
        let copies = gm.nodes_at(gi);
        if copies.is_empty() {
            continue;
        }
        let xn = gm.mesh.nodes[copies[0]];
        let upper = gm.copies.get(&gi).and_then(|c| c.first().copied()).unwrap_or(copies[0]);
        let items = pairs.of_node(gi);
        let Some(field) = items.iter().find(|&&it| p.x[it as usize / stride][n] > xn[n]).map(|&it| pairs.field[it as usize]) else {
            continue;
        };
        let (mut m, mut sm, mut sf) = (ExactSum::default(), ExactSum::default(), ExactSum::default());
        for &it in items.iter().filter(|&&it| pairs.field[it as usize] == field) {
            let pp = it as usize / stride;
            let w = p.mass[pp] * pairs.s[it as usize];
            m.add(w);
            sm.add(w * comp(&p.stress[pp]));
            sf.add(w * fea_stress_at_3d(fea, sol, p.x0[pp]).map_or(f64::NAN, |s| comp(&s)));
        }
        rows.push(LineRow3 {
            s: (xn - f.position).dot(&e1),
            position: xn.into(),
            mpm: sm.value() / m.value(),
            fea_eq11: sf.value() / m.value(),
            fea_nodal: comp(&sol.nodal_stress[upper]),
            is_front: gi == g.node_index(f.grid_node[0], f.grid_node[1], f.grid_node[2]),
            on_crack_face: copies.len() > 1,
        });
    }
    if rows.is_empty() {
        bail!("no node of the line holds material in both analyses");
    }
    let peak = rows.iter().map(|r| r.fea_eq11.abs()).fold(0.0, f64::max);
    let (mut max_diff, mut max_diff_at, mut front_diff) = (0.0, [f64::NAN; 3], 0.0);
    for r in &rows {
        let d = (r.mpm - r.fea_eq11).abs();
        if r.is_front {
            front_diff = d;
        } else if d > max_diff || max_diff_at[0].is_nan() {
            max_diff = d;
            max_diff_at = r.position;
        }
    }
    Ok(LineComparison3 { rows, front_position: f.position.into(), peak, max_diff, max_diff_at, front_diff })
}

impl LineComparison3 {
    /// `s,x,y,z,mpm,fea_eq11,fea_nodal,is_front,on_crack_face`.
    pub fn csv(&self) -> String {
        let mut t = String::from("s,x,y,z,mpm,fea_eq11,fea_nodal,is_front,on_crack_face\n");
        for r in &self.rows {
            let [x, y, z] = r.position;
            let _ = writeln!(t, "{:e},{x:e},{y:e},{z:e},{:e},{:e},{:e},{},{}", r.s, r.mpm, r.fea_eq11, r.fea_nodal, r.is_front, r.on_crack_face);
        }
        t
    }
}
