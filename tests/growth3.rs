//! 3D crack growth (issue 17; `src/fracture/growth3.rs`): scene errors and the 3D outputs.
//! The growing penny is case `front_growth_penny` (full suite: `cramp verify front_growth_penny`).
//! The extruded case `front_growth_slab` runs in tests/golden.rs.

use cramp::verify::scene_file::SceneFile;

/// Bad growth input is an error naming the field, never a panic.
#[test]
fn bad_growth_tables_name_the_field() {
    let err = |k: &str, v: &str| SceneFile::new("front_growth_3d.toml").set(k, v).load3().and_then(|s| Ok(s.build().map(|_| ())?)).unwrap_err().to_string();
    let e = err("cracks.0.fracture.growth.increment", "1.5");
    assert!(e.contains("cracks[0].fracture.growth.increment"), "{e}");
    let e = err("cracks.0.fracture.growth.every", "0");
    assert!(e.contains("cracks[0].fracture.growth.every"), "{e}");
    let e = err("materials.0.toughness.kic", "-1.0");
    assert!(e.contains("materials[0].toughness.kic"), "{e}");
    let e = SceneFile::new("front_growth_3d.toml").set("materials.0.toughness", "{ criterion = \"max_hoop_stress\", kic = 1.0 }").load3();
    assert!(e.is_ok());
}

/// A short run of the extruded scene writes growth.csv with one row per front node per
/// check and the crack surfaces in the VTK series.
#[test]
fn growing_front_writes_growth_csv_and_surfaces() {
    let scene = SceneFile::new("front_growth_3d.toml")
        .set("materials.0.toughness.kic", "0.5")
        .set("solver.end_time", "0.06")
        .set("output.archive_interval", "0.03")
        .load3()
        .unwrap();
    let dir = std::env::temp_dir().join(format!("cramp-growth3-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let opts = cramp::output::RunOptions { out_dir: Some(dir.clone()), ..Default::default() };
    let r = cramp::output::three_d::run_scene_3d(&scene, &opts).unwrap();
    let csv = std::fs::read_to_string(dir.join("growth.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some(cramp::fracture::growth3::NodeRecord::HEADER));
    let rows: Vec<&str> = lines.collect();
    let g = r.sim.growth.as_ref().unwrap();
    assert_eq!(rows.len(), g.records.len());
    assert!(g.records.iter().any(|x| x.grew), "the front grew");
    assert!(rows.iter().all(|l| l.split(',').count() == 22));
    let pvd = std::fs::read_to_string(dir.join("particles.pvd")).unwrap();
    assert!(pvd.contains("cracks_00002.vtk"), "{pvd}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Fronts on free faces (growth3 module doc, item 5): the extruded slab of
/// `front_growth_slab` without its rollers on z = 0 and z = 4, so the front's ends lie on
/// free faces (relative volume ½). Before the face rule both face nodes stopped at their
/// first check without moving, their neighbours were drawn to the faces, and the crack did
/// not get through. Now every front node grows to the far edge x = 20 (trimmed within a
/// tenth of a cell of it), the face nodes along their faces. Measured: 14–15 moves per
/// node, all stopped at the far edge by step 339 (t ≈ 0.29 ms); face nodes within 0.05 mm
/// of their face; about 12 s.
#[test]
fn free_face_fronts_grow_through_the_slab() {
    let scene = SceneFile::new("front_growth_3d.toml").set("boundary", "[]").load3().unwrap();
    let mut sim = scene.build().unwrap();
    sim.run_until(scene.solver.end_time, |_| {}).unwrap();
    let g = sim.growth.as_ref().unwrap();
    let labels: std::collections::BTreeSet<u32> = g.records.iter().map(|r| r.label).collect();
    assert_eq!(labels.len(), 5, "five front nodes, no splits or merges");
    for l in labels {
        let rows: Vec<_> = g.records.iter().filter(|r| r.label == l).collect();
        let z0 = rows[0].x.z;
        let moves = rows.iter().filter(|r| r.grew).count();
        let last = rows.last().unwrap();
        assert!(moves >= 10, "node {l} (z = {z0}) moved {moves} times");
        assert_eq!(last.status, cramp::fracture::growth3::NodeStatus::AtEdge, "node {l} ends at the boundary");
        // Its final position: the position before the last check plus the last move.
        let end = last.x.x + (last.advance - rows[rows.len() - 2].advance);
        assert!(end > 19.8 && end <= 20.0, "node {l} (z = {z0}) stopped at x = {end}");
        if !(0.5..=3.5).contains(&z0) {
            let face = z0.round();
            let off = rows.iter().map(|r| (r.x.z - face).abs()).fold(0.0, f64::max);
            assert!(off < 0.1, "face node {l} left its face by {off} mm");
        }
    }
    assert!(sim.cracks[0].front.is_empty(), "every front edge reached the far edge and was pruned");
}
