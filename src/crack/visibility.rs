//! Node visibility: the alternative to CRAMP's multiple velocity fields that Nairn 2003
//! §3.1 compares it with. "In node-visibility methods, a line is drawn from each particle
//! to each node. If that line crosses a crack, then that node no longer influences the
//! calculations for that particle" (Belytschko, Lu & Gu 1994, as used in EFG and MLPG).
//!
//! In MPM the particle's remaining (visible) shape functions are renormalized so that
//! they still sum to one, as an EFG/MLS approximation built on the visible nodes would:
//! S*_i = S_i / Σ_vis S_j and G*_i = (G_i − S*_i Σ_vis G_j) / Σ_vis S_j (the gradient of
//! S_i / Σ S_j). Mass and momentum are then conserved and every checked-mode invariant
//! still holds; the crack acts only by hiding nodes. Every node has a single velocity
//! field, so there is no crack contact (the scene must say `contact = "none"`) and the
//! crack surfaces move together with the crack (no opening displacement is tracked).
//!
//! The crossing test is CRAMP's (`geometry::crossing`): a node exactly on a crack is
//! hidden from the particles of both faces.

use super::geometry::{self, Side};
use crate::check::CheckError;
use crate::dim::Vector;
use crate::shape::MAX_NODES;
use crate::simulation::Simulation;

impl Simulation {
    /// Task 1 with cracks by node visibility: drop every pair whose line from particle to
    /// node crosses a crack, renormalize the particle's remaining shape functions and
    /// gradients, and put every pair in field 0.
    pub(crate) fn assign_visible_nodes(&mut self) -> Result<(), CheckError> {
        let grid = &self.grid;
        let p = &self.particles;
        let pairs = &mut self.pairs;
        for i in 0..p.len() {
            let base = i * MAX_NODES;
            let xp = p.x[i];
            let mut kept = 0;
            for k in base..base + pairs.count[i] as usize {
                let xn = grid.node_pos(pairs.node[k] as usize);
                let hidden = self.cracks.iter().any(|c| geometry::crossing(&c.points, &c.extent, xp, xn) != Side::None);
                if !hidden {
                    let to = base + kept;
                    pairs.node[to] = pairs.node[k];
                    pairs.s[to] = pairs.s[k];
                    pairs.g[to] = pairs.g[k];
                    kept += 1;
                }
            }
            let visible = base..base + kept;
            let sum_s = crate::exact::sum(&pairs.s[visible.clone()]);
            if sum_s.is_nan() || sum_s <= 0.0 {
                return Err(CheckError::NoVisibleNode { step: self.step_count, particle: i, id: p.id[i] });
            }
            if kept < pairs.count[i] as usize {
                let sum_g = Vector::new(
                    crate::exact::sum_iter(pairs.g[visible.clone()].iter().map(|g| g.x)),
                    crate::exact::sum_iter(pairs.g[visible.clone()].iter().map(|g| g.y)),
                );
                for k in visible.clone() {
                    let s = pairs.s[k] / sum_s;
                    pairs.g[k] = (pairs.g[k] - sum_g * s) / sum_s;
                    pairs.s[k] = s;
                }
                pairs.count[i] = kept as u8;
            }
            pairs.field[visible].fill(0);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    /// After a step with node visibility, every particle keeps only nodes that no crack
    /// hides, its shape functions still sum to one and its gradients to zero, and particles
    /// on the two faces of the crack share no node.
    #[test]
    fn visible_nodes_only_renormalized_and_faces_disconnected() {
        let text = r#"
            [grid]
            origin = [0.0, 0.0]
            size = [8.0, 8.0]
            cell = [1.0, 1.0]
            [solver]
            end_time = 1.0
            crack_method = "visibility"
            [[materials]]
            name = "m"
            E = 1.0
            nu = 0.3
            rho = 1.0
            state = "plane_strain"
            [[bodies]]
            material = "m"
            shape = { rectangle = { min = [1.0, 1.0], max = [7.0, 7.0] } }
            velocity_sine = { amplitude = [0.01, 0.02], k = [0.7, 0.4] }
            [[cracks]]
            points = [[0.5, 4.0], [4.5, 4.0]]
            contact = "none"
        "#;
        let mut sim = Scene::from_toml(text, "visibility").unwrap().build().unwrap();
        // The pairs after a step belong to the positions and crack at its start.
        let (x, crack) = (sim.particles.x.clone(), sim.cracks[0].clone());
        sim.step().unwrap();
        let (p, pairs) = (&sim.particles, &sim.pairs);
        let mut above_nodes = std::collections::HashSet::new();
        let mut below_nodes = std::collections::HashSet::new();
        let mut dropped = 0;
        for (i, &xi) in x.iter().enumerate() {
            let base = i * MAX_NODES;
            let k = base..base + pairs.count[i] as usize;
            dropped += crate::shape::weights(&sim.grid, sim.options.shape, &xi, &p.lp[i]).n - pairs.count[i] as usize;
            let s: f64 = pairs.s[k.clone()].iter().sum();
            let g = pairs.g[k.clone()].iter().fold(Vector::zeros(), |a, g| a + g);
            assert!((s - 1.0).abs() < 1e-14 && g.norm() < 1e-13, "particle {i}: ΣS = {s}, ΣG = {g:?}");
            for k in k {
                let xn = sim.grid.node_pos(pairs.node[k] as usize);
                assert_eq!(geometry::crossing(&crack.points, &crack.extent, xi, xn), Side::None);
                assert_eq!(pairs.field[k], 0);
                if xi.x < 4.0 {
                    if xi.y > 4.0 {
                        above_nodes.insert(pairs.node[k])
                    } else {
                        below_nodes.insert(pairs.node[k])
                    };
                }
            }
        }
        // The nodes on the crack line (y = 4, x = 1..4) are hidden from the particle rows on
        // both sides of it (y = 3.75 and 4.25, 7 particles each, 2 such nodes apiece).
        assert!(dropped >= 28, "only {dropped} hidden pairs");
        // Behind the crack (x < 4) the two faces see disjoint node sets (the nodes on the
        // crack line are hidden from both).
        assert!(above_nodes.is_disjoint(&below_nodes));
    }
}
