//! A 3D scene solved statically: the mapping of a [`Scene3`] onto the hex8 FEA, by the
//! rules of the 2D mapping ([`super::scene`], which explains them in full):
//!
//! * **Elements**: a grid cell holding at least one particle of the MPM discretisation
//!   ([`Scene3::build`]) becomes a hex8 element of the body owning most of its particles
//!   ([`super::scene::cell_owners`]).
//! * **Supports**: `vx = 0` / `vy = 0` / `vz = 0` on grid nodes become u = 0 on the mesh
//!   nodes there; a non-zero fixed velocity is an error. Each connected piece (elements
//!   joined through shared faces; a shared edge or corner is a hinge) must be held against
//!   the six rigid motions of space; if not, the error names the free translation or the
//!   axis of the free rotation. A piece with no support at all whose loads are in
//!   equilibrium gets the minimal support (one node fixed, one fixed across the line to
//!   it, a third fixed against rotation about that line), carrying no reaction, and its
//!   displacements are reported with the least-squares rigid motion removed.
//! * **Loads**: each loaded particle's force (its share of a `[[loads]]` force plus
//!   m_p b) is lumped onto the eight nodes of its cell with the trilinear shape
//!   functions, f_a += N_a(x_p) f_p — the MPM's linear weights S_ip at the initial
//!   positions, and the uGIMP ones too while the particle domains tile the cells; force
//!   and moment of every particle are preserved.
//! * Damping, time step, scheme, shape functions, initial velocities and load ramps are
//!   ignored (reported as notes).

use super::crack3::{j_front, FrontJ, MeshedCrack3};
use super::hex8;
use super::mesh3::{cell_index, GridMesh3};
use super::scene::{cell_notes, cell_owners, connected_pieces, free_rigid_mode, grid_axis, motion_notes, particle_forces, EndOfRun, Lattice, GAUSS3};
use crate::motion::{ComponentFn, TimeFn};
use super::solve::BoundaryConditions;
use super::solve3::{assemble_3d, nodal_vectors, postprocess_3d, Model3, Solution3};
use super::{FeaError, Result};
use crate::dim::{GridGeometry, Vector3};
use crate::material::LinearElastic;
use crate::scene3d::Scene3;
use std::time::Instant;

/// Relative tolerance of the equilibrium check of an unsupported piece (as in 2D).
const EQUILIBRIUM_TOL: f64 = 1e-9;

/// The six faces of a hex8 (corner indices).
const FACES: [[usize; 4]; 6] = [[0, 1, 2, 3], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];

/// A support added to an unsupported piece (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AutoSupport3 {
    pub node: usize,
    /// 0 = x, 1 = y, 2 = z.
    pub component: usize,
}

/// A 3D scene mapped onto the hex8 FEA.
#[derive(Clone, Debug)]
pub struct SceneFea3 {
    pub grid_mesh: GridMesh3,
    /// Meshed cracks (split nodes, front nodes).
    pub cracks: Vec<MeshedCrack3>,
    /// Material of every scene body; element `e` uses `materials[element_body[e]]`.
    pub materials: Vec<LinearElastic>,
    pub element_body: Vec<usize>,
    pub bcs: BoundaryConditions,
    pub auto_supports: Vec<AutoSupport3>,
    /// Mesh nodes of every piece that got automatic supports.
    pub free_pieces: Vec<Vec<usize>>,
    pub n_particles: usize,
    pub n_loaded_particles: usize,
    /// Sum of all nodal loads.
    pub load_resultant: Vector3,
    pub partial_cells: usize,
    pub mixed_cells: usize,
    /// What the static FEA ignored or approximated, one sentence each.
    pub notes: Vec<String>,
}

/// A solved 3D scene.
#[derive(Clone, Debug)]
pub struct FeaAnalysis3 {
    pub solution: Solution3,
    /// Strain energy ½ uᵀKu (½ fᵀu plus the reactions' work at non-zero prescribed displacements).
    pub strain_energy: f64,
    /// Largest |reaction| at the automatic supports (0 in exact arithmetic).
    pub max_auto_reaction: f64,
    pub equations: usize,
    /// Wall times in seconds: assembly, factorisation + solve, stress recovery.
    pub assembly_seconds: f64,
    pub solve_seconds: f64,
    pub stress_seconds: f64,
    /// Non-zeros of the lower triangle of K_ff.
    pub matrix_nonzeros: usize,
    /// J and K at every front node of every crack.
    pub front: Vec<FrontResult>,
    pub j_seconds: f64,
}

/// J and K at one front node for the domains that fit (1 to [`super::scene::MAX_J_CELLS`] cells).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct FrontResult {
    pub crack: usize,
    pub node: usize,
    pub grid_node: [usize; 3],
    pub position: [f64; 3],
    /// e1 (into the material), if the front runs along a grid axis here.
    pub direction: Option<[f64; 3]>,
    pub domains: Vec<FrontJ>,
    /// Why the larger domains (or all) were not evaluated.
    pub skipped: Option<String>,
}

fn scene_err(field: impl Into<String>, message: impl Into<String>) -> FeaError {
    FeaError::SceneField { field: field.into(), message: message.into() }
}

fn axis_name(v: &Vector3) -> String {
    let n = v.norm();
    for (c, name) in ["x", "y", "z"].iter().enumerate() {
        if (0..3).all(|d| d == c || v[d].abs() < 1e-6 * n) {
            return (*name).to_string();
        }
    }
    format!("({:.4}, {:.4}, {:.4})", v.x / n, v.y / n, v.z / n)
}

/// Row of prescribed DOF (x, component c) in the rigid modes (translations x, y, z,
/// rotations about x, y, z through `centre`, scaled by `size`): component c of t + ω × d.
fn rigid_row(x: &Vector3, c: usize, centre: Vector3, size: f64) -> [f64; 6] {
    let d = (x - centre) / size;
    let mut row = [0.0; 6];
    row[c] = 1.0;
    let rot = [Vector3::x(), Vector3::y(), Vector3::z()].map(|w| w.cross(&d)[c]);
    row[3..].copy_from_slice(&rot);
    row
}

/// The rigid motion left free by the prescribed DOFs `fixed` of a piece, in words, or
/// `None` if the piece is held ([`free_rigid_mode`]).
fn free_motion(fixed: &[(usize, usize)], x: &[Vector3], centre: Vector3, size: f64) -> Option<String> {
    let v = free_rigid_mode(fixed.iter().map(|&(a, c)| rigid_row(&x[a], c, centre, size)))?;
    let t = Vector3::new(v[0], v[1], v[2]);
    let omega = Vector3::new(v[3], v[4], v[5]) / size;
    Some(if omega.norm() * size < 1e-6 * t.norm() {
        format!("translation in {}", axis_name(&t))
    } else {
        // Velocity t + ω × (x − centre) is along ω on the axis x = centre + ω × t / |ω|².
        let p = (centre + omega.cross(&t) / omega.norm_squared()).map(|v| if v.abs() < 1e-9 * size { 0.0 } else { v });
        format!("rotation about the axis along {} through ({:.6}, {:.6}, {:.6})", axis_name(&omega), p.x, p.y, p.z)
    })
}

/// Every rigid mode the rows leave free (an orthonormal basis of the null space of their
/// Gram matrix, eigenvalues below 1e-9 of the largest; all six for no rows).
fn free_modes(rows: &[[f64; 6]]) -> Vec<nalgebra::Vector6<f64>> {
    let gram = rows.iter().fold(nalgebra::Matrix6::<f64>::zeros(), |g, r| {
        let r = nalgebra::Vector6::from_column_slice(r);
        g + r * r.transpose()
    });
    let eig = gram.symmetric_eigen();
    let max = eig.eigenvalues.iter().fold(0.0f64, |m, &v| m.max(v));
    (0..6).filter(|&k| max == 0.0 || eig.eigenvalues[k] <= 1e-9 * max).map(|k| eig.eigenvectors.column(k).into_owned()).collect()
}

impl SceneFea3 {
    /// Map a 3D scene onto the FEA (see the module doc). Errors name the scene field.
    pub fn from_scene(scene: &Scene3) -> Result<SceneFea3> {
        SceneFea3::with_cracks(scene, &[])
    }

    /// [`SceneFea3::from_scene`] with meshed planar cracks, each a triangulated surface
    /// (vertices, triangles; the layout of the MPM's crack surfaces), cut by
    /// [`GridMesh3::cut_planar_crack`] before supports and loads are mapped.
    pub fn with_cracks(scene: &Scene3, cracks: &[(Vec<Vector3>, Vec<[u32; 3]>)]) -> Result<SceneFea3> {
        super::scene::refuse_body_lattice(scene.solver.lattice)?;
        let sim = scene.build()?;
        let grid = sim.grid.clone();
        let p = &sim.particles;
        let cell_of = |x: &Vector3| -> [usize; 3] {
            std::array::from_fn(|c| (((x[c] - grid.origin[c]) / grid.h[c]).floor().max(0.0) as usize).min(grid.n[c] - 1))
        };
        let n = scene.solver.particles_per_cell;
        let (cell_body, partial_cells, mixed_cells) = cell_owners(
            grid.n.iter().product(),
            scene.bodies.len(),
            n * n * n,
            (0..p.len()).map(|k| (cell_index(&grid, cell_of(&p.x[k])), p.body[k] as usize)),
        );
        let mut grid_mesh = GridMesh3::from_grid(grid.clone(), |c| cell_body[cell_index(&grid, c)] != usize::MAX)?;
        // The scene's own [[cracks]] (their triangulated surfaces, as the MPM meshes them) first.
        let scene_cracks: Vec<(Vec<Vector3>, Vec<[u32; 3]>)> =
            sim.cracks.iter().map(|c| (c.surface.vertices.clone(), c.surface.triangles.clone())).collect();
        let meshed_cracks = scene_cracks
            .iter()
            .chain(cracks)
            .enumerate()
            .map(|(c, (v, t))| grid_mesh.cut_planar_crack(c, v, t))
            .collect::<Result<Vec<_>>>()?;
        let element_body: Vec<usize> =
            grid_mesh.element_cell.iter().map(|&c| cell_body[cell_index(&grid, c)]).collect();
        let materials: Vec<LinearElastic> = scene
            .bodies
            .iter()
            .map(|b| sim.materials[scene.materials.iter().position(|m| m.name == b.material).unwrap_or(0)])
            .collect();
        let mesh = &grid_mesh.mesh;
        let mut bcs = BoundaryConditions::for_nodes(mesh.n_nodes(), 3);
        let mut notes = vec!["static, linear-elastic, small-strain analysis: solver.damping, solver.end_time, the \
                              time step, the scheme and the shape functions are not used"
            .to_string()];

        // Supports on the mesh node at every constrained grid node: the displacement the
        // MPM gives the grid node by the end of the run (0 for a fixed support).
        let end = EndOfRun::of(&sim, scene.solver.end_time);
        let prescribed = end.node_displacements(&sim);
        for &g in &sim.bcs.nodes {
            let mask = sim.bcs.mask[g as usize];
            for a in grid_mesh.nodes_at(g as usize) {
                for c in (0..3).filter(|c| mask & (1 << c) != 0) {
                    bcs.prescribe(a, c, prescribed(g as usize, c))?;
                }
            }
        }
        for (k, b) in scene.boundary.iter().enumerate() {
            let tol = b.nodes.tolerance(grid.min_h());
            if !mesh.nodes.iter().any(|x| b.nodes.contains(x, tol)) {
                notes.push(format!(
                    "boundary[{k}] selects only grid nodes outside the material: it has no effect on the FEA"
                ));
            }
        }

        // Loads and body forces, particle by particle.
        let mut n_loaded_particles = 0;
        let mut load_resultant = Vector3::zeros();
        for (k, f) in particle_forces(&sim, end.time) {
            n_loaded_particles += 1;
            let c = cell_of(&p.x[k]);
            let Some(e) = grid_mesh.cell_element[cell_index(&grid, c)] else {
                return Err(FeaError::InvalidInput(format!("loaded particle at {:?} is in no element", p.x[k])));
            };
            let xi: [f64; 3] = std::array::from_fn(|d| {
                let centre = grid.origin[d] + (c[d] as f64 + 0.5) * grid.h[d];
                2.0 * (p.x[k][d] - centre) / grid.h[d]
            });
            for (a, &node) in hex8::shape(xi).iter().zip(&mesh.elements[e]) {
                bcs.add_load(node, (f * *a).as_slice())?;
            }
            load_resultant += f;
        }
        // Tractions as consistent nodal loads over each particle's face (3 × 3 Gauss points).
        let lattice = Lattice::new(p, &grid.origin);
        for (li, l) in scene.loads.iter().enumerate() {
            let Some(traction) = &l.traction else { continue };
            let field = format!("loads[{li}]");
            let comps: Vec<ComponentFn> = traction.iter().enumerate().map(|(c, t)| ComponentFn::new(&format!("{field}.traction[{c}]"), t, 3)).collect::<std::result::Result<_, _>>().map_err(|(f, m)| scene_err(f, m))?;
            let time = TimeFn::new(&format!("{field}.time"), l.time.as_ref()).map_err(|(f, m)| scene_err(f, m))?;
            let normal = scene.load_normal(li)?.unwrap_or_default();
            let axis = grid_axis(&normal).ok_or_else(|| scene_err(format!("{field}.normal"), format!("{normal:?}: the FEA applies tractions on faces normal to a grid axis only")))?;
            let (k1, k2) = ((axis + 1) % 3, (axis + 2) % 3);
            for k in (0..p.len()).filter(|&k| p.load[k] == li as u16) {
                let (x0, lp) = (p.x0[k], p.lp[k]);
                let side = lattice.exposed_side::<crate::dim::D3>(&x0, &lp, axis);
                let c = cell_of(&x0);
                let Some(e) = grid_mesh.cell_element[cell_index(&grid, c)] else {
                    return Err(FeaError::InvalidInput(format!("loaded particle at {x0:?} is in no element")));
                };
                for (s1, w1) in GAUSS3 {
                    for (s2, w2) in GAUSS3 {
                        let mut xf = x0;
                        xf[axis] += side * lp[axis];
                        xf[k1] += s1 * lp[k1];
                        xf[k2] += s2 * lp[k2];
                        let t = crate::motion::point(&[xf.x, xf.y, xf.z], end.time);
                        let tr = Vector3::new(comps[0].at(&t), comps[1].at(&t), comps[2].at(&t)) * (time.at(end.time) * w1 * w2 * lp[k1] * lp[k2]);
                        let xi: [f64; 3] = std::array::from_fn(|d| {
                            let centre = grid.origin[d] + (c[d] as f64 + 0.5) * grid.h[d];
                            2.0 * (xf[d] - centre) / grid.h[d]
                        });
                        for (a, &node) in hex8::shape(xi).iter().zip(&mesh.elements[e]) {
                            bcs.add_load(node, (tr * *a).as_slice())?;
                        }
                        load_resultant += tr;
                    }
                }
                n_loaded_particles += 1;
            }
        }

        // Pieces: elements joined through shared faces.
        let pieces = connected_pieces(&mesh.elements, &FACES);
        let (mut auto_supports, mut free_pieces) = (Vec::new(), Vec::new());
        let forces = bcs.forces().to_vec();
        let x = |a: usize| mesh.nodes[a];
        let f = |a: usize| Vector3::new(forces[3 * a], forces[3 * a + 1], forces[3 * a + 2]);
        for (&first_element, nodes) in &pieces {
            let nodes: Vec<usize> = nodes.iter().copied().collect();
            let body = element_body[first_element];
            let centre = nodes.iter().fold(Vector3::zeros(), |s, &a| s + x(a)) / nodes.len() as f64;
            let size = nodes.iter().map(|&a| (x(a) - centre).norm()).fold(0.0, f64::max).max(grid.min_h());
            let fixed_dofs = |bcs: &BoundaryConditions| -> Vec<(usize, usize)> {
                nodes.iter().flat_map(|&a| (0..3).map(move |c| (a, c))).filter(|&(a, c)| bcs.prescribed()[3 * a + c].is_some()).collect()
            };
            let fixed = fixed_dofs(&bcs);
            let here = format!("the piece of bodies[{body}] around ({:.6}, {:.6}, {:.6})", centre.x, centre.y, centre.z);
            if !fixed.is_empty() {
                let Some(motion) = free_motion(&fixed, &mesh.nodes, centre, size) else { continue };
                // Supports that leave rigid motions free: a static solution exists if the loads
                // do no work on any of them (then it is unique up to them), and the FEA adds
                // supports that stop exactly those motions (zero reactions); otherwise an error.
                let mut rows: Vec<[f64; 6]> = fixed.iter().map(|&(a, c)| rigid_row(&x(a), c, centre, size)).collect();
                let magnitude: f64 = nodes.iter().map(|&a| f(a).norm()).sum();
                let work = |v: &nalgebra::Vector6<f64>| -> f64 {
                    nodes.iter().map(|&a| (0..3).map(|c| f(a)[c] * nalgebra::Vector6::from_column_slice(&rigid_row(&x(a), c, centre, size)).dot(v)).sum::<f64>()).sum()
                };
                let mut modes = free_modes(&rows);
                let n_free = modes.len();
                if modes.iter().any(|v| work(v).abs() > EQUILIBRIUM_TOL * magnitude) {
                    return Err(scene_err(
                        "boundary",
                        format!(
                            "{here} is not held against rigid motion: its supports (vx = 0 / vy = 0 / vz = 0 on {} node \
                             component(s)) leave a rigid {motion} free and its loads do work on it, so the static problem \
                             has no solution; add [[boundary]] conditions that stop it",
                            fixed.len()
                        ),
                    ));
                }
                // Candidates farthest from the centre first (well-conditioned supports), then node order.
                let mut candidates: Vec<usize> = nodes.clone();
                candidates.sort_by(|&u, &v| (x(v) - centre).norm().total_cmp(&(x(u) - centre).norm()).then(u.cmp(&v)));
                let mut added = 0;
                'fill: for &a in &candidates {
                    for c in 0..3 {
                        if bcs.prescribed()[3 * a + c].is_some() {
                            continue;
                        }
                        let r = nalgebra::Vector6::from_column_slice(&rigid_row(&x(a), c, centre, size));
                        if modes.iter().map(|v| r.dot(v).powi(2)).sum::<f64>().sqrt() > 1e-3 * r.norm() {
                            bcs.prescribe(a, c, 0.0)?;
                            auto_supports.push(AutoSupport3 { node: a, component: c });
                            rows.push(rigid_row(&x(a), c, centre, size));
                            modes = free_modes(&rows);
                            added += 1;
                            if modes.is_empty() {
                                break 'fill;
                            }
                        }
                    }
                }
                notes.push(format!(
                    "{here}: its [[boundary]] supports leave {n_free} rigid motion(s) free (one is a {motion}), on which its \
                     loads do no work; the FEA stops them with {added} added support component(s) (zero reactions, stresses \
                     unaffected; displacements relative to those supports)"
                ));
                continue;
            }
            let magnitude: f64 = nodes.iter().map(|&a| f(a).norm()).sum();
            let net = nodes.iter().fold(Vector3::zeros(), |s, &a| s + f(a));
            let moment = nodes.iter().fold(Vector3::zeros(), |s, &a| s + (x(a) - centre).cross(&f(a)));
            if net.norm() > EQUILIBRIUM_TOL * magnitude || moment.norm() > EQUILIBRIUM_TOL * magnitude * size {
                return Err(scene_err(
                    "boundary",
                    format!(
                        "{here} has no support and its loads are not in equilibrium (net force ({:e}, {:e}, {:e}), net \
                         moment ({:e}, {:e}, {:e}) about its centre): a static solution does not exist; add [[boundary]] \
                         conditions (vx = 0 / vy = 0 / vz = 0) on it",
                        net.x, net.y, net.z, moment.x, moment.y, moment.z
                    ),
                ));
            }
            // Minimal support: a fixed; b (farthest from a) fixed across a–b; c (farthest
            // from the line a–b) fixed along the normal of the plane a, b, c.
            let a = nodes[0];
            let farthest = |dist: &dyn Fn(usize) -> f64| {
                *nodes.iter().max_by(|&&u, &&v| dist(u).total_cmp(&dist(v)).then(v.cmp(&u))).unwrap_or(&a)
            };
            let b = farthest(&|u| (x(u) - x(a)).norm());
            let d = x(b) - x(a);
            let c = farthest(&|u| (x(u) - x(a)).cross(&d).norm());
            let normal = d.cross(&(x(c) - x(a)));
            let along = |v: Vector3| (0..3).max_by(|&i, &j| v[i].abs().total_cmp(&v[j].abs())).unwrap_or(0);
            let kd = along(d);
            let added: Vec<(usize, usize)> =
                [(a, 0), (a, 1), (a, 2)].into_iter().chain((0..3).filter(|&k| k != kd).map(|k| (b, k))).chain([(c, along(normal))]).collect();
            for &(node, component) in &added {
                bcs.prescribe(node, component, 0.0)?;
                auto_supports.push(AutoSupport3 { node, component });
            }
            if let Some(motion) = free_motion(&fixed_dofs(&bcs), &mesh.nodes, centre, size) {
                return Err(scene_err("boundary", format!("{here} has no support, and no minimal support holds it (a rigid {motion} stays free); add [[boundary]] conditions on it")));
            }
            free_pieces.push(nodes.clone());
            notes.push(format!(
                "{here} has no [[boundary]] support; its loads are in equilibrium, so the FEA removes its rigid-body \
                 modes by fixing nodes {a}, {b} and {c} in {} component(s) (zero reactions, stresses unaffected); its \
                 displacements are reported with the least-squares rigid motion of its nodes removed",
                added.len()
            ));
        }

        if !sim.cracks.is_empty() {
            notes.push("crack contact is not modelled: the FEA crack faces are traction-free and may overlap (check the opening)".into());
        }
        motion_notes(
            &mut notes,
            scene.bodies.iter().map(|b| b.velocity != [0.0; 3] || b.velocity_sine.is_some()),
            scene.loads.iter().map(|l| l.ramp),
        );
        cell_notes(&mut notes, partial_cells, n * n * n, mixed_cells);
        Ok(SceneFea3 {
            grid_mesh,
            cracks: meshed_cracks,
            materials,
            element_body,
            bcs,
            auto_supports,
            free_pieces,
            n_particles: p.len(),
            n_loaded_particles,
            load_resultant,
            partial_cells,
            mixed_cells,
            notes,
        })
    }

    /// The model: element groups = scene bodies.
    pub fn model(&self) -> Result<Model3<'_>> {
        Model3::with_groups(&self.grid_mesh.mesh, self.materials.clone(), self.element_body.clone())
    }

    /// Assemble, factorise, solve, remove the rigid motion of unsupported pieces and recover stresses.
    pub fn analyse(&self) -> Result<FeaAnalysis3> {
        let model = self.model()?;
        let t0 = Instant::now();
        let system = assemble_3d(&model, &self.bcs)?;
        let t1 = Instant::now();
        let mut displacement = nodal_vectors(&system.factorize_and_solve()?);
        let t2 = Instant::now();
        let nodes = &self.grid_mesh.mesh.nodes;
        for piece in &self.free_pieces {
            // Least-squares rigid motion ū + ω × (x − x̄) (equal node weights): ū is the mean,
            // ω solves (Σ |r|² I − r rᵀ) ω = Σ r × (u − ū). Strain-free in the hex8, so
            // stresses and reactions do not change.
            let n = piece.len() as f64;
            let xm = piece.iter().fold(Vector3::zeros(), |s, &a| s + nodes[a]) / n;
            let um = piece.iter().fold(Vector3::zeros(), |s, &a| s + displacement[a]) / n;
            let (mut inertia, mut rhs) = (nalgebra::Matrix3::zeros(), Vector3::zeros());
            for &a in piece {
                let r = nodes[a] - xm;
                inertia += nalgebra::Matrix3::identity() * r.norm_squared() - r * r.transpose();
                rhs += r.cross(&(displacement[a] - um));
            }
            let omega = inertia.try_inverse().map(|i| i * rhs).unwrap_or_else(Vector3::zeros);
            for &a in piece {
                displacement[a] -= um + omega.cross(&(nodes[a] - xm));
            }
        }
        let solution = postprocess_3d(&model, &self.bcs, displacement);
        let f = self.bcs.forces();
        // ½ uᵀ f_int (f_int = f_ext + reaction; reactions work only where u ≠ 0 is prescribed).
        let pre = self.bcs.prescribed();
        let strain_energy = 0.5
            * (solution
                .displacement
                .iter()
                .enumerate()
                .map(|(a, u)| u.x * f[3 * a] + u.y * f[3 * a + 1] + u.z * f[3 * a + 2])
                .sum::<f64>()
                + (0..pre.len()).filter(|&d| pre[d].is_some_and(|v| v != 0.0)).map(|d| pre[d].unwrap_or(0.0) * solution.reaction[d / 3][d % 3]).sum::<f64>());
        let max_auto_reaction =
            self.auto_supports.iter().map(|s| solution.reaction[s.node][s.component].abs()).fold(0.0, f64::max);
        let t3 = Instant::now();
        let mut front = Vec::new();
        for (c, crack) in self.cracks.iter().enumerate() {
            for f in &crack.front {
                let (mut domains, mut skipped) = (Vec::new(), None);
                for cells in 1..=super::scene::MAX_J_CELLS {
                    match j_front(&self.grid_mesh, &model, &solution, crack, f, cells) {
                        Ok(r) => domains.push(r),
                        Err(e @ FeaError::BadTip { .. }) => {
                            skipped = Some(format!("domains of {cells} to {} cells not evaluated: {e}", super::scene::MAX_J_CELLS));
                            break;
                        }
                        Err(e) => return Err(e),
                    }
                }
                front.push(FrontResult {
                    crack: c,
                    node: f.node,
                    grid_node: f.grid_node,
                    position: f.position.into(),
                    direction: f.direction.map(Into::into),
                    domains,
                    skipped,
                });
            }
        }
        Ok(FeaAnalysis3 {
            front,
            j_seconds: t3.elapsed().as_secs_f64(),
            solution,
            strain_energy,
            max_auto_reaction,
            equations: system.n_equations(),
            assembly_seconds: (t1 - t0).as_secs_f64(),
            solve_seconds: (t2 - t1).as_secs_f64(),
            stress_seconds: t2.elapsed().as_secs_f64(),
            matrix_nonzeros: system.k.compute_nnz(),
        })
    }
}
