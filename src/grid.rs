//! The background grid: a regular rectangular grid of nodes, and the nodal arrays of
//! each velocity field (Nairn 2003 §2.1: field 0 for particles on the node's side of
//! every crack, 1 for particles above a crack relative to the node, 2 for below).
//!
//! Node `i` sits at `origin + (ix·hx, iy·hy)` with `i = ix + iy·(nx+1)`. Coordinates are
//! computed the same way everywhere so that a grid symmetric about a grid line gives
//! mirrored node coordinates to the bit. A 3D grid ([`Grid3`]) adds `iz·hz` and
//! `i = ix + (nx+1)·(iy + (ny+1)·iz)`. The solver sees either through
//! [`GridGeometry`]; the nodal arrays ([`Nodes`]) are generic over the vector type.

use crate::dim::{GridGeometry, Vector, Vector3, VectorOps};

/// Geometry of a regular background grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// Lower-left corner.
    pub origin: Vector,
    /// Cell size (hx, hy).
    pub h: Vector,
    /// Number of cells in x and y.
    pub nx: usize,
    pub ny: usize,
}

impl Grid {
    pub fn num_nodes(&self) -> usize {
        (self.nx + 1) * (self.ny + 1)
    }

    #[inline]
    pub fn node_index(&self, ix: usize, iy: usize) -> usize {
        ix + iy * (self.nx + 1)
    }

    #[inline]
    pub fn node_ij(&self, i: usize) -> (usize, usize) {
        (i % (self.nx + 1), i / (self.nx + 1))
    }

    /// Position of node i.
    #[inline]
    pub fn node_pos(&self, i: usize) -> Vector {
        let (ix, iy) = self.node_ij(i);
        Vector::new(self.origin.x + ix as f64 * self.h.x, self.origin.y + iy as f64 * self.h.y)
    }

    /// Upper-right corner.
    pub fn max_corner(&self) -> Vector {
        Vector::new(self.origin.x + self.nx as f64 * self.h.x, self.origin.y + self.ny as f64 * self.h.y)
    }

    /// Area of one cell (the undeformed nodal volume of an interior node, eq. 10).
    pub fn cell_area(&self) -> f64 {
        self.h.x * self.h.y
    }

    /// Smallest cell dimension, for the CFL time step.
    pub fn min_h(&self) -> f64 {
        self.h.x.min(self.h.y)
    }
}

impl GridGeometry<Vector> for Grid {
    fn num_nodes(&self) -> usize {
        Grid::num_nodes(self)
    }
    #[inline]
    fn node_pos(&self, i: usize) -> Vector {
        Grid::node_pos(self, i)
    }
    fn node_coords(&self, i: usize) -> Vec<usize> {
        let (ix, iy) = self.node_ij(i);
        vec![ix, iy]
    }
    fn origin(&self) -> Vector {
        self.origin
    }
    fn max_corner(&self) -> Vector {
        Grid::max_corner(self)
    }
    fn min_h(&self) -> f64 {
        Grid::min_h(self)
    }
    fn cell_measure(&self) -> f64 {
        self.cell_area()
    }
}

/// Geometry of a regular 3D background grid: node `i = ix + (nx+1)·(iy + (ny+1)·iz)` at
/// `origin + (ix·hx, iy·hy, iz·hz)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid3 {
    /// Corner of least coordinates.
    pub origin: Vector3,
    /// Cell size (hx, hy, hz).
    pub h: Vector3,
    /// Number of cells in x, y and z.
    pub n: [usize; 3],
}

impl Grid3 {
    #[inline]
    pub fn node_index(&self, ix: usize, iy: usize, iz: usize) -> usize {
        ix + (self.n[0] + 1) * (iy + (self.n[1] + 1) * iz)
    }

    #[inline]
    pub fn node_ijk(&self, i: usize) -> [usize; 3] {
        let (nx1, ny1) = (self.n[0] + 1, self.n[1] + 1);
        [i % nx1, (i / nx1) % ny1, i / (nx1 * ny1)]
    }
}

impl GridGeometry<Vector3> for Grid3 {
    fn num_nodes(&self) -> usize {
        (self.n[0] + 1) * (self.n[1] + 1) * (self.n[2] + 1)
    }
    #[inline]
    fn node_pos(&self, i: usize) -> Vector3 {
        let [ix, iy, iz] = self.node_ijk(i);
        Vector3::new(self.origin.x + ix as f64 * self.h.x, self.origin.y + iy as f64 * self.h.y, self.origin.z + iz as f64 * self.h.z)
    }
    fn node_coords(&self, i: usize) -> Vec<usize> {
        self.node_ijk(i).to_vec()
    }
    fn origin(&self) -> Vector3 {
        self.origin
    }
    fn max_corner(&self) -> Vector3 {
        Vector3::from_fn(|c, _| self.origin[c] + self.n[c] as f64 * self.h[c])
    }
    fn min_h(&self) -> f64 {
        self.h.x.min(self.h.y).min(self.h.z)
    }
    fn cell_measure(&self) -> f64 {
        self.h.x * self.h.y * self.h.z
    }
}

/// Nodal arrays of one velocity field, over all nodes of the grid (flat, indexed by node).
#[derive(Clone, Debug, Default)]
pub struct FieldArrays<V = Vector> {
    /// Lumped mass m_{i,j} (eq. 26).
    pub mass: Vec<f64>,
    /// Momentum p_{i,j} (eqs. 26, 29, 31).
    pub mom: Vec<V>,
    /// Internal force (eq. 28).
    pub fint: Vec<V>,
    /// External force, particle loads and body forces (eq. 28).
    pub fext: Vec<V>,
    /// Total force including damping (eq. 28), possibly modified by boundary conditions
    /// and contact.
    pub ftot: Vec<V>,
    /// Velocity p/m, computed where needed for the particle updates.
    pub vel: Vec<V>,
    /// Acceleration ftot/m.
    pub acc: Vec<V>,
}

impl<V: VectorOps> FieldArrays<V> {
    pub fn new(n: usize) -> Self {
        let z = V::zeros();
        FieldArrays {
            mass: vec![0.0; n],
            mom: vec![z; n],
            fint: vec![z; n],
            fext: vec![z; n],
            ftot: vec![z; n],
            vel: vec![z; n],
            acc: vec![z; n],
        }
    }
}

/// Maximum number of velocity fields per node: 0, 1 (above), 2 (below).
pub const MAX_FIELDS: usize = 3;

/// All nodal data of one step.
#[derive(Clone, Debug)]
pub struct Nodes<V = Vector> {
    /// One entry per velocity field in use by the scene: 1 without cracks, 3 with.
    pub fields: Vec<FieldArrays<V>>,
    /// Bit set per node of which fields are present (ϕ_{i,j} of eq. 32).
    pub present: Vec<u8>,
    /// Total nodal volume (eq. 27), only with cracks and only at the nodes a crack splits
    /// this step (NaN at the others): contact reads it only at nodes with two fields.
    pub volume: Vec<f64>,
    /// Average crack normal per node (from above to below), only with cracks.
    pub normal: Vec<V>,
    /// Which crack split each node (u16::MAX: none), only with cracks.
    pub crack: Vec<u16>,
    /// Nodes touched by at least one particle this step, ascending.
    pub active: Vec<u32>,
}

/// Empty nodal data (a placeholder while the arrays are moved out, e.g. by contact).
impl<V> Default for Nodes<V> {
    fn default() -> Self {
        Nodes { fields: Vec::new(), present: Vec::new(), volume: Vec::new(), normal: Vec::new(), crack: Vec::new(), active: Vec::new() }
    }
}

impl<V: VectorOps> Nodes<V> {
    pub fn new(num_nodes: usize, with_cracks: bool) -> Self {
        let nf = if with_cracks { MAX_FIELDS } else { 1 };
        Nodes {
            fields: (0..nf).map(|_| FieldArrays::new(num_nodes)).collect(),
            present: vec![0; num_nodes],
            volume: if with_cracks { vec![0.0; num_nodes] } else { Vec::new() },
            normal: if with_cracks { vec![V::zeros(); num_nodes] } else { Vec::new() },
            crack: if with_cracks { vec![u16::MAX; num_nodes] } else { Vec::new() },
            active: Vec::with_capacity(num_nodes),
        }
    }

    /// Every (field, node) in use this step: active nodes in ascending order, fields in order.
    pub fn present_fields(&self) -> impl Iterator<Item = (usize, usize)> + Clone + '_ {
        self.active.iter().flat_map(move |&node| {
            let i = node as usize;
            (0..self.fields.len()).filter(move |&f| self.present[i] & (1 << f) != 0).map(move |f| (f, i))
        })
    }

    #[inline]
    pub fn has_field(&self, node: usize, field: usize) -> bool {
        self.present[node] & (1u8 << field) != 0
    }
}
