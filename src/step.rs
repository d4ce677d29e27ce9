//! One MPM step, written as the appendix of Nairn 2003 lists it: one function per task.
//!
//! Every particle-to-node sum is a gather over the node's particle/node pairs (CSR built
//! in Task 1) accumulated with [`ExactSum`], and every node-to-particle sum is exact too,
//! so a step's result does not depend on particle order, thread count, or — for a scene
//! symmetric about a grid line — on which side of the mirror a particle is.

use crate::check::{CheckError, MASS_TOL, MOMENTUM_TOL, PARTITION_TOL};
use crate::dim::{Sym, Tensor, Vector};
use crate::exact::ExactSum;
use crate::material::Constitutive;
use crate::shape::{self, ShapeKind, MAX_NODES};
use crate::simulation::{Scheme, Simulation};

impl Simulation {
    /// Advance one time step (Tasks 0–8).
    pub fn step(&mut self) -> Result<(), CheckError> {
        let dt = self.options.dt;
        let scheme = self.options.scheme;
        // Steps are numbered from 1; every check inside this step reports this number.
        self.step_count += 1;
        self.apply_loads(self.time);
        if self.options.checked && self.momentum_conserving {
            self.momentum_ref = self.total_momentum();
        }

        self.task0_shape_functions()?;
        self.task1_extrapolate()?;
        self.task2_boundary_conditions();
        match scheme {
            Scheme::Usf => self.update_stresses(dt),
            Scheme::Usavg => self.update_stresses(0.5 * dt),
            Scheme::Usl | Scheme::Musl => {}
        }
        self.task3_forces();
        self.task4_update_momenta()?;
        self.task5_update_particles();
        match scheme {
            // Task 6a: stresses from the momenta of Task 4.
            Scheme::Usl => self.update_stresses(dt),
            // Task 6b: already updated in Task 2.
            Scheme::Usf => {}
            // Task 6c: re-extrapolate the new particle momenta, then update.
            Scheme::Musl => {
                self.task6c_reextrapolate();
                self.update_stresses(dt);
            }
            Scheme::Usavg => {
                self.task6c_reextrapolate();
                self.update_stresses(0.5 * dt);
            }
        }
        self.task7_move_cracks();
        // Task 8: all information is back on the particles.
        self.time += dt;
        if self.options.checked {
            self.check_after_step()?;
            if self.has_cracks() {
                self.check_crack_sides()?;
            }
        }
        Ok(())
    }

    /// Task 0: shape functions and gradients at the particle positions (eq. 24), stored
    /// per particle/node pair. A particle outside the grid always stops the run.
    fn task0_shape_functions(&mut self) -> Result<(), CheckError> {
        let grid = &self.grid;
        let kind = self.options.shape;
        let checked = self.options.checked;
        let step = self.step_count;
        let p = &self.particles;
        let pairs = &mut self.pairs;
        let lo = grid.origin;
        let hi = grid.max_corner();
        for i in 0..p.len() {
            let x = p.x[i];
            let margin = match kind {
                ShapeKind::Linear => Vector::zeros(),
                ShapeKind::Ugimp => p.lp[i],
            };
            let inside = x.x - margin.x >= lo.x
                && x.x + margin.x <= hi.x
                && x.y - margin.y >= lo.y
                && x.y + margin.y <= hi.y;
            if !inside {
                return Err(CheckError::OutsideGrid {
                    step,
                    particle: i,
                    id: p.id[i],
                    x: x.x,
                    y: x.y,
                    xmin: lo.x,
                    xmax: hi.x,
                    ymin: lo.y,
                    ymax: hi.y,
                });
            }
            let w = shape::weights(grid, kind, &x, &p.lp[i]);
            let base = i * MAX_NODES;
            pairs.count[i] = w.n as u8;
            pairs.node[base..base + w.n].copy_from_slice(&w.node[..w.n]);
            pairs.s[base..base + w.n].copy_from_slice(&w.s[..w.n]);
            pairs.g[base..base + w.n].copy_from_slice(&w.g[..w.n]);
            if checked {
                let sum_s = crate::exact::sum(&w.s[..w.n]);
                let gx = crate::exact::sum_iter(w.g[..w.n].iter().map(|g| g.x));
                let gy = crate::exact::sum_iter(w.g[..w.n].iter().map(|g| g.y));
                let gtol = PARTITION_TOL / grid.min_h();
                if (sum_s - 1.0).abs() > PARTITION_TOL || gx.abs() > gtol || gy.abs() > gtol {
                    return Err(CheckError::PartitionOfUnity { step, particle: i, id: p.id[i], sum_s, gx, gy });
                }
            }
        }
        Ok(())
    }

    /// Task 1: velocity field of every particle/node pair (line crossing, cracks only),
    /// then nodal masses and momenta per field (eq. 26) and, with cracks, nodal volumes (eq. 27).
    fn task1_extrapolate(&mut self) -> Result<(), CheckError> {
        if self.has_cracks() {
            self.task1_cracks()?;
        }
        self.build_node_incidence();

        let with_cracks = self.has_cracks();
        let nf = self.nodes.fields.len();
        let p = &self.particles;
        let pairs = &self.pairs;
        let thickness = &self.thickness;
        let nodes = &mut self.nodes;
        let mut acc = [[ExactSum::new(), ExactSum::new(), ExactSum::new()], [ExactSum::new(), ExactSum::new(), ExactSum::new()], [ExactSum::new(), ExactSum::new(), ExactSum::new()]];
        let mut vol = ExactSum::new();
        for &node in &nodes.active {
            let i = node as usize;
            for a in acc.iter_mut().take(nf) {
                a.iter_mut().for_each(ExactSum::clear);
            }
            vol.clear();
            let mut present = 0u8;
            for &item in &pairs.items[pairs.start[i] as usize..pairs.start[i + 1] as usize] {
                let item = item as usize;
                let pp = item / MAX_NODES;
                let f = pairs.field[item] as usize;
                let s = pairs.s[item];
                let m = p.mass[pp];
                present |= 1 << f;
                acc[f][0].add(m * s);
                acc[f][1].add(m * p.v[pp].x * s);
                acc[f][2].add(m * p.v[pp].y * s);
                if with_cracks {
                    // Nodal area (eq. 27 per unit thickness), compared with the cell area.
                    vol.add(p.volume(pp) / thickness[p.body[pp] as usize] * s);
                }
            }
            nodes.present[i] = present;
            for (f, a) in acc.iter().enumerate().take(nf) {
                let fa = &mut nodes.fields[f];
                fa.mass[i] = a[0].value();
                fa.mom[i] = Vector::new(a[1].value(), a[2].value());
            }
            if with_cracks {
                nodes.volume[i] = vol.value();
            }
        }
        if with_cracks {
            self.finish_crack_nodes()?;
        }
        if self.options.checked {
            self.check_nodal_masses()?;
        }
        Ok(())
    }

    /// Build the node → pair incidence (CSR) by a counting sort over the pairs, and the
    /// list of active nodes. Only nodes that some particle touches are visited afterwards.
    fn build_node_incidence(&mut self) {
        let np = self.particles.len();
        let nn = self.grid.num_nodes();
        let pairs = &mut self.pairs;
        // Last step's present bits are stale only on last step's active nodes.
        for &i in &self.nodes.active {
            self.nodes.present[i as usize] = 0;
        }
        // Count pairs per node (start[i+1]), list the active nodes, prefix-sum into offsets.
        pairs.start.fill(0);
        for i in 0..np {
            let base = i * MAX_NODES;
            for k in 0..pairs.count[i] as usize {
                pairs.start[pairs.node[base + k] as usize + 1] += 1;
            }
        }
        self.nodes.active.clear();
        for i in 0..nn {
            if pairs.start[i + 1] > 0 {
                self.nodes.active.push(i as u32);
            }
            pairs.start[i + 1] += pairs.start[i];
        }
        pairs.items.resize(pairs.start[nn] as usize, 0);
        pairs.fill.clear();
        pairs.fill.extend_from_slice(&pairs.start[..nn]);
        for i in 0..np {
            let base = i * MAX_NODES;
            for k in 0..pairs.count[i] as usize {
                let node = pairs.node[base + k] as usize;
                pairs.items[pairs.fill[node] as usize] = (base + k) as u32;
                pairs.fill[node] += 1;
            }
        }
    }

    /// Task 2: boundary conditions on the nodal momenta of Task 1 (and, with cracks, contact).
    fn task2_boundary_conditions(&mut self) {
        self.apply_momentum_bcs();
        if self.has_cracks() {
            self.apply_contact_to_momenta();
        }
    }

    /// Fixed velocity components: p_c = m v_c for every field of a constrained node.
    pub(crate) fn apply_momentum_bcs(&mut self) {
        for &node in &self.bcs.nodes {
            let i = node as usize;
            let mask = self.bcs.mask[i];
            let v = self.bcs.vel[i];
            for (f, fa) in self.nodes.fields.iter_mut().enumerate() {
                if self.nodes.present[i] & (1 << f) == 0 {
                    continue;
                }
                for c in 0..2 {
                    if mask & (1 << c) != 0 {
                        fa.mom[i][c] = fa.mass[i] * v[c];
                    }
                }
            }
        }
    }

    /// Nodal velocities v = p/m for every present field of every active node (eq. 34).
    fn compute_nodal_velocities(&mut self) {
        let nodes = &mut self.nodes;
        for &node in &nodes.active {
            let i = node as usize;
            for (f, fa) in nodes.fields.iter_mut().enumerate() {
                if nodes.present[i] & (1 << f) != 0 {
                    fa.vel[i] = fa.mom[i] / fa.mass[i];
                }
            }
        }
    }

    /// Stress and strain update (appendix, "Updating Stresses and Strains"): nodal
    /// velocities from the latest momenta (eq. 34), the velocity gradient at each particle
    /// (eq. 36, summed exactly), the strain increment (eq. 35), and the constitutive law.
    pub(crate) fn update_stresses(&mut self, dt_star: f64) {
        self.compute_nodal_velocities();
        let nodes = &self.nodes;
        let pairs = &self.pairs;
        let p = &mut self.particles;
        let mut l = [ExactSum::new(), ExactSum::new(), ExactSum::new(), ExactSum::new()];
        for i in 0..p.len() {
            l.iter_mut().for_each(ExactSum::clear);
            let base = i * MAX_NODES;
            for k in base..base + pairs.count[i] as usize {
                let v = nodes.fields[pairs.field[k] as usize].vel[pairs.node[k] as usize];
                let g = pairs.g[k];
                l[0].add(v.x * g.x);
                l[1].add(v.x * g.y);
                l[2].add(v.y * g.x);
                l[3].add(v.y * g.y);
            }
            let grad_v = Tensor::new(l[0].value(), l[1].value(), l[2].value(), l[3].value());
            let dl = grad_v * dt_star;
            let de = Sym::sym_part(&dl);
            let mat = &self.materials[p.material[i] as usize];
            mat.update(&de, &mut p.strain[i], &mut p.stress[i]);
            p.grad_u[i] += dl;
        }
    }

    /// Task 3: internal and external nodal forces per field (eq. 28), total force with
    /// damping −κp, zeroed in fixed directions. Also accumulates the damping energy.
    fn task3_forces(&mut self) {
        let kappa = self.options.damping;
        let nf = self.nodes.fields.len();
        let p = &self.particles;
        let pairs = &self.pairs;
        let nodes = &mut self.nodes;
        let body_force = &self.body_force;
        let has_ext = !self.loads.is_empty() || body_force.iter().any(|b| *b != Vector::zeros());
        let mut acc: [[ExactSum; 4]; 3] = Default::default();
        let mut damp_power = ExactSum::new();
        for &node in &nodes.active {
            let i = node as usize;
            for a in acc.iter_mut().take(nf) {
                a.iter_mut().for_each(ExactSum::clear);
            }
            for &item in &pairs.items[pairs.start[i] as usize..pairs.start[i + 1] as usize] {
                let item = item as usize;
                let pp = item / MAX_NODES;
                let f = pairs.field[item] as usize;
                // f_int = −V σ·G (the paper's −m σ̄·G with specific stress σ̄ = σ/ρ).
                let t = p.stress[pp].dot_vec(&pairs.g[item]);
                let v0 = p.vol0[pp];
                acc[f][0].add(-(v0 * t.x));
                acc[f][1].add(-(v0 * t.y));
                if has_ext {
                    let s = pairs.s[item];
                    let fp = p.force[pp] + body_force[p.body[pp] as usize] * p.mass[pp];
                    acc[f][2].add(fp.x * s);
                    acc[f][3].add(fp.y * s);
                }
            }
            for (f, a) in acc.iter().enumerate().take(nf) {
                if nodes.present[i] & (1 << f) == 0 {
                    continue;
                }
                let fa = &mut nodes.fields[f];
                fa.fint[i] = Vector::new(a[0].value(), a[1].value());
                fa.fext[i] = Vector::new(a[2].value(), a[3].value());
                let mom = fa.mom[i];
                fa.ftot[i] = (fa.fint[i] + fa.fext[i]) - mom * kappa;
                if kappa != 0.0 {
                    damp_power.add(kappa * mom.norm_squared() / fa.mass[i]);
                }
            }
        }
        // Fixed directions do not accelerate.
        for &node in &self.bcs.nodes {
            let i = node as usize;
            let mask = self.bcs.mask[i];
            for fa in nodes.fields.iter_mut() {
                for c in 0..2 {
                    if mask & (1 << c) != 0 {
                        fa.ftot[i][c] = 0.0;
                    }
                }
            }
        }
        self.work.damping += self.options.dt * damp_power.value();
    }

    /// Task 4: p' = p + Δt f_tot (eq. 29); then contact, with forces back-computed.
    fn task4_update_momenta(&mut self) -> Result<(), CheckError> {
        let dt = self.options.dt;
        let check_momentum = self.options.checked && self.momentum_conserving;
        let before = if check_momentum { self.nodal_momentum_total() } else { Vector::zeros() };
        let nodes = &mut self.nodes;
        for &node in &nodes.active {
            let i = node as usize;
            for (f, fa) in nodes.fields.iter_mut().enumerate() {
                if nodes.present[i] & (1 << f) != 0 {
                    fa.mom[i] += fa.ftot[i] * dt;
                }
            }
        }
        if self.has_cracks() {
            self.apply_contact_to_updated_momenta();
        }
        if check_momentum {
            let after = self.nodal_momentum_total();
            let scale = self.force_scale() * dt + self.nodal_momentum_scale();
            let tol = MOMENTUM_TOL * scale.max(f64::MIN_POSITIVE);
            // Non-finite momenta are named by the finiteness checks, which point at the culprit.
            let (a, b) = (after.x + after.y, before.x + before.y);
            if a.is_finite() && b.is_finite() && (after - before).norm() > tol {
                return Err(CheckError::Momentum {
                    step: self.step_count,
                    stage: "task 4 (nodal momentum update)",
                    bx: before.x,
                    by: before.y,
                    ax: after.x,
                    ay: after.y,
                    tol,
                });
            }
        }
        Ok(())
    }

    /// Task 5: particle positions and velocities from the updated nodal momenta and the
    /// total forces (eq. 30), each pair using its own velocity field. Also the work of the
    /// external loads, Σ_p (f_p + m_p b)·Δx_p: the particles move with the grid velocity,
    /// so this is the work the grid forces f_ext do. (The particle velocity v_p is not
    /// the velocity to use: FLIP updates leave components in it the grid cannot see, and
    /// under a load applied to a few rows of particles those correlate with the load.)
    fn task5_update_particles(&mut self) {
        let dt = self.options.dt;
        {
            let nodes = &mut self.nodes;
            for &node in &nodes.active {
                let i = node as usize;
                for (f, fa) in nodes.fields.iter_mut().enumerate() {
                    if nodes.present[i] & (1 << f) != 0 {
                        fa.vel[i] = fa.mom[i] / fa.mass[i];
                        fa.acc[i] = fa.ftot[i] / fa.mass[i];
                    }
                }
            }
        }
        let nodes = &self.nodes;
        let pairs = &self.pairs;
        let p = &mut self.particles;
        let body_force = &self.body_force;
        let has_ext = !self.loads.is_empty() || body_force.iter().any(|b| *b != Vector::zeros());
        let mut work = ExactSum::new();
        let mut s: [ExactSum; 4] = Default::default();
        for i in 0..p.len() {
            s.iter_mut().for_each(ExactSum::clear);
            let base = i * MAX_NODES;
            for k in base..base + pairs.count[i] as usize {
                let fa = &nodes.fields[pairs.field[k] as usize];
                let n = pairs.node[k] as usize;
                let w = pairs.s[k];
                s[0].add(w * fa.vel[n].x);
                s[1].add(w * fa.vel[n].y);
                s[2].add(w * fa.acc[n].x);
                s[3].add(w * fa.acc[n].y);
            }
            let dx = Vector::new(s[0].value(), s[1].value()) * dt;
            if has_ext {
                let f = p.force[i] + body_force[p.body[i] as usize] * p.mass[i];
                work.add(f.dot(&dx));
            }
            p.x[i] += dx;
            p.v[i] += Vector::new(s[2].value(), s[3].value()) * dt;
        }
        self.work.external_work += work.value();
    }

    /// Task 6c: extrapolate the new particle momenta to the grid with the shape functions
    /// and fields of Task 1 (eq. 31), then boundary conditions and contact.
    fn task6c_reextrapolate(&mut self) {
        let nf = self.nodes.fields.len();
        let p = &self.particles;
        let pairs = &self.pairs;
        let nodes = &mut self.nodes;
        let mut acc: [[ExactSum; 2]; 3] = Default::default();
        for &node in &nodes.active {
            let i = node as usize;
            for a in acc.iter_mut().take(nf) {
                a.iter_mut().for_each(ExactSum::clear);
            }
            for &item in &pairs.items[pairs.start[i] as usize..pairs.start[i + 1] as usize] {
                let item = item as usize;
                let pp = item / MAX_NODES;
                let f = pairs.field[item] as usize;
                let s = pairs.s[item];
                let m = p.mass[pp];
                acc[f][0].add(m * p.v[pp].x * s);
                acc[f][1].add(m * p.v[pp].y * s);
            }
            for (f, a) in acc.iter().enumerate().take(nf) {
                if nodes.present[i] & (1 << f) != 0 {
                    nodes.fields[f].mom[i] = Vector::new(a[0].value(), a[1].value());
                }
            }
        }
        self.apply_momentum_bcs();
        if self.has_cracks() {
            self.apply_contact_to_momenta();
        }
    }

    /// Exact total of the nodal momenta over all fields.
    fn nodal_momentum_total(&self) -> Vector {
        let mut sx = ExactSum::new();
        let mut sy = ExactSum::new();
        for (f, i) in self.nodes.present_fields() {
            let p = self.nodes.fields[f].mom[i];
            sx.add(p.x);
            sy.add(p.y);
        }
        Vector::new(sx.value(), sy.value())
    }

    /// Σ |p| over nodes: the scale against which a change of total momentum is judged.
    fn nodal_momentum_scale(&self) -> f64 {
        let n = &self.nodes;
        crate::exact::sum_iter(n.present_fields().map(|(f, i)| n.fields[f].mom[i].abs().sum()))
    }

    /// Σ |f_int| over nodes: the scale against which Σ f_int = 0 is judged.
    fn force_scale(&self) -> f64 {
        let n = &self.nodes;
        crate::exact::sum_iter(n.present_fields().map(|(f, i)| n.fields[f].fint[i].abs().sum()))
    }

    /// Checked mode after Task 1: positive masses where used; grid mass equals particle mass.
    fn check_nodal_masses(&self) -> Result<(), CheckError> {
        let step = self.step_count;
        let mut grid_mass = ExactSum::new();
        for (f, i) in self.nodes.present_fields() {
            let fa = &self.nodes.fields[f];
            let m = fa.mass[i];
            if !(m > 0.0) || !m.is_finite() {
                return Err(CheckError::NodalMass { step, node: i, field: f, mass: m });
            }
            if !fa.mom[i].x.is_finite() || !fa.mom[i].y.is_finite() {
                return Err(CheckError::NonFiniteNode {
                    step,
                    node: i,
                    field: f,
                    what: "momentum",
                    value: crate::check::fmt_vec(&fa.mom[i]),
                });
            }
            grid_mass.add(m);
        }
        let gm = grid_mass.value();
        let pm = crate::exact::sum(&self.particles.mass);
        if (gm - pm).abs() > MASS_TOL * pm {
            return Err(CheckError::TotalMass { step, grid: gm, particles: pm });
        }
        Ok(())
    }

    /// Checked mode at the end of a step: finite particle state, momentum conservation
    /// of the particles, and bounded energy.
    fn check_after_step(&self) -> Result<(), CheckError> {
        let step = self.step_count;
        let p = &self.particles;
        for i in 0..p.len() {
            let bad = |what: &'static str, value: String| CheckError::NonFiniteParticle { step, particle: i, id: p.id[i], what, value };
            if !(p.x[i].x.is_finite() && p.x[i].y.is_finite()) {
                return Err(bad("position", crate::check::fmt_vec(&p.x[i])));
            }
            if !(p.v[i].x.is_finite() && p.v[i].y.is_finite()) {
                return Err(bad("velocity", crate::check::fmt_vec(&p.v[i])));
            }
            if !p.stress[i].is_finite() {
                return Err(bad("stress", format!("{:?}", p.stress[i])));
            }
        }
        if self.momentum_conserving {
            let now = self.total_momentum();
            let before = self.momentum_ref;
            let scale = crate::exact::sum_iter((0..p.len()).map(|i| p.mass[i] * p.v[i].abs().sum()));
            let tol = MOMENTUM_TOL * scale.max(f64::MIN_POSITIVE);
            if (now - before).norm() > tol {
                return Err(CheckError::Momentum {
                    step,
                    stage: "particle update (Task 5)",
                    bx: before.x,
                    by: before.y,
                    ax: now.x,
                    ay: now.y,
                    tol,
                });
            }
        }
        let e = self.energies();
        let bound = 100.0 * (self.energy_scale + e.external_work.abs()) + f64::MIN_POSITIVE;
        if e.kinetic + e.strain > bound && self.energy_scale + e.external_work.abs() > 0.0 {
            return Err(CheckError::Unstable { step, total: e.kinetic + e.strain, scale: self.energy_scale + e.external_work.abs() });
        }
        Ok(())
    }
}
