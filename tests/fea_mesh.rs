//! Grid meshing, crack cutting, probes and VTK text of the FEA. References here are
//! exact counts (topology) and exact fields (constant stress is reproduced exactly).

use cramp::dim::Vector;
use cramp::fea::{self, BoundaryConditions, FeaError, Grid, GridMesh, Model};
use cramp::material::{LinearElastic, PlaneState};

fn unit_grid(n: usize) -> Grid {
    Grid::new(Vector::zeros(), Vector::new(1.0, 1.0), n, n).unwrap()
}

#[test]
fn grid_mesh_keeps_only_material_cells_and_their_nodes() {
    // L-shape: remove the upper-right 2×2 block of a 4×4 grid.
    let gm = GridMesh::from_grid(unit_grid(4), |i, j, _| !(i >= 2 && j >= 2)).unwrap();
    assert_eq!(gm.mesh.elements.len(), 12);
    // 25 grid nodes minus the 4 touched only by removed cells: (3,3),(4,3),(3,4),(4,4).
    assert_eq!(gm.mesh.n_nodes(), 21);
    // Every element is counter-clockwise with area 1.
    for e in 0..gm.mesh.elements.len() {
        let x = gm.mesh.element_coords(e);
        let area: f64 = (0..4).map(|k| x[k].x * x[(k + 1) % 4].y - x[(k + 1) % 4].x * x[k].y).sum::<f64>() / 2.0;
        assert!((area - 1.0).abs() < 1e-15);
    }
    assert!(matches!(GridMesh::from_grid(unit_grid(2), |_, _, _| false), Err(FeaError::InvalidGrid(_))));
    assert!(Grid::new(Vector::zeros(), Vector::new(0.0, 1.0), 2, 2).is_err());
}

#[test]
fn interior_crack_splits_interior_nodes_and_keeps_both_tips() {
    let mut gm = GridMesh::from_grid(unit_grid(6), |_, _, _| true).unwrap();
    let cracks = gm.cut_cracks(&[vec![Vector::new(1.0, 3.0), Vector::new(4.0, 3.0)]]).unwrap();
    assert_eq!(gm.mesh.n_nodes(), 49 + 2, "nodes (2,3) and (3,3) are duplicated, the tips are not");
    let [a, b] = cracks[0].tips;
    let (a, b) = (a.unwrap(), b.unwrap());
    assert_eq!((a.grid_node, b.grid_node), ([1, 3], [4, 3]));
    assert_eq!((a.direction, b.direction), (Vector::new(-1.0, 0.0), Vector::new(1.0, 0.0)));
    assert_eq!(gm.nodes_at(2, 3).len(), 2);
    assert_eq!(gm.nodes_at(1, 3).len(), 1);
    // Elements above the crack use the other copy than elements below.
    let above = gm.element_at(2, 3).unwrap();
    let below = gm.element_at(2, 2).unwrap();
    assert_ne!(gm.mesh.elements[above][0], gm.mesh.elements[below][3]);
}

#[test]
fn edge_crack_and_kinked_crack() {
    let mut gm = GridMesh::from_grid(unit_grid(6), |_, _, _| true).unwrap();
    let cracks = gm.cut_cracks(&[vec![Vector::new(0.0, 3.0), Vector::new(3.0, 3.0)]]).unwrap();
    assert_eq!(gm.mesh.n_nodes(), 49 + 3, "mouth (0,3), (1,3), (2,3) split; tip (3,3) not");
    assert!(cracks[0].tips[0].is_none());
    assert_eq!(cracks[0].tips[1].unwrap().grid_node, [3, 3]);

    let mut gm = GridMesh::from_grid(unit_grid(6), |_, _, _| true).unwrap();
    let pts = vec![Vector::new(0.0, 3.0), Vector::new(2.0, 3.0), Vector::new(2.0, 5.0)];
    let cracks = gm.cut_cracks(&[pts]).unwrap();
    assert_eq!(gm.mesh.n_nodes(), 49 + 4, "(0,3), (1,3), kink (2,3), (2,4) split");
    let tip = cracks[0].tips[1].unwrap();
    assert_eq!((tip.grid_node, tip.direction), ([2, 5], Vector::new(0.0, 1.0)));
}

#[test]
fn off_grid_cracks_are_clear_errors() {
    let mut gm = GridMesh::from_grid(unit_grid(6), |_, _, _| true).unwrap();
    // Second segment is diagonal.
    let err = gm.cut_cracks(&[vec![Vector::new(0.0, 3.0), Vector::new(2.0, 3.0), Vector::new(3.0, 4.0)]]).unwrap_err();
    println!("{err}");
    assert!(matches!(err, FeaError::CrackOffGrid { crack: 0, segment: 1, .. }));
    assert!(err.to_string().contains("neither horizontal nor vertical"));
    // End point inside a cell edge, not on a grid node.
    let err = gm.cut_cracks(&[vec![Vector::new(0.0, 3.0), Vector::new(2.5, 3.0)]]).unwrap_err();
    println!("{err}");
    assert!(matches!(err, FeaError::CrackOffGrid { segment: 0, .. }));
    // A horizontal crack between grid lines.
    let err = gm.cut_cracks(&[vec![Vector::new(0.0, 3.5), Vector::new(2.0, 3.5)]]).unwrap_err();
    assert!(matches!(err, FeaError::CrackOffGrid { .. }));
    assert!(matches!(gm.cut_cracks(&[vec![Vector::new(0.0, 3.0)]]), Err(FeaError::CrackTooShort { .. })));
    // Nothing was modified by the failed calls.
    assert_eq!(gm.mesh.n_nodes(), 49);
}

/// Uniform tension σyy = 1 on a 4×3 block: probes and nodal averages return it exactly
/// (to round-off, 1e-12), outside points give `None`.
#[test]
fn probe_line_and_vtk_text() {
    let grid = Grid::new(Vector::new(1.0, 2.0), Vector::new(0.5, 1.0), 8, 3).unwrap();
    let gm = GridMesh::from_grid(grid, |_, _, _| true).unwrap();
    let mat = LinearElastic { e: 100.0, nu: 0.3, rho: 1.0, state: PlaneState::PlaneStrain };
    let model = Model::new(&gm.mesh, mat, 2.0).unwrap();
    let mut bcs = BoundaryConditions::new(&gm.mesh);
    let bottom: Vec<usize> = (0..gm.mesh.n_nodes()).filter(|&a| gm.node_grid[a][1] == 0).collect();
    let top: Vec<usize> = (0..gm.mesh.n_nodes()).filter(|&a| gm.node_grid[a][1] == 3).collect();
    for &a in &bottom {
        bcs.prescribe(a, 1, 0.0).unwrap();
    }
    bcs.prescribe(bottom[0], 0, 0.0).unwrap();
    let mut top = top;
    top.sort_by_key(|&a| gm.node_grid[a][0]);
    for w in top.windows(2) {
        bcs.edge_traction(&model, w[0], w[1], |_| Vector::new(0.0, 1.0)).unwrap();
    }
    let sol = fea::solve(&model, &bcs).unwrap();
    let samples = fea::probe_line(&gm.mesh, &sol, Vector::new(0.5, 3.3), Vector::new(5.5, 3.3), 11);
    assert!(samples[0].stress.is_none() && samples[10].stress.is_none(), "x = 0.5 and 5.5 are outside");
    for s in &samples[1..10] {
        let st = s.stress.unwrap();
        assert!((st.yy - 1.0).abs() < 1e-12 && st.xx.abs() < 1e-12 && st.xy.abs() < 1e-12);
        assert!((st.zz - 0.3).abs() < 1e-12, "plane strain σzz = ν σyy");
    }
    let nodal = fea::nodal_results(&gm.mesh, &sol);
    assert_eq!(nodal.stress.len(), gm.mesh.n_nodes());

    let mut buf = Vec::new();
    fea::write_vtk(&mut buf, &gm.mesh, &sol, "uniform tension").unwrap();
    let text = String::from_utf8(buf).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "# vtk DataFile Version 3.0");
    assert_eq!(lines[2], "ASCII");
    assert_eq!(lines[3], "DATASET UNSTRUCTURED_GRID");
    let (n, ne) = (gm.mesh.n_nodes(), gm.mesh.elements.len());
    assert_eq!(lines[4], format!("POINTS {n} double"));
    assert_eq!(lines[5 + n], format!("CELLS {ne} {}", 5 * ne));
    assert_eq!(lines[6 + n + ne], format!("CELL_TYPES {ne}"));
    assert!(lines[7 + n + ne..7 + n + 2 * ne].iter().all(|l| *l == "9"));
    assert_eq!(lines[7 + n + 2 * ne], format!("POINT_DATA {n}"));
    assert_eq!(lines[8 + n + 2 * ne], "VECTORS displacement double");
    assert_eq!(lines[9 + 2 * n + 2 * ne], "TENSORS stress double");
    assert_eq!(lines[10 + 3 * n + 2 * ne], format!("CELL_DATA {ne}"));
    assert_eq!(lines[11 + 3 * n + 2 * ne], "TENSORS stress double");
    assert_eq!(lines.len(), 12 + 3 * n + 3 * ne);
    // Every data row parses as numbers.
    for l in lines[5..].iter().filter(|l| !l.starts_with(char::is_alphabetic)) {
        assert!(l.split_whitespace().all(|t| t.parse::<f64>().is_ok()), "{l}");
    }
    if let Ok(path) = std::env::var("CRAMP_FEA_VTK_OUT") {
        std::fs::write(path, &text).unwrap();
    }
}
