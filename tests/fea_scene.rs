//! The scene → FEA mapping of `cramp fea` (`cramp::fea::scene`), checked against the MPM's
//! own treatment of the same scene (the independent reference here is the MPM code path:
//! its node splitting, its shape functions, its particle loads), and its error messages.
//!
//! * Cracks: the FEA duplicates exactly the grid nodes the MPM gives two velocity fields
//!   (after one MPM step), for tips inside a cell and exactly on a node, horizontal and
//!   vertical cracks, both crack directions. Exact set equality.
//! * Supports: a piece held against all rigid motions is accepted; rollers only or a
//!   single pinned node give an error naming the free rigid motion.
//! * Loads: the FEA nodal loads equal the MPM's Σ_p S_ip f_p at the initial particle
//!   positions at every grid node (to 1e-14 relative: the same products summed in a
//!   different order), for linear and for uGIMP shape functions (the particle domains of
//!   the regular fill tile the cells, so the uGIMP weights are the bilinear ones until
//!   the particles move); resultant and moment to 1e-12.
//! * Bad input: every error names the scene field or the crack segment; `cramp fea` exits
//!   non-zero with the message.

use cramp::dim::Vector;
use cramp::fea::scene::SceneFea;
use cramp::fea::FeaError;
use cramp::scene::Scene;
use cramp::shape::weights;
use std::collections::BTreeSet;

fn scene(text: &str) -> Scene {
    Scene::from_toml(text, "test scene").unwrap()
}

/// A 20 × 8 mm plate (1 mm cells, margin 2), clamped on the left, with `extra` appended.
fn plate(shape: &str, extra: &str) -> String {
    format!(
        r#"
[grid]
origin = [-2.0, -2.0]
size = [24.0, 12.0]
cell = [1.0, 1.0]
[solver]
shape = "{shape}"
end_time = 1.0
[[materials]]
name = "m"
E = 100.0
nu = 0.3
rho = 1.0e-3
state = "plane_strain"
[[bodies]]
material = "m"
shape = {{ rectangle = {{ min = [0.0, 0.0], max = [20.0, 8.0] }} }}
[[boundary]]
nodes = {{ region = {{ min = [-2.0, -2.0], max = [0.0, 10.0] }} }}
vx = 0.0
vy = 0.0
{extra}
"#
    )
}

/// Grid nodes (i, j) with two velocity fields after one MPM step.
fn mpm_split_nodes(s: &Scene) -> BTreeSet<(usize, usize)> {
    let mut sim = s.build().unwrap();
    sim.step().unwrap();
    (0..sim.grid.num_nodes()).filter(|&n| sim.nodes.present[n].count_ones() > 1).map(|n| sim.grid.node_ij(n)).collect()
}

/// Grid nodes the FEA duplicated.
fn fea_split_nodes(f: &SceneFea) -> BTreeSet<(usize, usize)> {
    let gm = &f.grid_mesh;
    let mut out = BTreeSet::new();
    for i in 0..=gm.grid.nx {
        for j in 0..=gm.grid.ny {
            if gm.nodes_at(i, j).len() > 1 {
                out.insert((i, j));
            }
        }
    }
    out
}

#[test]
fn fea_duplicates_exactly_the_nodes_the_mpm_splits() {
    let cases = [
        // edge crack from the left, tip inside a cell, inside a cell near its end, exactly on a node
        ("[[-1.0, 4.0], [10.5, 4.0]]", Some((11.0, 4.0))),
        ("[[-1.0, 4.0], [10.9, 4.0]]", Some((11.0, 4.0))),
        ("[[-1.0, 4.0], [10.0, 4.0]]", Some((11.0, 4.0))),
        // edge crack from the right (tip direction −x)
        ("[[21.0, 4.0], [12.5, 4.0]]", Some((12.0, 4.0))),
        // vertical edge crack from the top, tip inside a cell
        ("[[10.0, 9.0], [10.0, 3.5]]", Some((10.0, 3.0))),
        // interior crack with two tips, one on a node
        ("[[5.5, 4.0], [14.0, 4.0]]", None),
        // kinked edge crack (the kink on a node)
        ("[[-1.0, 4.0], [6.0, 4.0], [6.0, 6.5]]", Some((6.0, 7.0))),
    ];
    for (shape, _) in [("linear", ()), ("ugimp", ())] {
        for (points, tip) in cases {
            let s = scene(&plate(shape, &format!("[[cracks]]\npoints = {points}\ncontact = \"none\"\n")));
            let fea = SceneFea::from_scene(&s).unwrap();
            let (mpm, fe) = (mpm_split_nodes(&s), fea_split_nodes(&fea));
            println!("{shape} {points}: {} split nodes; meshed {:?}", fe.len(), fea.cracks[0].meshed_points);
            assert_eq!(mpm, fe, "{shape} crack {points}: MPM-split vs FEA-duplicated grid nodes");
            if let Some((x, y)) = tip {
                let tips = fea.tips();
                assert_eq!(tips.len(), 1, "{points}");
                assert_eq!(tips[0].2.position, Vector::new(x, y), "{points}");
            } else {
                let tips = fea.tips();
                assert_eq!(tips.len(), 2, "{points}");
                assert_eq!(tips[0].2.position, Vector::new(5.0, 4.0));
                assert_eq!(tips[1].2.position, Vector::new(15.0, 4.0));
            }
        }
    }
}

#[test]
fn particle_loads_map_like_the_mpm() {
    let extra = r#"
[[loads]]
particles = { region = { min = [6.2, 1.1], max = [8.7, 2.9] } }
force = [0.3, -0.7]
ramp = 0.5
[[loads]]
particles = { line = { from = [19.75, 0.0], to = [19.75, 8.0] } }
force = [0.0, 1.0]
"#;
    for shape in ["linear", "ugimp"] {
        let mut s = scene(&plate(shape, extra));
        s.bodies[0].body_force = [0.0, -9.81e-3];
        let sim = s.build().unwrap();
        let fea = SceneFea::from_scene(&s).unwrap();
        assert!(fea.notes.iter().any(|n| n.contains("loads[0].ramp")), "ramp note");
        // MPM external nodal forces Σ_p S_ip f_p at the start (no cracks: one node per grid node).
        let p = &sim.particles;
        let mut mpm = vec![Vector::zeros(); sim.grid.num_nodes()];
        let (mut res, mut mom) = (Vector::zeros(), 0.0);
        for k in 0..p.len() {
            let mut f = sim.body_force[0] * p.mass[k];
            if p.load[k] != cramp::particles::NO_LOAD {
                f += sim.loads[p.load[k] as usize].force_per_particle;
            }
            res += f;
            mom += p.x[k].perp(&f);
            let w = weights(&sim.grid, sim.options.shape, &p.x[k], &p.lp[k]);
            for a in 0..w.n {
                mpm[w.node[a] as usize] += f * w.s[a];
            }
        }
        let gm = &fea.grid_mesh;
        let forces = fea.bcs.forces();
        let (mut fres, mut fmom, mut max_diff, mut scale) = (Vector::zeros(), 0.0, 0.0f64, 0.0f64);
        for a in 0..gm.mesh.n_nodes() {
            let f = Vector::new(forces[2 * a], forces[2 * a + 1]);
            fres += f;
            fmom += gm.mesh.nodes[a].perp(&f);
            let [i, j] = gm.node_grid[a];
            let m = mpm[sim.grid.node_index(i, j)];
            max_diff = max_diff.max((f - m).norm());
            scale = scale.max(m.norm());
        }
        println!(
            "{shape}: resultant {fres:?} vs {res:?}, moment {fmom:e} vs {mom:e}, max nodal difference {max_diff:e}"
        );
        assert!((fres - res).norm() < 1e-12 * res.norm());
        assert!((fmom - mom).abs() < 1e-12 * mom.abs());
        assert!(max_diff < 1e-14 * scale, "{shape}: MPM and FEA nodal loads differ by {max_diff:e}");
    }
}

fn fea_err(text: &str) -> FeaError {
    SceneFea::from_scene(&scene(text)).unwrap_err()
}

#[test]
fn bad_scenes_give_field_named_errors() {
    // A constant non-zero velocity is now a prescribed displacement v·NΔt at the end of the
    // run (issue 21), no longer an error.
    let moved = SceneFea::from_scene(&scene(&plate("ugimp", "").replace("vx = 0.0\nvy = 0.0", "vx = 0.5\nvy = 0.0"))).unwrap();
    assert!(moved.bcs.prescribed().iter().any(|v| v.is_some_and(|u| u > 0.0)));

    // (Not [10.5, 6.5]: that line passes exactly through the particle at (4.75, 5.25),
    // which the scene itself now refuses.)
    let e = fea_err(&plate("ugimp", "[[cracks]]\npoints = [[-1.0, 4.0], [10.5, 6.6]]\n"));
    println!("{e}");
    assert!(matches!(e, FeaError::CrackOffGrid { crack: 0, segment: 0, .. }));
    assert!(e.to_string().contains("neither horizontal nor vertical"));

    let e = fea_err(&plate("ugimp", "[[cracks]]\npoints = [[-1.0, 4.5], [10.5, 4.5]]\n"));
    println!("{e}");
    assert!(e.to_string().contains("between grid lines"));

    let e = fea_err(&plate("ugimp", "[[cracks]]\npoints = [[-1.0, 4.0], [6.5, 4.0], [10.0, 4.0]]\n"));
    println!("{e}");
    assert!(e.to_string().contains("segment 1") && e.to_string().contains("must be a grid node"));

    // A free body with an unbalanced load has no static solution.
    let free = plate(
        "ugimp",
        "[[loads]]\nparticles = { region = { min = [18.0, 0.0], max = [20.0, 8.0] } }\nforce = [1.0, 0.0]\n",
    )
    .replace("vx = 0.0\nvy = 0.0", "vx = 0.0")
    .replace("min = [-2.0, -2.0], max = [0.0, 10.0]", "min = [-2.0, -2.0], max = [-2.0, 10.0]");
    let e = fea_err(&free);
    println!("{e}");
    assert!(e.to_string().contains("`boundary`") && e.to_string().contains("not in equilibrium"));

    // Rollers only (vy = 0 on the bottom): x translation is free → not positive definite, with a hint.
    let rollers = plate(
        "ugimp",
        "[[loads]]\nparticles = { region = { min = [18.0, 7.0], max = [20.0, 8.0] } }\nforce = [0.0, -1.0]\n",
    )
    .replace("vx = 0.0\nvy = 0.0", "vy = 0.0")
    .replace("min = [-2.0, -2.0], max = [0.0, 10.0]", "min = [-2.0, -2.0], max = [22.0, 0.0]");
    let e = fea_err(&rollers);
    println!("{e}");
    assert!(e.to_string().contains("`boundary`") && e.to_string().contains("rigid translation in x free"));
    // A single pinned node leaves the rotation about it.
    let pinned = rollers
        .replace("min = [-2.0, -2.0], max = [22.0, 0.0]", "min = [0.0, 0.0], max = [0.0, 0.0]")
        .replace("vy = 0.0", "vx = 0.0\nvy = 0.0");
    let e = fea_err(&pinned);
    println!("{e}");
    assert!(e.to_string().contains("rigid rotation about (0.000000, 0.000000) free"));

    // Probes are validated with the scene.
    let e = Scene::from_toml(
        &plate("ugimp", "[[probes]]\nname = \"a b\"\nfrom = [0.0, 4.0]\nto = [20.0, 4.0]\npoints = 5\n"),
        "t",
    )
    .unwrap_err();
    assert!(e.to_string().contains("probes[0].name"), "{e}");
    let e = Scene::from_toml(
        &plate("ugimp", "[[probes]]\nname = \"a\"\nfrom = [0.0, 4.0]\nto = [30.0, 4.0]\npoints = 5\n"),
        "t",
    )
    .unwrap_err();
    assert!(e.to_string().contains("probes[0].to") && e.to_string().contains("outside the grid"), "{e}");
    let e = Scene::from_toml(
        &plate("ugimp", "[[probes]]\nname = \"a\"\nfrom = [0.0, 4.0]\nto = [10.0, 4.0]\npoints = 1\n"),
        "t",
    )
    .unwrap_err();
    assert!(e.to_string().contains("probes[0].points"), "{e}");
}

/// A disk on a clamped plate: partly filled cells are meshed in full and counted; the
/// two bodies become two element groups.
#[test]
fn bodies_become_element_groups() {
    let extra = r#"
[[materials]]
name = "hard"
E = 1000.0
nu = 0.3
rho = 1.0e-3
state = "plane_strain"
[[bodies]]
material = "hard"
shape = { disk = { center = [10.0, 9.0], radius = 0.9 } }
thickness = 2.0
"#;
    let s = scene(&plate("ugimp", extra));
    let fea = SceneFea::from_scene(&s).unwrap();
    let n1 = fea.element_body.iter().filter(|&&b| b == 1).count();
    println!("{} elements of the disk, {} partial cells; notes {:?}", n1, fea.partial_cells, fea.notes);
    assert_eq!(n1, 4, "the disk holds particles in the 4 cells around its centre");
    assert_eq!(fea.groups[1].1, 2.0);
    assert!(fea.partial_cells >= 4);
    // The disk touches the plate (shares nodes at y = 8), so the mesh is one supported piece.
    assert!(fea.auto_supports.is_empty());
    fea.analyse().unwrap();
}

/// `cramp fea` on the verification scene writes its files; bad input exits non-zero.
#[test]
fn cramp_fea_command() {
    let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cramp_fea_dcb_nairn2003");
    let _ = std::fs::remove_dir_all(&out);
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("verification/dcb_nairn2003.toml");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_cramp"))
        .args(["fea", scene.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    println!("{stdout}{}", String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success());
    assert!(stdout.contains("meshed at node (50, 0)"));
    for f in ["fea.vtk", "fea_gauss.vtk", "fea_nodes.csv", "probe_midplane.csv", "fea_summary.json"] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("fea_summary.json")).unwrap()).unwrap();
    assert_eq!(summary["tips"].as_array().unwrap().len(), 1);
    assert_eq!(summary["tips"][0]["domains"].as_array().unwrap().len(), 8);
    let probe = std::fs::read_to_string(out.join("probe_midplane.csv")).unwrap();
    assert_eq!(probe.lines().count(), 52);
    // The Gauss-point file reads back with the crate's VTK reader (ParaView's legacy format).
    let g = cramp::output::vtk::read_points(out.join("fea_gauss.vtk")).unwrap();
    assert_eq!(g.positions.len(), 4 * 900);

    let bad = std::env::temp_dir().join(format!("cramp_fea_bad_{}.toml", std::process::id()));
    std::fs::write(&bad, plate("ugimp", "[[cracks]]\npoints = [[-1.0, 4.0], [10.5, 6.6]]\n")).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_cramp"))
        .args(["fea", bad.to_str().unwrap(), "--out", out.join("bad").to_str().unwrap()])
        .output()
        .unwrap();
    let _ = std::fs::remove_file(&bad);
    let stderr = String::from_utf8_lossy(&o.stderr);
    println!("{stderr}");
    assert!(!o.status.success());
    assert!(stderr.contains("crack 0, segment 0") && stderr.contains("not supported"));
}
