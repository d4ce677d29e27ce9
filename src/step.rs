//! One MPM step, written as the appendix of Nairn 2003 lists it: one function per task.
//!
//! Every particle-to-node sum is a gather over the node's particle/node pairs (CSR built
//! in Task 1), and every node-to-particle sum runs over the particle's pairs; each is
//! correctly rounded, so a step's result does not depend on particle order, thread count,
//! or — for a scene symmetric about a grid line — on which side of the mirror a particle
//! is.
//!
//! Speed (issue 6), without changing a bit:
//! * the sums are computed with [`FastSum`], which certifies correct rounding, and redone
//!   in the rare case it cannot with a three-level compensated sum that certifies the
//!   cancelling sums of mirror planes, and [`ExactSum`] only for the lanes neither can
//!   certify (see `fast_or_exact`, and `Rerun` in `exact.rs`);
//! * per-node and per-particle work runs in parallel with rayon: each node's or
//!   particle's sums are independent, results are collected in index order into buffers
//!   kept across steps ([`Scratch`]), and stored serially;
//! * without cracks, and at the nodes and particles no crack splits, the gathers are
//!   compiled without velocity-field look-ups (`const` generics);
//! * the fast gathers and the shape functions also exist as copies compiled with AVX2
//!   ([`avx2`], chosen at run time by [`crate::simd`]; the same IEEE operations, so the
//!   same bits);
//! * the crack field assignment runs in parallel and tests only the crack segments near
//!   each particle–node pair ([`crate::crack::geometry::SegmentIndex`]);
//! * invariant checks run only in checked mode; energies only at history rows;
//! * nothing allocates once the buffers have grown to the scene (checked or not, any
//!   thread count; `tests/no_alloc.rs`).
//!
//! The step is generic over the dimension `S` ([`Dimension`]): the same tasks, sums and
//! checks in 2D and 3D, monomorphised per dimension; the crack tasks are the dimension's
//! own ([`Dimension::task1_cracks`] and the rest).

use crate::check::{CheckError, MASS_TOL, MOMENTUM_TOL, PARTITION_TOL};
use crate::dim::{GridGeometry, Space, SymOps, TensorOps, VectorOps};
use crate::exact::{Exact, ExactSum, Fast, Fast3, LaneSum, SumKind};
use crate::grid::MAX_FIELDS;
use crate::particles::NO_LOAD;
use crate::shape::ShapeKind;
use crate::simulation::{DampingOn, Dimension, Scheme, Simulation};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU8, Ordering};

/// `simd!(on, avx2_call, baseline_call)`: the AVX2 copy ([`avx2`]) when `on` (the value
/// of [`crate::simd::enabled`], read once per task), else the baseline code; both give
/// the same bits.
macro_rules! simd {
    ($on:expr, $avx2:expr, $base:expr) => {{
        #[cfg(target_arch = "x86_64")]
        {
            if $on {
                // SAFETY: enabled() is true only on a CPU with AVX2.
                unsafe { $avx2 }
            } else {
                $base
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            $base
        }
    }};
}

/// `g3!(f::<A>(args))`: the explicit AVX2 gather `crate::gather3::f` (called only when
/// `fast3d` gave the 3D simulation, i.e. on x86-64 with AVX2), its result as the generic
/// step's type; unreachable elsewhere.
macro_rules! g3 {
    ($($call:tt)*) => {{
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: fast3d gives Some only when the CPU has AVX2.
            unsafe { crate::gather3::$($call)* }.map(crate::gather3::same)
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            unreachable!("gather3 runs on x86-64 only")
        }
    }};
}

/// `g3_exact!(f(args))`: a `gather3` exact completion (no `Option`), its result as the
/// generic step's type.
macro_rules! g3_exact {
    ($($call:tt)*) => {{
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: fast3d gives Some only when the CPU has AVX2.
            crate::gather3::same(unsafe { crate::gather3::$($call)* })
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            unreachable!("gather3 runs on x86-64 only")
        }
    }};
}

/// `gather!(avx, rerun_avx, this.f::<CONST_ARGS>(args))`: the certified sums of one
/// gather, the same bits whichever way they come: the fast sums ([`Fast`]), else the
/// gather again with [`Exact`] accumulators (see [`fast_or_exact`]); the fast sums in their
/// AVX2 copy ([`avx2`]) when `avx` is set, the rerun when `rerun_avx` is.
///
/// The gathers of the pairs a crack may split (`CRACKS = true`) pass `rerun_avx = false`:
/// LLVM's AVX2 code of their reruns contains a `vmovq` encoding (VEX 66 0F D6, register
/// to register) that valgrind 3.19 cannot decode, which stopped callgrind on cracked
/// scenes; they are few, so their reruns run the baseline copy.
macro_rules! gather {
    ($avx:expr, $rerun_avx:expr, $this:ident . $f:ident :: <$($g:tt),*> ($($arg:expr),*)) => {
        fast_or_exact(
            || simd!($avx, avx2::$f::<S, Fast, $($g),*>($this, $($arg),*), $this.$f::<Fast, $($g),*>($($arg),*)),
            || simd!($rerun_avx, avx2::$f::<S, Exact, $($g),*>($this, $($arg),*), $this.$f::<Exact, $($g),*>($($arg),*)),
        )
    };
}

/// `gather_hinted!(avx, rerun_avx, hint, this.f::<CONST_ARGS>(args))`: [`gather!`] for a
/// node gather with a hint per node (see [`hinted`]): while the hint is set, the
/// three-level sums ([`Fast3`]) run instead of the fast ones (in the AVX2 copy when
/// `rerun_avx` is set).
macro_rules! gather_hinted {
    ($avx:expr, $rerun_avx:expr, $hint:expr, $this:ident . $f:ident :: <$($g:tt),*> ($($arg:expr),*)) => {
        hinted(
            $hint,
            || simd!($avx, avx2::$f::<S, Fast, $($g),*>($this, $($arg),*), $this.$f::<Fast, $($g),*>($($arg),*)),
            || simd!($rerun_avx, avx2::$f::<S, Fast3, $($g),*>($this, $($arg),*), $this.$f::<Fast3, $($g),*>($($arg),*)),
            || simd!($rerun_avx, avx2::$f::<S, Exact, $($g),*>($this, $($arg),*), $this.$f::<Exact, $($g),*>($($arg),*)),
        )
    };
}

impl<S: Dimension> Simulation<S> {
    /// Advance one time step (Tasks 0–8).
    pub fn step(&mut self) -> Result<(), CheckError> {
        let dt = self.options.dt;
        let scheme = self.options.scheme;
        // Steps are numbered from 1; every check inside this step reports this number.
        self.step_count += 1;
        self.apply_loads(self.time);
        self.collect_forced_particles();
        if self.options.checked && self.momentum_conserving {
            self.momentum_ref = self.total_momentum();
        }

        self.task0_shape_functions()?;
        self.task1_extrapolate()?;
        self.task2_boundary_conditions()?;
        match scheme {
            Scheme::Usf => self.update_stresses(dt),
            Scheme::Usavg => self.update_stresses(0.5 * dt),
            Scheme::Usl | Scheme::Musl => {}
        }
        self.task3_forces();
        if self.growth.is_some() {
            S::hold_released(self);
        }
        self.task4_update_momenta()?;
        self.task5_update_particles();
        match scheme {
            // Task 6a: stresses from the momenta of Task 4.
            Scheme::Usl => self.update_stresses(dt),
            // Task 6b: already updated in Task 2.
            Scheme::Usf => {}
            // Task 6c: re-extrapolate the new particle momenta, then update.
            Scheme::Musl => {
                self.task6c_reextrapolate()?;
                self.update_stresses(dt);
            }
            Scheme::Usavg => {
                self.task6c_reextrapolate()?;
                self.update_stresses(0.5 * dt);
            }
        }
        if self.has_cracks() {
            S::task7_move_cracks(self);
        }
        // Task 8: all information is back on the particles.
        self.time += dt;
        // Crack propagation (001 §2.3.2), only in scenes that let a crack grow.
        if self.growth.is_some() {
            S::grow_cracks(self)?;
        }
        if self.options.checked {
            self.check_after_step()?;
            if self.has_cracks() {
                S::check_crack_sides(self)?;
            }
        }
        crate::fingerprint::on_step(self);
        Ok(())
    }

    /// Task 0: shape functions and gradients at the particle positions (eq. 24), stored
    /// per particle/node pair. A particle outside the grid always stops the run.
    ///
    /// In parallel over particles: each particle writes only its own stride of the pair
    /// arrays. A failing particle is reported by the lowest index, as a serial loop would.
    fn task0_shape_functions(&mut self) -> Result<(), CheckError> {
        let grid = &self.grid;
        let kind = self.options.shape;
        let checked = self.options.checked;
        let avx = crate::simd::enabled();
        let p = &self.particles;
        let pairs = &mut self.pairs;
        let first_bad = (
            pairs.count.par_iter_mut(),
            pairs.node.par_chunks_mut(S::MAX_NODES),
            pairs.s.par_chunks_mut(S::MAX_NODES),
            pairs.g.par_chunks_mut(S::MAX_NODES),
        )
            .into_par_iter()
            .with_min_len(PARTICLE_CHUNK)
            .enumerate()
            .filter_map(|(i, (count, node, s, g))| {
                if !inside_grid::<S>(grid, kind, &p.x[i], &p.lp[i]) {
                    return Some(i);
                }
                let n = simd!(avx, avx2::weights_into::<S>(grid, kind, &p.x[i], &p.lp[i], node, s, g), S::weights_into(grid, kind, &p.x[i], &p.lp[i], node, s, g));
                *count = n as u8;
                (checked && partition_of_unity_error::<S>(grid, &s[..n], &g[..n]).is_some()).then_some(i)
            })
            .min();
        match first_bad {
            None => Ok(()),
            Some(i) => Err(self.task0_error(i)),
        }
    }

    /// The error for particle `i`, which failed Task 0: outside the grid, or (checked
    /// mode) a broken partition of unity.
    #[cold]
    fn task0_error(&self, i: usize) -> CheckError {
        let (grid, p, kind, step) = (&self.grid, &self.particles, self.options.shape, self.step_count);
        let x = p.x[i];
        if !inside_grid::<S>(grid, kind, &x, &p.lp[i]) {
            let (lo, hi) = (grid.origin(), grid.max_corner());
            use crate::check::components;
            return CheckError::OutsideGrid { step, particle: i, id: p.id[i], x: components(&x), lo: components(&lo), hi: components(&hi) };
        }
        let k = self.pairs.of_particle(i);
        let (sum_s, g) = partition_of_unity_error::<S>(grid, &self.pairs.s[k.clone()], &self.pairs.g[k]).expect("task 0 reported this particle");
        CheckError::PartitionOfUnity { step, particle: i, id: p.id[i], sum_s, g }
    }

    /// Task 1: velocity field of every particle/node pair (line crossing, cracks only),
    /// then nodal masses and momenta per field (eq. 26) and, with cracks, nodal volumes (eq. 27).
    ///
    /// Each node's sums are a gather over its pairs, independent of every other node's:
    /// computed in parallel over the active nodes, then stored in node order.
    fn task1_extrapolate(&mut self) -> Result<(), CheckError> {
        if self.has_cracks() {
            S::task1_cracks(self)?;
        }
        self.build_node_incidence();

        let with_cracks = self.has_cracks();
        let nf = self.nodes.fields.len();
        let mut sums = std::mem::take(&mut self.scratch.mass);
        let avx = crate::simd::enabled();
        let mut mv = std::mem::take(&mut self.scratch.mass_momentum);
        let fast3 = if avx { fast3d(self) } else { None };
        if let Some(d3) = fast3 {
            #[cfg(target_arch = "x86_64")]
            crate::gather3::fill_mass_momentum(d3, &mut mv);
        }
        let this = &*self;
        this.nodes
            .active
            .par_iter()
            .enumerate()
            .with_min_len(NODE_CHUNK)
            .map(|(a, &node)| {
                let hint = &this.scratch.gather_hints[node as usize][HINT_MASS];
                match (with_cracks, this.is_split(node)) {
                    (false, _) | (true, false) => match fast3 {
                        Some(d3) => hinted_lanes(
                            hint,
                            || g3!(node_mass::<crate::gather3::Acc4>(d3, &mv, a)),
                            || g3!(node_mass::<crate::gather3::Acc4x3>(d3, &mv, a)),
                            |u| g3_exact!(node_mass_exact(d3, &mv, a, u)),
                        ),
                        None => gather_hinted!(avx, avx, hint, this.node_mass::<false, false>(a)),
                    },
                    (true, true) => gather_hinted!(avx, false, hint, this.node_mass::<true, true>(a)),
                }
            })
            .collect_into_vec(&mut sums);
        self.scratch.mass_momentum = mv;
        let nodes = &mut self.nodes;
        for (&node, g) in nodes.active.iter().zip(sums.iter()) {
            let i = node as usize;
            nodes.present[i] = g.present;
            for (f, fa) in nodes.fields.iter_mut().enumerate().take(nf) {
                fa.mass[i] = g.mass[f];
                fa.mom[i] = g.mom[f];
            }
            if with_cracks {
                nodes.volume[i] = g.volume;
            }
        }
        self.scratch.mass = sums;
        if with_cracks {
            S::finish_crack_nodes(self)?;
        }
        if self.options.checked {
            self.check_nodal_masses()?;
        }
        Ok(())
    }

    /// Build the node → pair incidence (CSR) by a counting sort over the pairs, and the
    /// list of active nodes. Only nodes that some particle touches are visited, here and
    /// afterwards: the work is proportional to the pairs and the active nodes, never to
    /// the grid (which has 10⁶–10⁷ nodes in 3D).
    ///
    /// In parallel, with the serial result: the particles are split into contiguous
    /// chunks (one per thread); each chunk lists the nodes it touches first (an atomic
    /// mark per node), the lists are merged and sorted into the active nodes, and each
    /// active node gets its compact index (`pairs.slot`). The chunks count their pairs per
    /// active node; a serial prefix sum over the active nodes gives every (node, chunk)
    /// its own slots, chunk after chunk, so a node's pairs stay in particle order; then
    /// each chunk writes its pairs into its slots (through atomic cells, as the slots of
    /// different chunks interleave) and the slots are copied into `items`.
    fn build_node_incidence(&mut self) {
        let np = self.particles.len();
        let nn = self.grid.num_nodes();
        let pairs = &mut self.pairs;
        let scratch = &mut self.scratch;
        // Last step's present bits and compact indices are stale only on last step's active nodes.
        for &i in &self.nodes.active {
            self.nodes.present[i as usize] = 0;
            pairs.slot[i as usize] = u32::MAX;
        }
        if scratch.marks.len() != nn {
            scratch.marks = (0..nn).map(|_| AtomicBool::new(false)).collect();
            scratch.gather_hints = (0..nn).map(|_| Default::default()).collect();
        }
        let chunks = rayon::current_num_threads().clamp(1, np.div_ceil(4096).max(1));
        let per_chunk = np.div_ceil(chunks).max(1);
        scratch.chunk_counts.resize_with(chunks, Vec::new);
        scratch.chunk_nodes.resize_with(chunks, Vec::new);
        let (count, node) = (&pairs.count, &pairs.node);
        let stride = S::MAX_NODES;
        // Every pair (k, node) of chunk c, in order: nested loops over the particles and
        // their node slices (a flat_map iterator costs about twice the instructions).
        #[inline(always)]
        fn for_chunk_pairs(count: &[u8], node: &[u32], stride: usize, range: std::ops::Range<usize>, mut f: impl FnMut(usize, usize)) {
            for (i, &n) in count[range.clone()].iter().enumerate() {
                let base = (range.start + i) * stride;
                for (j, &nd) in node[base..base + n as usize].iter().enumerate() {
                    f(base + j, nd as usize);
                }
            }
        }
        let chunk = |c: usize| c * per_chunk..((c + 1) * per_chunk).min(np);
        // The nodes each chunk touches first.
        let marks = &scratch.marks[..];
        scratch.chunk_nodes.par_iter_mut().enumerate().for_each(|(c, list)| {
            list.clear();
            // Which chunk claims a node first is a race between threads, so a list's
            // length varies from step to step: reserve its bound once, so the step never
            // allocates (tests/three_d_no_alloc.rs).
            list.reserve(nn.min(per_chunk * stride));
            for_chunk_pairs(count, node, stride, chunk(c), |_, n| {
                // A plain load first: most pairs meet a node already marked, and the
                // swap (a locked exchange) is needed only to claim a new one.
                if !marks[n].load(Ordering::Relaxed) && !marks[n].swap(true, Ordering::Relaxed) {
                    list.push(n as u32);
                }
            });
        });
        // The active nodes, ascending, and their compact indices.
        let active = &mut self.nodes.active;
        active.clear();
        for list in &scratch.chunk_nodes {
            active.extend_from_slice(list);
        }
        active.sort_unstable();
        for (k, &n) in active.iter().enumerate() {
            marks[n as usize].store(false, Ordering::Relaxed);
            pairs.slot[n as usize] = k as u32;
        }
        let na = active.len();
        let slot = &pairs.slot;
        // Pairs per active node, per chunk.
        scratch.chunk_counts.par_iter_mut().enumerate().for_each(|(c, counts)| {
            counts.clear();
            counts.resize(na, 0);
            // Slices, not the Vecs: a store through a slice cannot change a Vec's pointer or
            // length, so they are not reloaded per pair.
            let (counts, slot) = (&mut counts[..], &slot[..]);
            for_chunk_pairs(count, node, stride, chunk(c), |_, n| counts[slot[n] as usize] += 1);
        });
        // Offsets: the a-th active node's pairs are items[start[a]..start[a+1]], chunk by
        // chunk; the counts become each chunk's write cursors.
        pairs.start.clear();
        pairs.start.push(0);
        let mut total = 0u32;
        for a in 0..na {
            for counts in scratch.chunk_counts.iter_mut() {
                let n = counts[a];
                counts[a] = total;
                total += n;
            }
            pairs.start.push(total);
        }
        let total = total as usize;
        if scratch.slots.len() < total {
            scratch.slots.resize_with(total, || AtomicU32::new(0));
        }
        let slots = &scratch.slots;
        scratch.chunk_counts.par_iter_mut().enumerate().for_each(|(c, cursor)| {
            let (cursor, slot, slots) = (&mut cursor[..], &slot[..], &slots[..]);
            for_chunk_pairs(count, node, stride, chunk(c), |k, n| {
                let a = slot[n] as usize;
                slots[cursor[a] as usize].store(k as u32, Ordering::Relaxed);
                cursor[a] += 1;
            });
        });
        pairs.items.resize(total, 0);
        // With each item its particle (item / MAX_NODES), which the 3D gathers of
        // `crate::gather3` read instead of dividing once per pair and gather. Reserved to
        // the most pairs there can be, so the resize never allocates.
        let owner = &mut scratch.item_particle;
        if owner.capacity() < np * stride {
            owner.reserve(np * stride - owner.len());
        }
        owner.resize(total, 0);
        (pairs.items.par_chunks_mut(4096), owner.par_chunks_mut(4096), slots[..total].par_chunks(4096)).into_par_iter().for_each(|(items, owners, slots)| {
            for ((item, owner), slot) in items.iter_mut().zip(owners.iter_mut()).zip(slots) {
                *item = slot.load(Ordering::Relaxed);
                *owner = *item / stride as u32;
            }
        });
    }

    /// Task 2: boundary conditions on the nodal momenta of Task 1 (and, with cracks, contact).
    fn task2_boundary_conditions(&mut self) -> Result<(), CheckError> {
        self.apply_momentum_bcs();
        if self.has_cracks() {
            S::contact_momenta(self)?;
        }
        Ok(())
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
                for c in 0..S::DIM {
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
    /// In parallel over particles (each particle reads the grid and writes only itself).
    pub(crate) fn update_stresses(&mut self, dt_star: f64) {
        self.compute_nodal_velocities();
        let with_cracks = self.has_cracks();
        let mut grads = std::mem::take(&mut self.scratch.grad_v);
        let this = &*self;
        let avx = crate::simd::enabled();
        let fast3 = if avx { fast3d(this) } else { None };
        let grad_v = |i: usize| match with_cracks && this.is_split_particle(i) {
            false => match fast3 {
                Some(d3) => g3!(velocity_gradient(d3, i)).unwrap_or_else(|| g3_exact!(velocity_gradient_exact(d3, i))),
                None => gather!(avx, avx, this.velocity_gradient::<false>(i)),
            },
            true => gather!(avx, false, this.velocity_gradient::<true>(i)),
        };
        // Velocity gradients first (reading the grid), then the particle updates.
        (0..self.particles.len()).into_par_iter().with_min_len(PARTICLE_CHUNK).map(grad_v).collect_into_vec(&mut grads);
        let materials = &self.materials;
        let p = &mut self.particles;
        (p.strain.par_iter_mut(), p.stress.par_iter_mut(), p.grad_u.par_iter_mut(), p.material.par_iter(), grads.par_iter())
            .into_par_iter()
            .with_min_len(PARTICLE_CHUNK)
            .for_each(|(strain, stress, grad_u, &material, grad_v)| {
                let dl = *grad_v * dt_star;
                let de = S::Sym::sym_part(&dl);
                S::hooke(&materials[material as usize], &de, strain, stress);
                *grad_u += dl;
            });
        self.scratch.grad_v = grads;
    }

    /// Task 3: internal and external nodal forces per field (eq. 28), total force with
    /// damping −κp, zeroed in fixed directions. Also accumulates the damping energy.
    /// The per-node gathers run in parallel over the active nodes.
    fn task3_forces(&mut self) {
        let kappa = self.options.damping;
        let nf = self.nodes.fields.len();
        let has_body = self.body_force.iter().any(|b| *b != S::Vector::zeros());
        let has_ext = !self.loads.is_empty() || has_body;
        if has_ext {
            self.mark_loaded_nodes(has_body);
        }
        let mut sums = std::mem::take(&mut self.scratch.force);
        let avx = crate::simd::enabled();
        let mut cols = std::mem::take(&mut self.scratch.stress_columns);
        let fast3 = if avx { fast3d(self) } else { None };
        if let Some(d3) = fast3 {
            #[cfg(target_arch = "x86_64")]
            crate::gather3::fill_stress_columns(d3, &mut cols);
        }
        let this = &*self;
        let loaded = &self.scratch.loaded_nodes;
        this.nodes
            .active
            .par_iter()
            .enumerate()
            .with_min_len(NODE_CHUNK)
            .map(|(a, &node)| {
                let ext = has_ext && loaded[a];
                let hint = &this.scratch.gather_hints[node as usize][HINT_FORCE];
                match this.is_split(node) {
                    false if !ext && fast3.is_some() => hinted_lanes(
                        hint,
                        || g3!(node_forces::<crate::gather3::Acc4>(fast3.unwrap(), &cols, a)),
                        || g3!(node_forces::<crate::gather3::Acc4x3>(fast3.unwrap(), &cols, a)),
                        |u| g3_exact!(node_forces_exact(fast3.unwrap(), &cols, a, u)),
                    ),
                    false => gather_hinted!(avx, avx, hint, this.node_forces::<false>(a, ext, has_body)),
                    true => gather_hinted!(avx, false, hint, this.node_forces::<true>(a, ext, has_body)),
                }
            })
            .collect_into_vec(&mut sums);
        let nodes = &mut self.nodes;
        for (&node, g) in nodes.active.iter().zip(sums.iter()) {
            let i = node as usize;
            for (f, fa) in nodes.fields.iter_mut().enumerate().take(nf) {
                if nodes.present[i] & (1 << f) == 0 {
                    continue;
                }
                fa.fint[i] = g.fint[f];
                fa.fext[i] = g.fext[f];
                let mom = fa.mom[i];
                fa.ftot[i] = (fa.fint[i] + fa.fext[i]) - mom * kappa;
            }
        }
        self.scratch.force = sums;
        self.scratch.stress_columns = cols;
        // Cohesive crack segments pull their faces together (2D growth with a cohesive law).
        if self.growth.is_some() {
            S::apply_cohesive(self);
        }
        // The reactions, before the fixed directions' forces are removed.
        self.work.boundary_work += self.boundary_power() * self.options.dt;
        let nodes = &mut self.nodes;
        // Fixed directions do not accelerate.
        for &node in &self.bcs.nodes {
            let i = node as usize;
            let mask = self.bcs.mask[i];
            for fa in nodes.fields.iter_mut() {
                for c in 0..S::DIM {
                    if mask & (1 << c) != 0 {
                        fa.ftot[i][c] = 0.0;
                    }
                }
            }
        }
        // Power of the damping force κp·v = κ|p|²/m, over every field in use.
        let damp_power = if kappa != 0.0 {
            let n = &self.nodes;
            crate::exact::sum_fast(n.present_fields().map(|(f, i)| kappa * n.fields[f].mom[i].norm_squared() / n.fields[f].mass[i]))
        } else {
            0.0
        };
        self.work.damping += self.options.dt * damp_power;
    }

    /// Power of the velocity boundary conditions, Σ v_c R_c over every field of every node
    /// component held at a non-zero velocity v_c. The reaction R_c = −f_tot,c is the force
    /// the condition removes in Task 3 (internal, external and damping force −κp, eq. 28),
    /// so that R_c v_c Δt is the energy the moving node puts into the body: the kinetic
    /// energy of Task 5 gets nothing from a held component (its acceleration is zero),
    /// while the strain energy of Task 6 takes −f_int,c v_c Δt, the external work
    /// f_ext,c v_c Δt (the particles move with the node) and the damping energy κ p_c v_c Δt
    /// (eq. 28's power is counted at every field). Components held still do no work and
    /// are skipped, so the sum is +0 in scenes without moving conditions. Summed exactly:
    /// the same bits for any particle order and thread count.
    fn boundary_power(&self) -> f64 {
        let (bcs, nodes) = (&self.bcs, &self.nodes);
        let moving = |i: usize, c: usize| bcs.mask[i] & (1 << c) != 0 && bcs.vel[i][c] != 0.0;
        let terms = bcs.nodes.iter().map(|&node| node as usize).flat_map(|i| {
            nodes.fields.iter().enumerate().filter(move |(f, _)| nodes.present[i] & (1 << f) != 0).flat_map(move |(_, fa)| {
                (0..S::DIM).filter(move |&c| moving(i, c)).map(move |c| -fa.ftot[i][c] * bcs.vel[i][c])
            })
        });
        crate::exact::sum_fast(terms)
    }

    /// Which active nodes have a pair whose external force term `node_forces` computes:
    /// those of the particles with a body force, a non-zero load or a non-finite mass
    /// (`scratch.loaded_nodes`, by active position). At every other node all its terms are
    /// the +0 of an unloaded particle, whose sum `node_forces` gives as +0 without
    /// visiting its pairs: the same bits, without a test per pair (in the DCB, a few end
    /// layers of particles carry the loads).
    fn mark_loaded_nodes(&mut self, has_body: bool) {
        let (p, pairs) = (&self.particles, &self.pairs);
        let loaded = &mut self.scratch.loaded_nodes;
        loaded.clear();
        loaded.resize(self.nodes.active.len(), false);
        for i in 0..p.len() {
            // The test of `node_forces` for a term it may skip.
            let unloaded = !has_body && (0..S::DIM).all(|c| p.force[i][c].to_bits() == 0) && p.mass[i].is_finite();
            if !unloaded {
                for k in pairs.of_particle(i) {
                    loaded[pairs.slot[pairs.node[k] as usize] as usize] = true;
                }
            }
        }
    }

    /// Task 4: p' = p + Δt f_tot (eq. 29); then contact, with forces back-computed.
    fn task4_update_momenta(&mut self) -> Result<(), CheckError> {
        let dt = self.options.dt;
        let check_momentum = self.options.checked && self.momentum_conserving;
        let before = if check_momentum { self.nodal_momentum_total() } else { S::Vector::zeros() };
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
            S::contact_updated_momenta(self)?;
        }
        if check_momentum {
            let after = self.nodal_momentum_total();
            let scale = self.force_scale() * dt + self.nodal_momentum_scale();
            let tol = MOMENTUM_TOL * scale.max(f64::MIN_POSITIVE);
            // Non-finite momenta are named by the finiteness checks, which point at the culprit.
            if after.is_finite() && before.is_finite() && (after - before).norm() > tol {
                use crate::check::components;
                return Err(CheckError::Momentum { step: self.step_count, stage: "task 4 (nodal momentum update)", before: components(&before), after: components(&after), tol });
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
    /// The sums run in parallel over particles.
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
        let with_cracks = self.has_cracks();
        let mut incs = std::mem::take(&mut self.scratch.increments);
        let this = &*self;
        let avx = crate::simd::enabled();
        let fast3 = if avx { fast3d(this) } else { None };
        let increments = |i: usize| match with_cracks && this.is_split_particle(i) {
            false => match fast3 {
                Some(d3) => fast_or_exact(
                    || g3!(particle_increments(d3, i)),
                    || simd!(avx, avx2::particle_increments::<S, Exact, false>(this, i), this.particle_increments::<Exact, false>(i)),
                ),
                None => gather!(avx, avx, this.particle_increments::<false>(i)),
            },
            true => gather!(avx, false, this.particle_increments::<true>(i)),
        };
        (0..self.particles.len()).into_par_iter().with_min_len(PARTICLE_CHUNK).map(increments).collect_into_vec(&mut incs);
        let p = &mut self.particles;
        // Work of the external loads, summed exactly over the particles with a load or a
        // body force: the others' terms are ±0, which change the exact sum only in its
        // sign when it is exactly zero, so that case is summed over all particles.
        let has_ext = !self.loads.is_empty() || self.body_force.iter().any(|b| *b != S::Vector::zeros());
        if has_ext {
            let body_force = &self.body_force;
            let work = |i: usize| {
                let f = p.force[i] + body_force[p.body[i] as usize] * p.mass[i];
                f.dot(&(incs[i].0 * dt))
            };
            let mut sum = crate::exact::sum_fast(self.scratch.forced.iter().map(|&i| work(i as usize)));
            if sum == 0.0 {
                sum = crate::exact::sum_fast((0..p.len()).map(work));
            }
            self.work.external_work += sum;
        } else {
            self.work.external_work += 0.0;
        }
        let kappa = self.options.damping;
        if kappa != 0.0 && self.options.damping_on == DampingOn::Particles {
            // Particle damping: the grid force −κp already gave each particle −κ Σ S v_i;
            // the rest of −κ v_p is −κ (v_p − Σ S v_i), the part the grid cannot see. Its
            // work, κ Δt Σ m_p v_p·(v_p − Σ S v_i), joins the damping energy.
            let (mass, v) = (&p.mass, &p.v);
            self.work.damping += crate::exact::sum_fast((0..p.len()).map(|i| kappa * dt * mass[i] * v[i].dot(&(v[i] - incs[i].0))));
            (p.x.par_iter_mut(), p.v.par_iter_mut(), incs.par_iter()).into_par_iter().with_min_len(PARTICLE_CHUNK).for_each(|(x, v, (vel, acc))| {
                *x += *vel * dt;
                *v += *acc * dt - (*v - *vel) * (kappa * dt);
            });
        } else {
            (p.x.par_iter_mut(), p.v.par_iter_mut(), incs.par_iter()).into_par_iter().with_min_len(PARTICLE_CHUNK).for_each(|(x, v, (vel, acc))| {
                *x += *vel * dt;
                *v += *acc * dt;
            });
        }
        self.scratch.increments = incs;
    }

    /// Task 6c: extrapolate the new particle momenta to the grid with the shape functions
    /// and fields of Task 1 (eq. 31), then boundary conditions and contact. The per-node
    /// gathers run in parallel over the active nodes.
    fn task6c_reextrapolate(&mut self) -> Result<(), CheckError> {
        let nf = self.nodes.fields.len();
        let mut sums = std::mem::take(&mut self.scratch.momentum);
        let avx = crate::simd::enabled();
        let mut mv = std::mem::take(&mut self.scratch.mass_momentum);
        let fast3 = if avx { fast3d(self) } else { None };
        if let Some(d3) = fast3 {
            #[cfg(target_arch = "x86_64")]
            crate::gather3::fill_mass_momentum(d3, &mut mv);
        }
        let this = &*self;
        this.nodes
            .active
            .par_iter()
            .enumerate()
            .with_min_len(NODE_CHUNK)
            .map(|(a, &node)| {
                let hint = &this.scratch.gather_hints[node as usize][HINT_MOMENTUM];
                match this.is_split(node) {
                    false if fast3.is_some() => hinted_lanes(
                        hint,
                        || g3!(node_momentum::<crate::gather3::Acc4>(fast3.unwrap(), &mv, a)),
                        || g3!(node_momentum::<crate::gather3::Acc4x3>(fast3.unwrap(), &mv, a)),
                        |u| g3_exact!(node_momentum_exact(fast3.unwrap(), &mv, a, u)),
                    ),
                    false => gather_hinted!(avx, avx, hint, this.node_momentum::<false>(a)),
                    true => gather_hinted!(avx, false, hint, this.node_momentum::<true>(a)),
                }
            })
            .collect_into_vec(&mut sums);
        let nodes = &mut self.nodes;
        for (&node, mom) in nodes.active.iter().zip(sums.iter()) {
            let i = node as usize;
            for (f, fa) in nodes.fields.iter_mut().enumerate().take(nf) {
                if nodes.present[i] & (1 << f) != 0 {
                    fa.mom[i] = mom[f];
                }
            }
        }
        self.scratch.momentum = sums;
        self.scratch.mass_momentum = mv;
        self.apply_momentum_bcs();
        if self.has_cracks() {
            S::contact_momenta(self)?;
        }
        Ok(())
    }

    /// List the particles with a load or a body force (for the external work of Task 5).
    fn collect_forced_particles(&mut self) {
        let has_body = self.body_force.iter().any(|b| *b != S::Vector::zeros());
        let (p, body_force, forced) = (&self.particles, &self.body_force, &mut self.scratch.forced);
        forced.clear();
        if self.loads.is_empty() && !has_body {
            return;
        }
        forced.extend((0..p.len()).filter(|&i| p.load[i] != NO_LOAD || (has_body && body_force[p.body[i] as usize] != S::Vector::zeros())).map(|i| i as u32));
    }

    /// Exact total of the nodal momenta over all fields.
    fn nodal_momentum_total(&self) -> S::Vector {
        let mut sums = [ExactSum::new(), ExactSum::new(), ExactSum::new()];
        for (f, i) in self.nodes.present_fields() {
            let p = self.nodes.fields[f].mom[i];
            for (c, sum) in sums.iter_mut().enumerate().take(S::DIM) {
                sum.add(p[c]);
            }
        }
        S::Vector::from_fn(|c| sums[c].value())
    }

    /// Σ |p| over nodes: the scale against which a change of total momentum is judged.
    fn nodal_momentum_scale(&self) -> f64 {
        let n = &self.nodes;
        crate::exact::sum_fast(n.present_fields().map(|(f, i)| n.fields[f].mom[i].abs_sum()))
    }

    /// Σ |f_int| over nodes: the scale against which Σ f_int = 0 is judged.
    fn force_scale(&self) -> f64 {
        let n = &self.nodes;
        crate::exact::sum_fast(n.present_fields().map(|(f, i)| n.fields[f].fint[i].abs_sum()))
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
            if !fa.mom[i].is_finite() {
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
            if !p.x[i].is_finite() {
                return Err(bad("position", crate::check::fmt_vec(&p.x[i])));
            }
            if !p.v[i].is_finite() {
                return Err(bad("velocity", crate::check::fmt_vec(&p.v[i])));
            }
            if !p.stress[i].is_finite() {
                return Err(bad("stress", format!("{:?}", p.stress[i])));
            }
        }
        if self.momentum_conserving {
            let now = self.total_momentum();
            let before = self.momentum_ref;
            let scale = crate::exact::sum_fast((0..p.len()).map(|i| p.mass[i] * p.v[i].abs_sum()));
            let tol = MOMENTUM_TOL * scale.max(f64::MIN_POSITIVE);
            if (now - before).norm() > tol {
                use crate::check::components;
                return Err(CheckError::Momentum { step, stage: "particle update (Task 5)", before: components(&before), after: components(&now), tol });
            }
        }
        // Kinetic + strain energy can only exceed the energy put in (initial, loads, moving
        // grips) by the scheme's error; 100 times it is a blow-up.
        let e = self.energies();
        let scale = self.energy_scale + e.external_work.abs() + e.boundary_work.abs();
        let bound = 100.0 * scale + f64::MIN_POSITIVE;
        if e.kinetic + e.strain > bound && scale > 0.0 {
            return Err(CheckError::Unstable { step, total: e.kinetic + e.strain, scale });
        }
        Ok(())
    }
}

/// The sums of the step, one node or one particle at a time, written once for any
/// [`SumKind`] and any dimension: run with [`Fast`] sums, and with [`Exact`] ones when the
/// fast sum cannot certify a result (see [`fast_or_exact`]). `CRACKS = false` compiles the
/// crack-free variant, where every pair is in field 0 (no field look-ups, no volume sums);
/// it also serves the nodes that no crack splits in a cracked scene. The quantities summed
/// together per pair are the lanes of one accumulator (1 + DIM for mass and momentum, DIM
/// for forces, DIM² for the velocity gradient, 2·DIM for the particle increments). The
/// node gathers take the node's position `a` in the ascending list `nodes.active`.
impl<S: Dimension> Simulation<S> {
    /// May the pairs of `node` be in fields other than 0? Only if the scene has cracks and
    /// the line-crossing test of Task 1 found a crack between the node and one of its
    /// particles (which records the crack in `nodes.crack`); otherwise all are in field 0.
    #[inline]
    fn is_split(&self, node: u32) -> bool {
        self.has_cracks() && self.nodes.crack[node as usize] != u16::MAX
    }

    /// May the pairs of particle `i` be in fields other than 0? Not if Task 1's crossing
    /// tests gave every one of them field 0 (`scratch.split`, written by the dimension's
    /// field assignment each step; when it is not there — node visibility, or a copy of
    /// the simulation that has not run Task 1 — assume they may).
    #[inline]
    fn is_split_particle(&self, i: usize) -> bool {
        self.scratch.split.get(i).copied().unwrap_or(true)
    }

    /// Give field 0 to every pair of the active node `a` (position in `nodes.active`) whose
    /// field is in `join` (bit f for field f), and gather the node's Task 1 sums again
    /// ([`Self::node_mass`], the sums of a split node): the node then holds exactly what it
    /// would have held had the crossing test given those pairs field 0, and the later tasks,
    /// which read `pairs.field`, treat those particles as field 0 there. The node's crack
    /// (`nodes.crack`) is kept. For a node one crack splits three ways
    /// ([`crate::crack::three_d`]'s `finish_crack_nodes`).
    pub(crate) fn join_fields_into_zero(&mut self, a: usize, join: u8) {
        let (start, end) = (self.pairs.start[a] as usize, self.pairs.start[a + 1] as usize);
        for k in start..end {
            let item = self.pairs.items[k] as usize;
            if join & (1 << self.pairs.field[item]) != 0 {
                self.pairs.field[item] = 0;
            }
        }
        let g = fast_or_exact(|| self.node_mass::<Fast, true, true>(a), || self.node_mass::<Exact, true, true>(a));
        let i = self.nodes.active[a] as usize;
        let nodes = &mut self.nodes;
        nodes.present[i] = g.present;
        for (f, fa) in nodes.fields.iter_mut().enumerate() {
            fa.mass[i] = g.mass[f];
            fa.mom[i] = g.mom[f];
        }
        nodes.volume[i] = g.volume;
    }

    /// Task 1 at one node: mass and momentum per field (eq. 26), and the nodal area per
    /// unit thickness (eq. 27; the volume in 3D) for contact.
    ///
    /// `FIELDS = false` for a node no crack splits (every pair in field 0); `VOLUME` at the
    /// nodes a crack splits, the only ones where contact reads the nodal volume (NaN
    /// elsewhere: not computed).
    #[inline(always)]
    fn node_mass<K: SumKind, const FIELDS: bool, const VOLUME: bool>(&self, a: usize) -> Option<NodeMass<S::Vector>> {
        let (p, pairs) = (&self.particles, &self.pairs);
        let mut acc: [K::Of<S::MassLanes>; MAX_FIELDS] = Default::default();
        let mut vol = K::Of::<[f64; 1]>::default();
        let mut present = 0u8;
        for &item in pairs.of_active(a) {
            let item = item as usize;
            let pp = item / S::MAX_NODES;
            let f = if FIELDS { pairs.field[item] as usize } else { 0 };
            let s = pairs.s[item];
            let m = p.mass[pp];
            present |= 1 << f;
            let mut lanes = S::MassLanes::default();
            lanes[0] = m * s;
            for c in 0..S::DIM {
                lanes[c + 1] = m * p.v[pp][c] * s;
            }
            let w = if FIELDS { pairs.frac[item] } else { 1.0 };
            if w != 1.0 {
                present |= 1;
            }
            add_shared(&mut acc, f, w, lanes, S::DIM + 1);
            if VOLUME {
                // Nodal area (eq. 27 per unit thickness), compared with the cell area.
                // The particle's current area, eq. 25 per unit thickness (only the pairs of
                // split nodes need it).
                let area = p.volume(pp) / self.thickness[p.body[pp] as usize];
                vol.add_lanes([area * s]);
            }
        }
        let mut out = NodeMass { present, ..Default::default() };
        for (f, a) in acc.iter().enumerate().take(self.nodes.fields.len()) {
            let l = a.certified_lanes()?;
            out.mass[f] = l[0];
            out.mom[f] = S::Vector::from_fn(|c| l[c + 1]);
        }
        out.volume = if VOLUME { vol.certified_lanes()?[0] } else { f64::NAN };
        Some(out)
    }

    /// Task 3 at one node: internal force −Σ V σ·G and external force Σ f S per field (eq. 28).
    /// `has_ext` is false at a node no particle with an external force term touches
    /// (`mark_loaded_nodes`): its external force is +0, as the sum of the terms gives.
    #[inline(always)]
    fn node_forces<K: SumKind, const CRACKS: bool>(&self, a: usize, has_ext: bool, has_body: bool) -> Option<NodeForce<S::Vector>> {
        let (p, pairs) = (&self.particles, &self.pairs);
        let node = self.nodes.active[a];
        let mut int: [K::Of<S::VecLanes>; MAX_FIELDS] = Default::default();
        let mut ext: [K::Of<S::VecLanes>; MAX_FIELDS] = Default::default();
        let mut skipped_zeros = [false; MAX_FIELDS];
        for &item in pairs.of_active(a) {
            let item = item as usize;
            let pp = item / S::MAX_NODES;
            let f = if CRACKS { pairs.field[item] as usize } else { 0 };
            // f_int = −V σ·G (the paper's −m σ̄·G with specific stress σ̄ = σ/ρ).
            let t = p.stress[pp].dot_vec(&pairs.g[item]);
            let v0 = p.vol0[pp];
            let mut lanes = S::VecLanes::default();
            for c in 0..S::DIM {
                lanes[c] = -(v0 * t[c]);
            }
            let w = if CRACKS { pairs.frac[item] } else { 1.0 };
            add_shared(&mut int, f, w, lanes, S::DIM);
            if has_ext {
                let force = p.force[pp];
                if !has_body && (0..S::DIM).all(|c| force[c].to_bits() == 0) && p.mass[pp].is_finite() {
                    // An unloaded particle: f_p = +0 + (±0)·m = (+0, +0) exactly, and its
                    // terms +0·S = +0 only decide the sign of an all-zero sum (below).
                    skipped_zeros[f] = true;
                    if w != 1.0 {
                        skipped_zeros[0] = true;
                    }
                } else {
                    let s = pairs.s[item];
                    let fp = force + self.body_force[p.body[pp] as usize] * p.mass[pp];
                    let mut lanes = S::VecLanes::default();
                    for c in 0..S::DIM {
                        lanes[c] = fp[c] * s;
                    }
                    add_shared(&mut ext, f, w, lanes, S::DIM);
                }
            }
        }
        let mut out = NodeForce::default();
        for f in 0..self.nodes.fields.len() {
            if self.nodes.present[node as usize] & (1 << f) != 0 {
                let (i, e) = (int[f].certified_lanes()?, ext[f].certified_lanes()?);
                out.fint[f] = S::Vector::from_fn(|c| i[c]);
                out.fext[f] = if skipped_zeros[f] {
                    // With the +0 terms added, a −0 sum would have been +0 (x + 0 = x otherwise).
                    S::Vector::from_fn(|c| e[c] + 0.0)
                } else {
                    S::Vector::from_fn(|c| e[c])
                };
            }
        }
        Some(out)
    }

    /// Task 6c at one node: momentum per field from the new particle velocities (eq. 31).
    #[inline(always)]
    fn node_momentum<K: SumKind, const CRACKS: bool>(&self, a: usize) -> Option<[S::Vector; MAX_FIELDS]> {
        let (p, pairs) = (&self.particles, &self.pairs);
        let node = self.nodes.active[a];
        let mut acc: [K::Of<S::VecLanes>; MAX_FIELDS] = Default::default();
        for &item in pairs.of_active(a) {
            let item = item as usize;
            let pp = item / S::MAX_NODES;
            let f = if CRACKS { pairs.field[item] as usize } else { 0 };
            let s = pairs.s[item];
            let m = p.mass[pp];
            let mut lanes = S::VecLanes::default();
            for c in 0..S::DIM {
                lanes[c] = m * p.v[pp][c] * s;
            }
            let w = if CRACKS { pairs.frac[item] } else { 1.0 };
            add_shared(&mut acc, f, w, lanes, S::DIM);
        }
        let mut out = [S::Vector::zeros(); MAX_FIELDS];
        for (f, mom) in out.iter_mut().enumerate().take(self.nodes.fields.len()) {
            if self.nodes.present[node as usize] & (1 << f) != 0 {
                let l = acc[f].certified_lanes()?;
                *mom = S::Vector::from_fn(|c| l[c]);
            }
        }
        Some(out)
    }

    /// Velocity gradient at particle `i` (eq. 36): Σ v_i ⊗ G_ip over its pairs, each in
    /// the pair's own velocity field.
    #[inline(always)]
    fn velocity_gradient<K: SumKind, const CRACKS: bool>(&self, i: usize) -> Option<S::Tensor> {
        let (nodes, pairs) = (&self.nodes, &self.pairs);
        let mut l = K::Of::<S::TensorLanes>::default();
        let k = pairs.of_particle(i);
        for (((&f, &node), g), item) in pairs.field[k.clone()].iter().zip(&pairs.node[k.clone()]).zip(&pairs.g[k.clone()]).zip(k) {
            let f = if CRACKS { f as usize } else { 0 };
            let mut v = nodes.fields[f].vel[node as usize];
            if CRACKS && pairs.frac[item] != 1.0 {
                // A pair in a crack-tip zone sees its two fields' velocities in its shares.
                let w = pairs.frac[item];
                v = v * w + nodes.fields[0].vel[node as usize] * (1.0 - w);
            }
            let mut lanes = S::TENSOR_TERM;
            for a in 0..S::DIM {
                for b in 0..S::DIM {
                    lanes[a * S::TENSOR_ROW + b] = v[a] * g[b];
                }
            }
            l.add_lanes(lanes);
        }
        let t = l.certified_lanes()?;
        Some(S::Tensor::from_fn(|a, b| t[a * S::TENSOR_ROW + b]))
    }

    /// Task 5 at particle `i` (eq. 30): (Σ S v_i, Σ S a_i) over its pairs, the velocity
    /// that moves the particle and the acceleration that updates its velocity.
    #[inline(always)]
    fn particle_increments<K: SumKind, const CRACKS: bool>(&self, i: usize) -> Option<(S::Vector, S::Vector)> {
        let (nodes, pairs) = (&self.nodes, &self.pairs);
        let mut s = K::Of::<S::IncLanes>::default();
        let k = pairs.of_particle(i);
        for (((&f, &n), &w), item) in pairs.field[k.clone()].iter().zip(&pairs.node[k.clone()]).zip(&pairs.s[k.clone()]).zip(k) {
            let fa = &nodes.fields[if CRACKS { f as usize } else { 0 }];
            let n = n as usize;
            let (mut vel, mut acc) = (fa.vel[n], fa.acc[n]);
            if CRACKS && pairs.frac[item] != 1.0 {
                // A pair in a crack-tip zone moves with its two fields in its shares.
                let (share, fb) = (pairs.frac[item], &nodes.fields[0]);
                vel = vel * share + fb.vel[n] * (1.0 - share);
                acc = acc * share + fb.acc[n] * (1.0 - share);
            }
            let mut lanes = S::IncLanes::default();
            for c in 0..S::DIM {
                lanes[c] = w * vel[c];
                lanes[S::DIM + c] = w * acc[c];
            }
            s.add_lanes(lanes);
        }
        let l = s.certified_lanes()?;
        Some((S::Vector::from_fn(|c| l[c]), S::Vector::from_fn(|c| l[S::DIM + c])))
    }
}

/// Add a pair's terms (the first `n` lanes of `lanes`) to field `f`, or, for a pair in a
/// crack-tip zone with share `w` < 1 (crack::tip_zone), w of them to field `f` and 1 − w
/// to field 0.
#[inline(always)]
pub(crate) fn add_shared<L: crate::exact::Lanes, A: crate::exact::LaneSum<L>>(acc: &mut [A; MAX_FIELDS], f: usize, w: f64, lanes: L, n: usize) {
    if w == 1.0 {
        acc[f].add_lanes(lanes);
        return;
    }
    let (mut a, mut b) = (lanes, lanes);
    for c in 0..n {
        a[c] *= w;
        b[c] *= 1.0 - w;
    }
    acc[f].add_lanes(a);
    acc[0].add_lanes(b);
}

/// Which node gather a hint of `Scratch::gather_hints` is for.
const HINT_MASS: usize = 0;
const HINT_FORCE: usize = 1;
const HINT_MOMENTUM: usize = 2;
/// Steps a node gather runs with [`Fast3`] after its fast sums failed, before it tries
/// them again.
const HINT_STEPS: u8 = 8;

/// A node gather with a hint: the nodes whose fast sums fail in one step (the nodes on
/// the mirror planes of a symmetric scene, where a sum cancels to zero or to round-off)
/// nearly always fail in the next ones too, and then pay for two gathers, the fast one
/// and the rerun. So after a failure the node's next [`HINT_STEPS`] gathers of that kind
/// run with [`Fast3`] (three-level sums, which certify those sums) straight away, and
/// then the fast sums are tried again. [`Exact`] follows whenever the sums in use cannot
/// certify. Every path gives the correctly rounded sums, so the hint moves no bit; it is
/// read and written only by the task gathering this node (one per node and step).
#[inline(always)]
fn hinted<T>(hint: &AtomicU8, fast: impl FnOnce() -> Option<T>, three: impl FnOnce() -> Option<T>, exact: impl FnOnce() -> Option<T>) -> T {
    let steps = hint.load(Ordering::Relaxed);
    if steps == 0 {
        if let Some(v) = fast() {
            return v;
        }
        hint.store(HINT_STEPS, Ordering::Relaxed);
        return rerun(exact).expect("ExactSum always certifies its sums");
    }
    hint.store(steps - 1, Ordering::Relaxed);
    three().or_else(|| rerun(exact)).expect("ExactSum always certifies its sums")
}

/// [`hinted`] for the 3D node gathers of `gather3`, which say which lanes they left
/// uncertified (`Err(u)`): the fast sums (or, while the hint is set, the three-level ones)
/// first; where the fast sums fail, the three-level sums; the lanes those leave open are
/// summed exactly by `exact(u)` over the same terms (`gather3::ExactLanes`). The hint
/// works as in [`hinted`]. Every certified lane and every exact one is the correctly
/// rounded sum, so which of them a lane took does not show in the bits.
#[inline(always)]
fn hinted_lanes<T, U>(hint: &AtomicU8, fast: impl FnOnce() -> Result<T, U>, three: impl FnOnce() -> Result<T, U>, exact: impl FnOnce(U) -> T) -> T {
    let steps = hint.load(Ordering::Relaxed);
    if steps == 0 {
        match fast() {
            Ok(v) => return v,
            Err(_) => hint.store(HINT_STEPS, Ordering::Relaxed),
        }
    } else {
        hint.store(steps - 1, Ordering::Relaxed);
    }
    three().unwrap_or_else(exact)
}

/// Run a gather's exact rerun out of line: its [`Exact`] accumulators keep their terms
/// (tens of kilobytes of stack), which inlined into the caller made every call of the
/// gather probe that stack, page by page, rerun or not.
#[cold]
#[inline(never)]
fn rerun<T>(exact: impl FnOnce() -> Option<T>) -> Option<T> {
    exact()
}

/// The fast sums if they certify their results, else the gather again with [`Exact`]
/// accumulators (`exact::Rerun`: exact sums for the lanes the fast sums cannot certify).
/// Both give the correctly rounded sums, so the bits do not depend on which was used.
#[inline(always)]
fn fast_or_exact<T>(fast: impl FnOnce() -> Option<T>, exact: impl FnOnce() -> Option<T>) -> T {
    fast().or_else(|| rerun(exact)).expect("ExactSum always certifies its sums")
}

/// Copies of the gathers (fast and rerun, `K`) and of the shape functions compiled with
/// AVX2 (see [`crate::simd`]): each is the baseline function inlined (`#[inline(always)]`)
/// into a function with the `avx2` target feature, so the same IEEE operations run on
/// wider registers and give the same bits.
#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::*;

    #[target_feature(enable = "avx2")]
    pub(super) fn node_mass<S: Dimension, K: SumKind, const FIELDS: bool, const VOLUME: bool>(s: &Simulation<S>, a: usize) -> Option<NodeMass<S::Vector>> {
        s.node_mass::<K, FIELDS, VOLUME>(a)
    }

    #[target_feature(enable = "avx2")]
    pub(super) fn node_forces<S: Dimension, K: SumKind, const CRACKS: bool>(s: &Simulation<S>, a: usize, has_ext: bool, has_body: bool) -> Option<NodeForce<S::Vector>> {
        s.node_forces::<K, CRACKS>(a, has_ext, has_body)
    }

    #[target_feature(enable = "avx2")]
    pub(super) fn node_momentum<S: Dimension, K: SumKind, const CRACKS: bool>(s: &Simulation<S>, a: usize) -> Option<[S::Vector; MAX_FIELDS]> {
        s.node_momentum::<K, CRACKS>(a)
    }

    #[target_feature(enable = "avx2")]
    pub(super) fn velocity_gradient<S: Dimension, K: SumKind, const CRACKS: bool>(s: &Simulation<S>, i: usize) -> Option<S::Tensor> {
        s.velocity_gradient::<K, CRACKS>(i)
    }

    #[target_feature(enable = "avx2")]
    pub(super) fn particle_increments<S: Dimension, K: SumKind, const CRACKS: bool>(s: &Simulation<S>, i: usize) -> Option<(S::Vector, S::Vector)> {
        s.particle_increments::<K, CRACKS>(i)
    }

    #[target_feature(enable = "avx2")]
    pub(super) fn weights_into<S: Space>(grid: &S::Grid, kind: ShapeKind, x: &S::Vector, lp: &S::Vector, node: &mut [u32], s: &mut [f64], g: &mut [S::Vector]) -> usize {
        use std::any::TypeId;
        if TypeId::of::<S>() == TypeId::of::<crate::dim::D3>() && kind == ShapeKind::Ugimp {
            // 3D uGIMP: the 1D weights of the three axes at once (gather3::weights_ugimp, the
            // same values as shape::weights_into_3d).
            // SAFETY: S is D3, so its grid, vectors and slices are Grid3 and Vector3 ones.
            unsafe {
                let grid = &*(grid as *const S::Grid as *const crate::grid::Grid3);
                let (x, lp) = (&*(x as *const S::Vector as *const crate::dim::Vector3), &*(lp as *const S::Vector as *const crate::dim::Vector3));
                let g = std::slice::from_raw_parts_mut(g.as_mut_ptr() as *mut crate::dim::Vector3, g.len());
                return crate::gather3::weights_ugimp(grid, x, lp, node.try_into().unwrap(), s.try_into().unwrap(), g.try_into().unwrap());
            }
        }
        S::weights_into(grid, kind, x, lp, node, s, g)
    }
}

/// The simulation as a 3D one whose crack-free gathers run the explicit AVX2 code of
/// [`crate::gather3`] (the caller has checked that the CPU has AVX2), or None (2D).
#[inline(always)]
fn fast3d<S: Dimension>(sim: &Simulation<S>) -> Option<&Simulation<crate::dim::D3>> {
    #[cfg(target_arch = "x86_64")]
    {
        crate::gather3::as_d3(sim)
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        None
    }
}

/// Smallest number of particles a parallel task takes (keeps rayon's overhead small).
pub(crate) const PARTICLE_CHUNK: usize = 256;
/// Smallest number of active nodes a parallel task takes.
const NODE_CHUNK: usize = 64;

/// Is the particle (with its uGIMP domain) inside the grid?
#[inline]
fn inside_grid<S: Space>(grid: &S::Grid, kind: ShapeKind, x: &S::Vector, lp: &S::Vector) -> bool {
    let margin = match kind {
        ShapeKind::Linear => S::Vector::zeros(),
        ShapeKind::Ugimp => *lp,
    };
    let (lo, hi) = (grid.origin(), grid.max_corner());
    (0..S::DIM).all(|c| x[c] - margin[c] >= lo[c] && x[c] + margin[c] <= hi[c])
}

/// Checked mode: (ΣS, ΣG) if the weights break the partition of unity, else None.
#[inline]
fn partition_of_unity_error<S: Space>(grid: &S::Grid, s: &[f64], g: &[S::Vector]) -> Option<(f64, Vec<f64>)> {
    let sum_s = crate::exact::sum(s);
    let gtol = PARTITION_TOL / grid.min_h();
    let gsum = |c: usize| crate::exact::sum_iter(g.iter().map(|g| g[c]));
    let bad = (sum_s - 1.0).abs() > PARTITION_TOL || (0..S::DIM).any(|c| gsum(c).abs() > gtol);
    bad.then(|| (sum_s, (0..S::DIM).map(gsum).collect()))
}

/// One active node's Task 1 sums, per field.
#[derive(Clone, Copy, Debug)]
pub struct NodeMass<V> {
    pub present: u8,
    pub mass: [f64; MAX_FIELDS],
    pub mom: [V; MAX_FIELDS],
    pub volume: f64,
}

impl<V: VectorOps> Default for NodeMass<V> {
    fn default() -> Self {
        NodeMass { present: 0, mass: [0.0; MAX_FIELDS], mom: [V::zeros(); MAX_FIELDS], volume: 0.0 }
    }
}

/// One active node's Task 3 sums, per field.
#[derive(Clone, Copy, Debug)]
pub struct NodeForce<V> {
    pub fint: [V; MAX_FIELDS],
    pub fext: [V; MAX_FIELDS],
}

impl<V: VectorOps> Default for NodeForce<V> {
    fn default() -> Self {
        NodeForce { fint: [V::zeros(); MAX_FIELDS], fext: [V::zeros(); MAX_FIELDS] }
    }
}

/// Per-step buffers of the parallel gathers (one entry per active node), kept across
/// steps so the time step does not allocate.
#[derive(Debug)]
pub struct Scratch<S: Space> {
    pub mass: Vec<NodeMass<S::Vector>>,
    pub force: Vec<NodeForce<S::Vector>>,
    pub momentum: Vec<[S::Vector; MAX_FIELDS]>,
    pub grad_v: Vec<S::Tensor>,
    pub increments: Vec<(S::Vector, S::Vector)>,
    /// 3D gathers ([`crate::gather3`]): per particle (m, m·v) for Tasks 1 and 6c, and the
    /// stress columns and −V for Task 3.
    pub mass_momentum: Vec<[f64; 4]>,
    pub stress_columns: Vec<[[f64; 4]; 4]>,
    /// CSR build: the particle of each entry of `pairs.items` (item / MAX_NODES).
    pub item_particle: Vec<u32>,
    /// CSR build: pairs per active node of each particle chunk, then the chunks' write cursors.
    pub chunk_counts: Vec<Vec<u32>>,
    /// CSR build: the nodes each particle chunk touched first.
    pub chunk_nodes: Vec<Vec<u32>>,
    /// CSR build: per grid node, touched this step (false again once the active list is built).
    pub marks: Vec<AtomicBool>,
    /// Per grid node, per node gather (mass, forces, momentum): the steps it still runs
    /// with three-level sums after its fast sums failed (see `hinted`).
    pub gather_hints: Vec<[AtomicU8; 3]>,
    /// CSR build: the pair slots, written by the chunks in parallel.
    pub slots: Vec<AtomicU32>,
    /// Particles with a load or a body force this step, ascending.
    pub forced: Vec<u32>,
    /// Task 3: per active node, whether a particle with an external force term touches it.
    pub loaded_nodes: Vec<bool>,
    /// Task 1 with cracks (2D): each crack's segment index, the crack each split pair
    /// crossed, and per particle whether any of its pairs is split.
    pub crack_index: Vec<crate::crack::geometry::SegmentIndex>,
    /// Task 1 with cracks (3D): each crack's triangle index.
    pub crack_index3: Vec<crate::crack::crossing3::TriangleIndex>,
    /// Task 1 with cracks (3D): each crack's nodes lying on its axis-plane triangles.
    pub crack_node_on3: Vec<crate::crack::three_d::NodeOnIndex>,
    /// Task 7 with cracks (3D): per grid node, its position in `touched3` (u32::MAX where
    /// no point of the crack being moved touches it), and the touched nodes.
    pub node_slot3: Vec<u32>,
    pub touched3: Vec<crate::crack::three_d::Touched3>,
    /// Task 7 with cracks (3D): the linear weights of each point of the crack being moved.
    pub weights3: Vec<crate::crack::three_d::PointWeights3>,
    /// Task 7 with cracks (2D): the crack particles of the crack being moved, as they were
    /// before the move.
    pub crack_points: Vec<crate::dim::Vector>,
    pub pair_crack: Vec<u16>,
    pub split: Vec<bool>,
    /// Task 1 with cracks (2D): the crack-tip zones of this step (`solver.tip_zone`).
    pub tip_zones: Vec<crate::crack::tip_zone::TipZone>,
}

/// Every buffer is refilled before it is read within a step, so a copy of a simulation
/// starts with empty ones (and the atomics need no copying).
impl<S: Space> Clone for Scratch<S> {
    fn clone(&self) -> Self {
        Scratch::default()
    }
}

impl<S: Space> Default for Scratch<S> {
    fn default() -> Self {
        Scratch {
            mass: Vec::new(),
            force: Vec::new(),
            momentum: Vec::new(),
            grad_v: Vec::new(),
            increments: Vec::new(),
            mass_momentum: Vec::new(),
            stress_columns: Vec::new(),
            item_particle: Vec::new(),
            chunk_counts: Vec::new(),
            chunk_nodes: Vec::new(),
            marks: Vec::new(),
            gather_hints: Vec::new(),
            slots: Vec::new(),
            forced: Vec::new(),
            loaded_nodes: Vec::new(),
            crack_index: Vec::new(),
            crack_index3: Vec::new(),
            crack_node_on3: Vec::new(),
            node_slot3: Vec::new(),
            touched3: Vec::new(),
            weights3: Vec::new(),
            crack_points: Vec::new(),
            pair_crack: Vec::new(),
            split: Vec::new(),
            tip_zones: Vec::new(),
        }
    }
}

/// Single stages of the step, for `benches/step.rs` (not a stable API: the state after
/// calling them alone is not that of a real step).
#[doc(hidden)]
impl<S: Dimension> Simulation<S> {
    /// Particle to grid: Task 0 (shape functions) and Task 1 (crack fields, CSR, gathers).
    pub fn bench_particle_to_grid(&mut self) -> Result<(), CheckError> {
        self.task0_shape_functions()?;
        self.task1_extrapolate()
    }

    /// Grid update: Tasks 2–4 (boundary conditions and contact, forces, momenta).
    pub fn bench_grid_update(&mut self) -> Result<(), CheckError> {
        self.task2_boundary_conditions()?;
        self.task3_forces();
        self.task4_update_momenta()
    }

    /// Grid to particle: Task 5 (particle update) and the stress update.
    pub fn bench_grid_to_particle(&mut self) {
        self.task5_update_particles();
        self.update_stresses(0.5 * self.options.dt);
    }
}

/// Crack stages of the 2D step, for `benches/step.rs`.
#[doc(hidden)]
impl Simulation {
    /// The line-crossing field assignment of Task 1 alone (cracks only).
    pub fn bench_crack_fields(&mut self) -> Result<(), CheckError> {
        self.assign_velocity_fields()
    }

    /// One contact pass over the nodes with two fields (cracks only).
    pub fn bench_contact(&mut self) -> Result<(), CheckError> {
        self.apply_contact_to_momenta()
    }
}
