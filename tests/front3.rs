//! J and K along 3D crack fronts (issue 16): the scene table reaches the run and
//! cracks.csv holds one row per front node and history time, the same as the in-memory
//! results, and nothing is computed without the table. The accuracy checks are the quick
//! cases front_j_slab and front_j_penny (tests/golden.rs) and the unit tests of
//! src/fracture/front3.rs (the contour against the closed-form K fields).

mod common;

use cramp::output::three_d::run_scene_3d;
use cramp::output::RunOptions;
use cramp::verify::scene_file::SceneFile;

#[test]
fn cracks_csv_has_a_row_per_front_node_and_history_time() {
    let scene = SceneFile::new("front_sent_3d.toml").set("solver.end_time", "0.02").set("output.history_interval", "0.005").set("output.archive_interval", "0.01").load3().unwrap();
    let dir = common::temp_dir("front3_cracks_csv");
    let r = run_scene_3d(&scene, &RunOptions { out_dir: Some(dir.clone()), force: true, ..Default::default() }).unwrap();
    // Front nodes in the body: x = 6, z = 0, 1, 2, 3, 4 (the crack reaches half a cell past both faces).
    let nodes: std::collections::BTreeSet<u32> = r.fronts.iter().map(|f| f.node).collect();
    assert_eq!(nodes.len(), 5, "front nodes: {nodes:?}");
    for f in &r.fronts {
        // The crack particles move with the material (Task 7): by far less than a cell here.
        assert!((f.x.x - 6.0).abs() < 1e-3 && (-1e-3..=4.0 + 1e-3).contains(&f.x.z), "node at {:?}", f.x);
        assert!((f.frame.e1 - cramp::dim::Vector3::x()).norm() < 1e-6 && (f.frame.e2 - cramp::dim::Vector3::y()).norm() < 1e-6, "frame {:?}", f.frame);
        assert!(f.j1.is_finite() && f.k.iter().all(|k| k.is_finite()));
    }
    let times = r.history.len() - 1; // no row at t = 0
    assert_eq!(r.fronts.len(), 5 * times);
    let text = std::fs::read_to_string(dir.join("cracks.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(cramp::fracture::front3::FrontResult::HEADER));
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), r.fronts.len());
    for (row, f) in rows.iter().zip(&r.fronts) {
        assert_eq!(*row, f.csv());
    }
    // The front snapshots (none at t = 0, before the first step): five points each, listed in particles.pvd.
    let vtk = std::fs::read_to_string(dir.join("front_00001.vtk")).unwrap();
    assert!(vtk.contains("POINTS 5 ") && vtk.contains("SCALARS k1 double") && vtk.contains("VECTORS e1 double"), "{vtk}");
    assert!(!dir.join("front_00000.vtk").exists());
    assert!(std::fs::read_to_string(dir.join("particles.pvd")).unwrap().contains("front_00002.vtk"));
    // Without the table: no cracks.csv, no results.
    let mut plain = scene.clone();
    plain.cracks[0].fracture = None;
    let dir2 = common::temp_dir("front3_no_table");
    let r2 = run_scene_3d(&plain, &RunOptions { out_dir: Some(dir2.clone()), force: true, ..Default::default() }).unwrap();
    assert!(r2.fronts.is_empty());
    assert!(!dir2.join("cracks.csv").exists());
    std::fs::remove_dir_all(dir).ok();
    std::fs::remove_dir_all(dir2).ok();
}

/// An extruded crack oblique to the grid is exactly its 2D scene (3d-references.md §4.1):
/// the inclined centre crack of `front_oblique_2d.toml` (45° to the grid and to the load,
/// between the node and particle lines) and its extrusion between rollers
/// (`front_oblique_3d.toml`). Every 3D front node must sit where the 2D tip is and give
/// the 2D circle contour's J₁ up to round-off: the 3D path (particle–node segments against
/// two-sided triangles in general position, the 3D front contour) against the 2D path
/// (polyline crossing, `fracture.circle`), which share no crack geometry code. Measured
/// 4e−16 relative; the bound 1e−12 only allows sums taken in another order. The
/// grid-aligned counterpart is the quick case front_j_slab (equal to the bit).
#[test]
fn oblique_extruded_crack_matches_2d() {
    use cramp::fracture::jintegral::TipEnd;
    let s2 = SceneFile::new("front_oblique_2d.toml").load().unwrap();
    let s3 = SceneFile::new("front_oblique_3d.toml").load3().unwrap();
    let mut a = s2.build().unwrap();
    a.run_until(s2.solver.end_time, |_| {}).unwrap();
    let mut b = s3.build().unwrap();
    b.run_until(s3.solver.end_time, |_| {}).unwrap();
    assert_eq!(a.step_count, b.step_count);
    let radius = 1.5 * a.grid.min_h();
    let tips: Vec<(cramp::dim::Vector, f64)> = [TipEnd::Start, TipEnd::End]
        .into_iter()
        .map(|end| {
            let pts = &a.cracks[0].points;
            let x = if matches!(end, TipEnd::Start) { pts[0] } else { pts[pts.len() - 1] };
            (x, a.circle_j_2d(0, end, radius, 16).0)
        })
        .collect();
    assert!(tips.iter().all(|(_, j)| *j > 1e-3), "the 2D tips are loaded: {tips:?}");
    let req = s3.front_requests(&b.cracks).unwrap().remove(0).expect("the slab asks for J");
    let front = b.front_fracture(0, &req);
    assert_eq!(front.len(), 8, "four front nodes inside the slab at each end");
    for f in &front {
        let (x, j) = tips.iter().min_by(|p, q| ((p.0.x - f.x.x).hypot(p.0.y - f.x.y)).total_cmp(&(q.0.x - f.x.x).hypot(q.0.y - f.x.y))).unwrap();
        assert!((x.x - f.x.x).abs() < 1e-12 && (x.y - f.x.y).abs() < 1e-12, "node at {:?}, 2D tip at {x:?}", f.x);
        assert!((f.j1 / j - 1.0).abs() < 1e-12, "node at {:?}: J₁ {} against the 2D {j}", f.x, f.j1);
    }
}

/// Mirror images at a symmetry plane (`fracture.mirrors`): on the SENT slab (rollers on both
/// z faces, so the fields do not depend on z) the front node on the face z = 0, whose domain
/// the face cuts, gets with the mirror z = 0 the domain J₁ and interaction K of the node at
/// mid-thickness, whose domain is whole (ψ half-length 1 cell = the half-thickness), and a
/// K_III of zero; without the mirror its K_III is not given. Tolerance 1e−9: the fields are
/// the same along z to round-off, and the sums are exact.
#[test]
fn mirror_images_complete_a_domain_cut_by_a_symmetry_plane() {
    use cramp::fracture::front3::{DomainShape, FrontRequest};
    let scene = SceneFile::new("front_sent_3d.toml").set("solver.end_time", "0.05").load3().unwrap();
    let mut sim = scene.build().unwrap();
    sim.run_until(scene.solver.end_time, |_| {}).unwrap();
    let req = scene.front_requests(&sim.cracks).unwrap().remove(0).unwrap();
    let h = 2.0;
    let dreq = FrontRequest { domain: Some(DomainShape { inner: 2.0 * h, outer: 3.0 * h, along: h }), interaction: true, ..req };
    let at = |fr: &[cramp::fracture::front3::FrontResult], z: f64| fr.iter().find(|f| (f.x.z - z).abs() < 1e-3).unwrap().clone();
    let plain = sim.front_fracture(0, &dreq);
    let mirrored = sim.front_fracture(0, &FrontRequest { mirrors: vec![(2, 0.0)], ..dreq.clone() });
    let (mid, face, face_plain) = (at(&mirrored, 2.0), at(&mirrored, 0.0), at(&plain, 0.0));
    assert_eq!(at(&plain, 2.0).j1, mid.j1, "the mirror changed a whole domain");
    assert!(face_plain.k[2].is_nan(), "K_III at the cut face node without the mirror: {:?}", face_plain.k);
    assert!((face.j1 - mid.j1).abs() <= 1e-9 * mid.j1, "J₁ face {} vs mid-thickness {}", face.j1, mid.j1);
    for m in 0..2 {
        assert!((face.k[m] - mid.k[m]).abs() <= 1e-9 * mid.k[0], "K[{m}] face {:?} vs mid-thickness {:?}", face.k, mid.k);
    }
    assert!(face.k[2].abs() <= 1e-9 * mid.k[0], "K_III at the face node with the mirror: {:?}", face.k);
}

/// A mirror plane with material on both sides of it is refused when the scene is built,
/// naming the table and a particle on each side.
#[test]
fn mirror_plane_through_the_material_is_refused() {
    let scene = SceneFile::new("front_sent_3d.toml").set("cracks.0.fracture.method", "\"domain\"").set("cracks.0.fracture.mirrors", "[{ axis = \"z\", at = 2.0 }]").load3().unwrap();
    let err = scene.build().err().expect("refused").to_string();
    for n in ["cracks[0].fracture.mirrors[0]", "both sides of the plane z = 2", "symmetry plane"] {
        assert!(err.contains(n), "error does not contain {n:?}: {err}");
    }
}
