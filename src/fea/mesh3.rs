//! 3D meshes: flat node and hex8 element arrays, and the structured mesh of the
//! material cells of the MPM's 3D background grid (the 3D form of [`super::mesh`]).

use super::{FeaError, Result};
use crate::dim::Vector3;
use crate::grid::Grid3;

/// An unstructured mesh of 8-noded hexahedra.
///
/// Node `a` has position `nodes[a]` and DOFs `3a` (x), `3a + 1` (y), `3a + 2` (z).
/// Element nodes are in the order of [`super::hex8::CORNERS`] (positive Jacobian); a
/// general distorted hexahedron is allowed.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh3 {
    pub nodes: Vec<Vector3>,
    pub elements: Vec<[usize; 8]>,
}

impl Mesh3 {
    /// Checks indices and coordinates (orientation is checked by [`super::solve3::Model3::new`]).
    pub fn new(nodes: Vec<Vector3>, elements: Vec<[usize; 8]>) -> Result<Mesh3> {
        if let Some(a) = nodes.iter().position(|x| !x.iter().all(|c| c.is_finite())) {
            return Err(FeaError::InvalidInput(format!("node {a} has a non-finite coordinate")));
        }
        let n_nodes = nodes.len();
        for (e, conn) in elements.iter().enumerate() {
            if let Some(&node) = conn.iter().find(|&&node| node >= n_nodes) {
                return Err(FeaError::ElementNodeOutOfRange { element: e, node, n_nodes });
            }
            for k in 0..8 {
                if conn[k + 1..].contains(&conn[k]) {
                    return Err(FeaError::InvalidInput(format!("element {e} uses node {} twice", conn[k])));
                }
            }
        }
        Ok(Mesh3 { nodes, elements })
    }

    pub fn n_nodes(&self) -> usize {
        self.nodes.len()
    }

    pub fn n_dofs(&self) -> usize {
        3 * self.nodes.len()
    }

    /// The eight node positions of element `e`.
    pub fn element_coords(&self, e: usize) -> [Vector3; 8] {
        self.elements[e].map(|a| self.nodes[a])
    }
}

/// Grid offsets of the eight corners of a cell, in [`super::hex8::CORNERS`] order.
pub const CELL_CORNERS: [[usize; 3]; 8] =
    [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]];

/// The structured hex8 mesh of the material cells of a [`Grid3`].
///
/// Element `e` is grid cell `element_cell[e]`; its nodes are the cell corners in
/// [`CELL_CORNERS`] order. Only grid nodes touched by a material cell become mesh nodes,
/// numbered in grid order (x fastest, then y, then z).
#[derive(Clone, Debug)]
pub struct GridMesh3 {
    pub grid: Grid3,
    pub mesh: Mesh3,
    /// Grid cell (i, j, k) of every element.
    pub element_cell: Vec<[usize; 3]>,
    /// Element of every grid cell (flat cell index), `None` for an empty cell.
    pub cell_element: Vec<Option<usize>>,
    /// Grid node (i, j, k) of every mesh node.
    pub node_grid: Vec<[usize; 3]>,
    /// Mesh node of every grid node (flat node index), `usize::MAX` where there is none;
    /// on a cut crack the node of the − side.
    pub grid_node: Vec<usize>,
    /// Crack-face copies (the + side of a cut crack) of every split grid node.
    pub copies: std::collections::BTreeMap<usize, Vec<usize>>,
}

/// Flat index of cell (i, j, k).
pub fn cell_index(grid: &Grid3, [i, j, k]: [usize; 3]) -> usize {
    i + grid.n[0] * (j + grid.n[1] * k)
}

impl GridMesh3 {
    /// Mesh the cells (i, j, k) for which `holds_material([i, j, k])` is true.
    pub fn from_grid(grid: Grid3, mut holds_material: impl FnMut([usize; 3]) -> bool) -> Result<GridMesh3> {
        let [nx, ny, nz] = grid.n;
        let mut cell_element = vec![None; nx * ny * nz];
        let mut element_cell = Vec::new();
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    if holds_material([i, j, k]) {
                        cell_element[cell_index(&grid, [i, j, k])] = Some(element_cell.len());
                        element_cell.push([i, j, k]);
                    }
                }
            }
        }
        if element_cell.is_empty() {
            return Err(FeaError::InvalidGrid("no cell holds material: the mesh would be empty".into()));
        }
        let corner = |c: [usize; 3], o: [usize; 3]| grid.node_index(c[0] + o[0], c[1] + o[1], c[2] + o[2]);
        let n_grid_nodes = (nx + 1) * (ny + 1) * (nz + 1);
        let mut used = vec![false; n_grid_nodes];
        for &c in &element_cell {
            for o in CELL_CORNERS {
                used[corner(c, o)] = true;
            }
        }
        let mut grid_node = vec![usize::MAX; n_grid_nodes];
        let mut nodes = Vec::new();
        let mut node_grid = Vec::new();
        for (g, _) in used.iter().enumerate().filter(|(_, u)| **u) {
            grid_node[g] = nodes.len();
            nodes.push(crate::dim::GridGeometry::node_pos(&grid, g));
            node_grid.push(grid.node_ijk(g));
        }
        let elements = element_cell.iter().map(|&c| CELL_CORNERS.map(|o| grid_node[corner(c, o)])).collect();
        Ok(GridMesh3 { grid, mesh: Mesh3 { nodes, elements }, element_cell, cell_element, node_grid, grid_node, copies: Default::default() })
    }

    /// Element at cell (i, j, k) with signed indices; `None` outside the grid or for an empty cell.
    pub fn element_at(&self, c: [isize; 3]) -> Option<usize> {
        if (0..3).any(|d| c[d] < 0 || c[d] >= self.grid.n[d] as isize) {
            return None;
        }
        self.cell_element[cell_index(&self.grid, c.map(|v| v as usize))]
    }

    /// Mesh nodes at the flat grid node `g`: none outside the material, two on a cut crack.
    pub fn nodes_at(&self, g: usize) -> Vec<usize> {
        let mut out: Vec<usize> = (self.grid_node[g] != usize::MAX).then_some(self.grid_node[g]).into_iter().collect();
        out.extend(self.copies.get(&g).into_iter().flatten());
        out
    }
}
