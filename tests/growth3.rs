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
