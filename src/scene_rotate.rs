//! `rotate = { angle = θ, about = [x, y] }` of a 2D scene: the whole scene turned about a
//! point while the grid stays (issue 20 item 1, the rotation-invariance case).
//!
//! A user checks that an answer does not depend on how the body sits on the grid by
//! running the same file with `--set 'rotate = { angle = 30.0, about = [10.0, 0.0] }'`;
//! the case `rotation` does this for the fracture scenes. The rotation is applied when the
//! file is read ([`crate::scene::Scene::from_toml`]), before validation, so a rotated body
//! that leaves the grid is refused as any other, and the scene that runs (and that
//! `cramp verify --export` writes, with the `rotate` table in it) is exactly the rotated
//! one. Counter-clockwise, degrees; with R the rotation and c = `about`:
//!
//! | entity | rotated as |
//! |---|---|
//! | points: polygon and crack points, disk centres, `line` ends, probe ends, a `velocity_sine` origin, a Williams tip | c + R(x − c) |
//! | vectors: `velocity`, `body_force`, load `force` and `normal`, sine amplitude and wave vector | R v |
//! | `rectangle` body | the polygon of its four rotated corners |
//! | `region` selection | the polygon of its four rotated corners (inclusive, as the box) |
//! | boundary `vx`+`vy`, `ux`+`uy` (numbers) | the rotated vector |
//! | Williams `angle` | + θ |
//!
//! What cannot be rotated is refused, naming the field: a boundary that prescribes one
//! component only (a roller: its direction would no longer be a grid axis, and cramp
//! prescribes grid components), expressions of position (their variables are grid
//! coordinates), and tractions (a traction's per-particle shares are exact only on
//! grid-aligned edges: docs/scene.md; give the total `force` instead). An angle of 0
//! leaves the scene unchanged to the bit.

use crate::motion::Component;
use crate::scene::{Scene, SceneError, Selection, ShapeSpec};
use serde::{Deserialize, Serialize};

/// `rotate = { angle, about }`.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RotateSpec {
    /// Counter-clockwise angle in degrees.
    pub angle: f64,
    /// Centre of the rotation.
    pub about: [f64; 2],
}

fn invalid(field: impl Into<String>, message: impl Into<String>) -> SceneError {
    SceneError::Invalid { field: field.into(), message: message.into() }
}

/// The rotation x ↦ c + R(x − c).
#[derive(Clone, Copy)]
struct Rotation {
    cos: f64,
    sin: f64,
    c: [f64; 2],
}

impl Rotation {
    fn vector(&self, v: [f64; 2]) -> [f64; 2] {
        [self.cos * v[0] - self.sin * v[1], self.sin * v[0] + self.cos * v[1]]
    }

    fn point(&self, x: [f64; 2]) -> [f64; 2] {
        let r = self.vector([x[0] - self.c[0], x[1] - self.c[1]]);
        [self.c[0] + r[0], self.c[1] + r[1]]
    }

    fn corners(&self, min: [f64; 2], max: [f64; 2]) -> Vec<[f64; 2]> {
        [[min[0], min[1]], [max[0], min[1]], [max[0], max[1]], [min[0], max[1]]].into_iter().map(|p| self.point(p)).collect()
    }

    fn selection(&self, s: &Selection) -> Selection {
        match s {
            Selection::Region { min, max } => Selection::Polygon { points: self.corners(*min, *max) },
            Selection::Line { from, to } => Selection::Line { from: self.point(*from), to: self.point(*to) },
            Selection::Polygon { points } => Selection::Polygon { points: points.iter().map(|&p| self.point(p)).collect() },
        }
    }

    /// A pair of components given as numbers, rotated; one alone or an expression is refused.
    fn pair(&self, field: &str, names: [&str; 2], x: &mut Option<Component>, y: &mut Option<Component>) -> Result<(), SceneError> {
        match (x.as_ref(), y.as_ref()) {
            (None, None) => Ok(()),
            (Some(Component::Number(a)), Some(Component::Number(b))) => {
                let r = self.vector([*a, *b]);
                *x = Some(Component::Number(r[0]));
                *y = Some(Component::Number(r[1]));
                Ok(())
            }
            (Some(_), Some(_)) => Err(invalid(
                format!("{field}.{}", names[0]),
                "a rotated scene (`rotate`) takes numbers here, not expressions (their x, y are grid coordinates)",
            )),
            (Some(_), None) | (None, Some(_)) => {
                let given = if x.is_some() { names[0] } else { names[1] };
                Err(invalid(
                    format!("{field}.{given}"),
                    format!(
                        "a rotated scene (`rotate`) cannot hold one component only: after the rotation a roller's direction is no longer a grid axis; give both `{}` and `{}` (e.g. 0 and 0 for a clamp) or leave the support out",
                        names[0], names[1]
                    ),
                ))
            }
        }
    }
}

/// The scene turned by its `rotate` table (and the table removed); the scene itself when
/// it has none or the angle is 0.
pub fn apply(mut scene: Scene) -> Result<Scene, SceneError> {
    let Some(spec) = scene.rotate.take() else { return Ok(scene) };
    if !spec.angle.is_finite() || spec.about.iter().any(|a| !a.is_finite()) {
        return Err(invalid("rotate", format!("angle and about must be finite numbers, got angle = {}, about = {:?}", spec.angle, spec.about)));
    }
    if spec.angle == 0.0 {
        return Ok(scene);
    }
    let (sin, cos) = spec.angle.to_radians().sin_cos();
    let r = Rotation { cos, sin, c: spec.about };
    for b in &mut scene.bodies {
        b.shape = match &b.shape {
            ShapeSpec::Rectangle { min, max } => ShapeSpec::Polygon { points: r.corners(*min, *max) },
            ShapeSpec::Disk { center, radius } => ShapeSpec::Disk { center: r.point(*center), radius: *radius },
            ShapeSpec::Polygon { points } => ShapeSpec::Polygon { points: points.iter().map(|&p| r.point(p)).collect() },
        };
        b.velocity = r.vector(b.velocity);
        b.body_force = r.vector(b.body_force);
        if let Some(s) = &mut b.velocity_sine {
            s.amplitude = r.vector(s.amplitude);
            s.k = r.vector(s.k);
            s.origin = r.point(s.origin);
        }
    }
    for (i, b) in scene.boundary.iter_mut().enumerate() {
        let field = format!("boundary[{i}]");
        b.nodes = r.selection(&b.nodes);
        r.pair(&field, ["vx", "vy"], &mut b.vx, &mut b.vy)?;
        r.pair(&field, ["ux", "uy"], &mut b.ux, &mut b.uy)?;
        if let Some(w) = &mut b.williams {
            let tip = w.tip.get(..2).and_then(|t| <[f64; 2]>::try_from(t).ok()).ok_or_else(|| invalid(format!("{field}.williams.tip"), "needs [x, y]"))?;
            let t = r.point(tip);
            w.tip[0] = t[0];
            w.tip[1] = t[1];
            w.angle += spec.angle;
        }
    }
    for (i, l) in scene.loads.iter_mut().enumerate() {
        if l.traction.is_some() {
            return Err(invalid(
                format!("loads[{i}].traction"),
                "a rotated scene (`rotate`) cannot take a traction: its per-particle shares of the edge are exact only on grid-aligned edges; give the total `force` instead",
            ));
        }
        l.particles = r.selection(&l.particles);
        l.force = l.force.map(|f| r.vector(f));
        l.normal = l.normal.map(|n| r.vector(n));
    }
    for c in &mut scene.cracks {
        for p in &mut c.points {
            *p = r.point(*p);
        }
    }
    for p in &mut scene.probes {
        p.from = r.point(p.from);
        p.to = r.point(p.to);
    }
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SCENE: &str = r#"
[grid]
origin = [-30.0, -30.0]
size = [60.0, 60.0]
cell = [1.0, 1.0]
[solver]
end_time = 0.1
[[materials]]
name = "m"
E = 1000.0
nu = 0.3
rho = 1e-3
state = "plane_strain"
[[bodies]]
material = "m"
shape = { rectangle = { min = [0.0, -10.0], max = [10.0, 10.0] } }
velocity = [1.0, 0.0]
[[boundary]]
nodes = { region = { min = [-1.0, -10.0], max = [0.0, 10.0] } }
vx = 0.0
vy = 0.0
[[loads]]
particles = { region = { min = [0.0, 9.5], max = [10.0, 10.0] } }
force = [0.0, 2.0]
[[cracks]]
points = [[-1.0, 0.0], [4.5, 0.0]]
"#;

    #[test]
    fn quarter_turn_maps_every_entity() {
        let s = Scene::from_toml(&format!("rotate = {{ angle = 90.0, about = [0.0, 0.0] }}\n{SCENE}"), "test").unwrap();
        assert!(s.rotate.is_none());
        let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12;
        let ShapeSpec::Polygon { points } = &s.bodies[0].shape else { panic!("rectangle → polygon") };
        assert!(close(points[0], [10.0, 0.0]) && close(points[2], [-10.0, 10.0]));
        assert!(close(s.bodies[0].velocity, [0.0, 1.0]));
        assert!(close(s.loads[0].force.unwrap(), [-2.0, 0.0]));
        assert!(close(s.cracks[0].points[1], [0.0, 4.5]));
        let Selection::Polygon { points } = &s.boundary[0].nodes else { panic!("region → polygon") };
        assert!(close(points[0], [10.0, -1.0]));
    }

    #[test]
    fn zero_angle_is_the_same_scene() {
        let plain = Scene::from_toml(SCENE, "test").unwrap();
        let turned = Scene::from_toml(&format!("rotate = {{ angle = 0.0, about = [3.0, 1.0] }}\n{SCENE}"), "test").unwrap();
        assert_eq!(plain, turned);
    }

    #[test]
    fn a_roller_is_refused_naming_the_field() {
        let text = format!("rotate = {{ angle = 30.0, about = [0.0, 0.0] }}\n{}", SCENE.replace("vy = 0.0\n", ""));
        let e = Scene::from_toml(&text, "test").unwrap_err().to_string();
        assert!(e.contains("boundary[0].vx") && e.contains("one component"), "{e}");
    }
}
