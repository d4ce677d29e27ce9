//! Helpers shared by several test files (each file under tests/ is its own crate; this
//! module is included with `mod common;`).

use cramp::verify::{self, Variant};

/// The block-on-a-crack scene of the `crack_friction` case at 1 mm cells
/// ([`cramp::verify::cases::cracks::block_on_crack`]): a 20 × 4 mm block pressed onto a
/// fixed 36 × 4 mm base across a horizontal crack on y = 0, total `force` (x, y) on the
/// block's particles ramped over `ramp`, the crack's `contact` law as TOML.
#[allow(dead_code)]
pub fn block_on_crack(force: [f64; 2], ramp: f64, end_time: f64, contact: &str) -> String {
    cramp::verify::cases::cracks::block_on_crack(1.0, force, ramp, end_time, contact).to_toml().unwrap()
}

/// Run a verification case of `verification/cases.toml` through the library (as `cramp
/// verify` does), print its table and notes, write its report section (figures and data
/// files) to target/tmp/<case>/, and assert that it passed. The tolerances are the
/// manifest's.
#[allow(dead_code)]
pub fn verify_case(name: &str, variant: Variant) -> verify::CaseResult {
    let case = verify::select(&[name.to_string()], variant).expect("a registered case").remove(0);
    let result = verify::run_case(&case, variant);
    println!("{}", verify::report::text_table(std::slice::from_ref(&result)));
    for n in &result.notes {
        println!("{n}");
    }
    let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let problems = verify::report::write_report(&out, std::slice::from_ref(&result), variant, result.wall_s).unwrap();
    println!("report with figures and data in {}", out.display());
    assert!(problems.is_empty(), "{problems:?}");
    assert!(result.passed, "verification case {name} failed: {:?}", result.errors);
    result
}

/// A pseudo-random permutation of 0..n (Fisher–Yates driven by a 64-bit LCG), for the
/// particle-order tests.
#[allow(dead_code)]
pub fn lcg_permutation(n: usize, seed: u64) -> Vec<usize> {
    let mut perm: Vec<usize> = (0..n).collect();
    let mut s = seed;
    for i in (1..n).rev() {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        let j = ((s >> 33) % (i as u64 + 1)) as usize;
        perm.swap(i, j);
    }
    perm
}

/// A small 3D scene that runs every part of the 3D step except cracks: two bodies of
/// different materials in one velocity field (a box with a sine velocity field and a
/// body force, and a sphere falling onto it), roller boundary conditions on a node plane
/// (`plane` selection) and a node box (`box` selection), a ramped particle load and grid
/// damping. 8 particles per cell; 256 in the box, 136 in the sphere; cells of 1/8 so the
/// node coordinates are exact.
#[allow(dead_code)]
pub const LOADED_3D: &str = r#"
[grid]
origin = [0.0, 0.0, 0.0]
size = [1.0, 1.0, 1.0]
cell = [0.125, 0.125, 0.125]

[solver]
cfl = 0.5
end_time = 1.0
damping = 0.5

[[materials]]
name = "soft"
E = 1000.0
nu = 0.3
rho = 1.0

[[materials]]
name = "stiff"
E = 5000.0
nu = 0.25
rho = 2.0

[[bodies]]
material = "soft"
shape = { box = { min = [0.25, 0.25, 0.25], max = [0.75, 0.5, 0.75] } }
velocity_sine = { amplitude = [0.1, -0.2, 0.05], k = [7.0, 3.0, 5.0] }
body_force = [0.0, -0.5, 0.1]

[[bodies]]
material = "stiff"
shape = { sphere = { center = [0.5, 0.75, 0.5], radius = 0.2 } }
velocity = [0.0, -0.3, 0.02]

[[boundary]]
nodes = { plane = { point = [0.0, 0.25, 0.0], normal = [0.0, 1.0, 0.0] } }
vy = 0.0

[[boundary]]
nodes = { box = { min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 0.25] } }
vz = 0.0

[[loads]]
particles = { box = { min = [0.625, 0.25, 0.25], max = [0.75, 0.5, 0.75] } }
force = [0.02, 0.01, -0.01]
ramp = 0.05
"#;

/// [`LOADED_3D`] with cells of 1/16 and the box widened to 0.75 × 0.25 × 0.75: 5,700
/// particles, more than the 4096 per chunk of the particle→node pair lists, so 2 threads
/// build them in 2 chunks.
#[allow(dead_code)]
pub fn loaded_3d_fine() -> String {
    let text = LOADED_3D
        .replace("cell = [0.125, 0.125, 0.125]", "cell = [0.0625, 0.0625, 0.0625]")
        .replace("min = [0.25, 0.25, 0.25], max = [0.75, 0.5, 0.75]", "min = [0.125, 0.25, 0.125], max = [0.875, 0.5, 0.875]");
    assert_ne!(text, LOADED_3D);
    text
}

/// The bits of a 3D particle's position, velocity, stress, strain and displacement
/// gradient (3 + 3 + 6 + 6 + 9 values).
#[allow(dead_code)]
pub fn particle_bits_3d(sim: &cramp::simulation::Simulation<cramp::dim::D3>, k: usize) -> Vec<u64> {
    let p = &sim.particles;
    let (x, v, s, e, g) = (&p.x[k], &p.v[k], &p.stress[k], &p.strain[k], &p.grad_u[k]);
    let mut out = vec![x.x, x.y, x.z, v.x, v.y, v.z, s.xx, s.yy, s.zz, s.xy, s.xz, s.yz, e.xx, e.yy, e.zz, e.xy, e.xz, e.yz];
    out.extend(g.iter());
    out.into_iter().map(f64::to_bits).collect()
}

/// The bits of a 3D run's energies (kinetic, strain, external work, damping) and total momentum.
#[allow(dead_code)]
pub fn global_bits_3d(sim: &cramp::simulation::Simulation<cramp::dim::D3>) -> Vec<u64> {
    let (e, m) = (sim.energies(), sim.total_momentum());
    [e.kinetic, e.strain, e.external_work, e.damping, m.x, m.y, m.z].into_iter().map(f64::to_bits).collect()
}

/// Parse and build a 3D scene (panics on error: for scenes the test itself wrote).
#[allow(dead_code)]
pub fn build_3d(text: &str) -> cramp::simulation::Simulation<cramp::dim::D3> {
    cramp::scene3d::Scene3::from_toml(text, "test scene", None).unwrap().build().unwrap()
}

/// The 12 outward-oriented triangles (right-hand rule) of the axis-aligned box
/// [min, max], in single precision as STL stores them.
#[allow(dead_code)]
pub fn box_triangles(min: [f32; 3], max: [f32; 3]) -> Vec<[[f32; 3]; 3]> {
    let corner = |i: usize| std::array::from_fn(|c| if (i >> c) & 1 == 1 { max[c] } else { min[c] });
    // Faces z = min, z = max, y = min, y = max, x = min, x = max as quads of corner indices
    // (bit c of the index set: coordinate c at max), each counter-clockwise seen from outside.
    let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    quads.iter().flat_map(|q| [[corner(q[0]), corner(q[1]), corner(q[2])], [corner(q[0]), corner(q[2]), corner(q[3])]]).collect()
}

/// Unit normal of a triangle by the right-hand rule (zero for a degenerate triangle).
fn stl_normal(t: &[[f32; 3]; 3]) -> [f32; 3] {
    let d = |a: [f32; 3], b: [f32; 3]| [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let (u, v) = (d(t[0], t[1]), d(t[0], t[2]));
    let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if l > 0.0 {
        n.map(|x| x / l)
    } else {
        [0.0; 3]
    }
}

/// An ASCII STL file of the triangles (written here by hand, independently of the reader).
#[allow(dead_code)]
pub fn ascii_stl(triangles: &[[[f32; 3]; 3]]) -> String {
    let mut s = String::from("solid test\n");
    for t in triangles {
        let n = stl_normal(t);
        s += &format!("  facet normal {:e} {:e} {:e}\n    outer loop\n", n[0], n[1], n[2]);
        for v in t {
            s += &format!("      vertex {:e} {:e} {:e}\n", v[0], v[1], v[2]);
        }
        s += "    endloop\n  endfacet\n";
    }
    s + "endsolid test\n"
}

/// A binary STL file of the triangles: 80-byte header, count, then per triangle the
/// normal and three vertices as little-endian f32 and a zero attribute word.
#[allow(dead_code)]
pub fn binary_stl(triangles: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut b = vec![b' '; 80];
    b[..12].copy_from_slice(b"binary cramp");
    b.extend((triangles.len() as u32).to_le_bytes());
    for t in triangles {
        for x in stl_normal(t).iter().chain(t.iter().flatten()) {
            b.extend(x.to_le_bytes());
        }
        b.extend([0u8, 0]);
    }
    b
}

/// A fresh directory under the target's temporary directory for one test.
#[allow(dead_code)]
pub fn temp_dir(name: &str) -> std::path::PathBuf {
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A 10 × 60 mm plane-strain plate (E = 1000 MPa, ν = 0.3, ρ = 1e−3 g/mm³) on 1 mm cells,
/// rollers on x = 0, without `[solver]` (tests/loaded_energy.rs, tests/checked_mode.rs).
#[allow(dead_code)]
pub const PLATE: &str = r#"
[grid]
origin = [-2.25, -32.0]
size = [14.0, 64.0]
cell = [1.0, 1.0]
[[materials]]
name = "m"
E = 1000.0
nu = 0.3
rho = 1.0e-3
state = "plane_strain"
[[bodies]]
material = "m"
shape = { rectangle = { min = [0.0, -30.0], max = [10.0, 30.0] } }
[[boundary]]
nodes = { region = { min = [-3.0, -32.0], max = [0.0, 32.0] } }
vx = 0.0
"#;

/// Grips for [`PLATE`]: the nodes beyond its top and bottom edges move apart at ±0.02 mm/ms.
#[allow(dead_code)]
pub const PLATE_GRIPS: &str = r#"
[[boundary]]
nodes = { region = { min = [-3.0, 30.0], max = [12.0, 32.0] } }
vy = 0.02
[[boundary]]
nodes = { region = { min = [-3.0, -32.0], max = [12.0, -30.0] } }
vy = -0.02
"#;
