//! Meshes: flat node and element arrays, and the structured mesh taken from the
//! MPM background grid ("the same grid of rectangular 4-noded elements",
//! Nairn 2003 §3.1).

use super::{FeaError, Result};
use crate::dim::Vector;

/// An unstructured mesh of 4-noded quadrilaterals.
///
/// Node `a` has position `nodes[a]` and DOFs `2a` (x) and `2a + 1` (y).
/// Element nodes are listed counter-clockwise (positive Jacobian, see
/// [`super::element`]); a general, distorted convex quadrilateral is allowed.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    pub nodes: Vec<Vector>,
    pub elements: Vec<[usize; 4]>,
}

impl Mesh {
    /// Checks indices and coordinates. The orientation/convexity check needs the
    /// Jacobian and is done when the model is built ([`super::solve::Model::new`]).
    pub fn new(nodes: Vec<Vector>, elements: Vec<[usize; 4]>) -> Result<Mesh> {
        if let Some(a) = nodes.iter().position(|x| !(x.x.is_finite() && x.y.is_finite())) {
            return Err(FeaError::InvalidInput(format!("node {a} has a non-finite coordinate")));
        }
        let n_nodes = nodes.len();
        for (e, conn) in elements.iter().enumerate() {
            for &node in conn {
                if node >= n_nodes {
                    return Err(FeaError::ElementNodeOutOfRange { element: e, node, n_nodes });
                }
            }
            for k in 0..4 {
                for l in k + 1..4 {
                    if conn[k] == conn[l] {
                        return Err(FeaError::InvalidInput(format!("element {e} uses node {} twice", conn[k])));
                    }
                }
            }
        }
        Ok(Mesh { nodes, elements })
    }

    pub fn n_nodes(&self) -> usize {
        self.nodes.len()
    }

    pub fn n_dofs(&self) -> usize {
        2 * self.nodes.len()
    }

    /// The four node positions of element `e`.
    pub fn element_coords(&self, e: usize) -> [Vector; 4] {
        self.elements[e].map(|a| self.nodes[a])
    }

    pub(crate) fn check_node(&self, node: usize) -> Result<()> {
        if node < self.nodes.len() {
            Ok(())
        } else {
            Err(FeaError::NodeOutOfRange { node, n_nodes: self.nodes.len() })
        }
    }
}

/// A regular background grid: `nx × ny` cells of size `h.x × h.y`, lower-left
/// corner at `origin`. Cell (i, j) spans [x0 + i hx, x0 + (i+1) hx] × [y0 + j hy, y0 + (j+1) hy];
/// grid node (i, j) is at (x0 + i hx, y0 + j hy), 0 ≤ i ≤ nx, 0 ≤ j ≤ ny.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    pub origin: Vector,
    pub h: Vector,
    pub nx: usize,
    pub ny: usize,
}

impl Grid {
    pub fn new(origin: Vector, h: Vector, nx: usize, ny: usize) -> Result<Grid> {
        if !(origin.x.is_finite() && origin.y.is_finite()) {
            return Err(FeaError::InvalidGrid(format!("origin ({}, {}) is not finite", origin.x, origin.y)));
        }
        if !(h.x > 0.0 && h.y > 0.0 && h.x.is_finite() && h.y.is_finite()) {
            return Err(FeaError::InvalidGrid(format!("cell size ({}, {}) must be positive and finite", h.x, h.y)));
        }
        if nx == 0 || ny == 0 {
            return Err(FeaError::InvalidGrid(format!("{nx} × {ny} cells: need at least one cell each way")));
        }
        Ok(Grid { origin, h, nx, ny })
    }

    /// Position of grid node (i, j).
    pub fn node_position(&self, i: usize, j: usize) -> Vector {
        Vector::new(self.origin.x + i as f64 * self.h.x, self.origin.y + j as f64 * self.h.y)
    }

    /// Flat index of grid node (i, j).
    pub fn node_index(&self, i: usize, j: usize) -> usize {
        i + j * (self.nx + 1)
    }

    /// Flat index of cell (i, j).
    pub fn cell_index(&self, i: usize, j: usize) -> usize {
        i + j * self.nx
    }

    /// Centre of cell (i, j).
    pub fn cell_center(&self, i: usize, j: usize) -> Vector {
        self.node_position(i, j) + 0.5 * self.h
    }

    /// The grid node at `x`, if `x` is within `tol` (relative to the cell size) of one.
    pub fn snap_to_node(&self, x: Vector, tol: f64) -> Option<(usize, usize)> {
        let si = (x.x - self.origin.x) / self.h.x;
        let sj = (x.y - self.origin.y) / self.h.y;
        let (ri, rj) = (si.round(), sj.round());
        let on = (si - ri).abs() <= tol && (sj - rj).abs() <= tol;
        let inside = ri >= 0.0 && rj >= 0.0 && ri <= self.nx as f64 && rj <= self.ny as f64;
        (on && inside).then_some((ri as usize, rj as usize))
    }
}

/// The structured Q4 mesh of the material cells of a [`Grid`].
///
/// Element `e` is grid cell `element_cell[e]`; its nodes are the cell corners
/// (i, j), (i+1, j), (i+1, j+1), (i, j+1) — counter-clockwise. Only grid nodes
/// touched by a material cell become mesh nodes. After cracks are cut
/// ([`GridMesh::cut_cracks`]) a grid node can own several mesh nodes (one per crack face).
#[derive(Clone, Debug)]
pub struct GridMesh {
    pub grid: Grid,
    pub mesh: Mesh,
    /// Grid cell (i, j) of every element.
    pub element_cell: Vec<[usize; 2]>,
    /// Element of every grid cell (flat cell index), `None` for an empty cell.
    pub cell_element: Vec<Option<usize>>,
    /// Grid node (i, j) of every mesh node (crack-face copies share it).
    pub node_grid: Vec<[usize; 2]>,
}

impl GridMesh {
    /// Mesh the cells for which `holds_material(i, j, cell_centre)` is true.
    pub fn from_grid(grid: Grid, mut holds_material: impl FnMut(usize, usize, Vector) -> bool) -> Result<GridMesh> {
        let n_cells = grid.nx * grid.ny;
        let mut cell_element = vec![None; n_cells];
        let mut element_cell = Vec::new();
        for j in 0..grid.ny {
            for i in 0..grid.nx {
                if holds_material(i, j, grid.cell_center(i, j)) {
                    cell_element[grid.cell_index(i, j)] = Some(element_cell.len());
                    element_cell.push([i, j]);
                }
            }
        }
        if element_cell.is_empty() {
            return Err(FeaError::InvalidGrid("no cell holds material: the mesh would be empty".into()));
        }
        // Number the used grid nodes in grid order (row by row).
        let mut used = vec![false; (grid.nx + 1) * (grid.ny + 1)];
        for &[i, j] in &element_cell {
            for (a, b) in [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)] {
                used[grid.node_index(a, b)] = true;
            }
        }
        let mut mesh_node = vec![usize::MAX; used.len()];
        let mut nodes = Vec::new();
        let mut node_grid = Vec::new();
        for j in 0..=grid.ny {
            for i in 0..=grid.nx {
                let g = grid.node_index(i, j);
                if used[g] {
                    mesh_node[g] = nodes.len();
                    nodes.push(grid.node_position(i, j));
                    node_grid.push([i, j]);
                }
            }
        }
        let elements = element_cell
            .iter()
            .map(|&[i, j]| {
                [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)].map(|(a, b)| mesh_node[grid.node_index(a, b)])
            })
            .collect();
        Ok(GridMesh { grid, mesh: Mesh { nodes, elements }, element_cell, cell_element, node_grid })
    }

    /// Element at cell (i, j) with signed indices; `None` outside the grid or for an empty cell.
    pub fn element_at(&self, i: isize, j: isize) -> Option<usize> {
        if i < 0 || j < 0 || i >= self.grid.nx as isize || j >= self.grid.ny as isize {
            return None;
        }
        self.cell_element[self.grid.cell_index(i as usize, j as usize)]
    }

    /// All mesh nodes at grid node (i, j) (more than one on a cut crack).
    pub fn nodes_at(&self, i: usize, j: usize) -> Vec<usize> {
        // Nodes sit at the corners of the up-to-four cells around (i, j).
        let mut out = Vec::new();
        for (di, dj, corner) in [(0isize, 0isize, 0usize), (-1, 0, 1), (-1, -1, 2), (0, -1, 3)] {
            if let Some(e) = self.element_at(i as isize + di, j as isize + dj) {
                let a = self.mesh.elements[e][corner];
                if !out.contains(&a) {
                    out.push(a);
                }
            }
        }
        out
    }

    /// Mesh nodes lying on the grid line x = x0 + i hx (all copies), sorted by y.
    pub fn nodes_on_column(&self, i: usize) -> Vec<usize> {
        let mut v: Vec<usize> = (0..self.mesh.n_nodes()).filter(|&a| self.node_grid[a][0] == i).collect();
        v.sort_by_key(|&a| self.node_grid[a][1]);
        v
    }
}
