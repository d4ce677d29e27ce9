//! Scenes shared by several test files (each file under tests/ is its own crate; this
//! module is included with `mod common;`).

/// A 20 × 4 mm block pressed onto a fixed 36 × 4 mm base across a horizontal crack on
/// y = 0 and pushed sideways: total `force` (x, y) on the block's particles, ramped over
/// `ramp`; the crack's `contact` law as TOML (e.g. `"none"` or
/// `{ friction = { mu = 0.3 } }`). E = 0.1 MPa, ν = 0.33, ρ = 1.5 g/cm³, plane stress,
/// 1 mm cells, uGIMP, USAVG, checked (units mm, g, ms).
#[allow(dead_code)]
pub fn block_on_crack(force: [f64; 2], ramp: f64, end_time: f64, contact: &str) -> String {
    let points: Vec<String> = (0..40).map(|i| format!("[{}, 0.0]", -9.5 + i as f64)).collect();
    format!(
        r#"
title = "block sliding on a crack face"
[grid]
origin = [-10.0, -6.0]
size = [40.0, 12.0]
cell = [1.0, 1.0]
[solver]
end_time = {end_time}
[[materials]]
name = "m"
E = 0.1
nu = 0.33
rho = 1.5e-3
state = "plane_stress"
[[bodies]]
material = "m"
shape = {{ rectangle = {{ min = [0.0, 0.0], max = [20.0, 4.0] }} }}
[[bodies]]
material = "m"
shape = {{ rectangle = {{ min = [-8.0, -4.0], max = [28.0, 0.0] }} }}
[[boundary]]
nodes = {{ region = {{ min = [-10.0, -6.0], max = [30.0, -3.0] }} }}
vx = 0.0
vy = 0.0
[[loads]]
particles = {{ region = {{ min = [0.0, 0.0], max = [20.0, 4.0] }} }}
force = [{fx}, {fy}]
ramp = {ramp}
[[cracks]]
points = [{p}]
contact = {contact}
"#,
        fx = force[0],
        fy = force[1],
        p = points.join(", ")
    )
}
