//! Overrides of scene fields: `cramp run scene.toml --set grid.cell=[0.5,0.5]`.
//!
//! A sweep (cell size, particles per cell, shape, scheme, contour, …) is one scene file and
//! a list of overrides, not a copy of the file per variant. An override is `PATH=VALUE`:
//!
//! * `PATH` is a dotted path of keys from the top of the file; an integer segment indexes an
//!   array — an array of tables (`cracks.0.contact`, the first `[[cracks]]`) or a plain
//!   array (`grid.cell.1`). Every key but the last must exist, except that a missing
//!   table is created (`output.archive_interval=1` in a file without `[output]`); an index
//!   must be within the array, or equal to its length to append an element
//!   (`boundary.2={ nodes = { … }, vy = 0.0 }` to a file with two `[[boundary]]`).
//! * `VALUE` is a TOML value (`0.5`, `[0.5, 0.5]`, `"linear"`, `{ friction = { mu = 0.3 } }`,
//!   `true`); a bare word that is not a TOML value (`linear`) is taken as a string.
//!
//! The overridden file is then read exactly as a file is ([`crate::scene3d::AnyScene::from_toml`]):
//! same parsing, same validation, same messages. A bad path is an error naming the `--set`;
//! a value of the wrong type, or an unknown key, is the parser's message prefixed with the
//! `--set` that introduced it; a value that fails validation gets the validation message
//! with the `--set` that set the field appended (or, when no override set that field, the
//! list of overrides the scene was read with).

use crate::scene::SceneError;
use crate::scene3d::AnyScene;
use std::path::Path;

/// One `PATH=VALUE` override.
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    /// The dotted path, e.g. `cracks.0.contact`.
    pub path: String,
    pub value: toml::Value,
    /// The argument as given (`PATH=VALUE`), for messages and export headers.
    pub arg: String,
}

fn bad(arg: &str, message: impl Into<String>) -> SceneError {
    SceneError::Override { arg: arg.to_string(), message: message.into() }
}

impl Override {
    /// Parse `PATH=VALUE` (see the module documentation).
    pub fn parse(arg: &str) -> Result<Override, SceneError> {
        let Some((path, value)) = arg.split_once('=') else {
            return Err(bad(arg, "expected PATH=VALUE, e.g. grid.cell=[0.5, 0.5]"));
        };
        let path = path.trim();
        if path.is_empty() || path.split('.').any(|s| s.is_empty() || !s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')) {
            return Err(bad(arg, format!("`{path}` is not a dotted path of keys and indices (letters, digits, `_`, `-`), e.g. cracks.0.contact")));
        }
        let text = value.trim();
        let value = text;
        let parsed = format!("v = {value}").parse::<toml::Table>().ok().and_then(|mut t| t.remove("v"));
        let value = match parsed {
            Some(v) => v,
            None if !value.is_empty() && value.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') => toml::Value::String(value.to_string()),
            None => return Err(bad(arg, format!("`{value}` is not a TOML value (a number, \"string\", [array], {{ inline = table }} or true/false)"))),
        };
        Ok(Override { path: path.to_string(), value, arg: format!("{path}={text}") })
    }

    /// An override from a path and a value written as TOML (cases use this: the value is
    /// parsed exactly as on the command line).
    pub fn new(path: &str, value: impl std::fmt::Display) -> Result<Override, SceneError> {
        Override::parse(&format!("{path}={value}"))
    }

    /// Apply to a parsed file.
    pub fn apply(&self, table: &mut toml::Table) -> Result<(), SceneError> {
        let segments: Vec<&str> = self.path.split('.').collect();
        let mut node = TableOrArray::Table(table);
        for (k, seg) in segments.iter().enumerate() {
            let last = k + 1 == segments.len();
            let here = segments[..k].join(".");
            let at = if here.is_empty() { "the top of the scene".to_string() } else { format!("`{here}`") };
            node = match node {
                TableOrArray::Table(t) => {
                    if last {
                        t.insert(seg.to_string(), self.value.clone());
                        return Ok(());
                    }
                    let next_is_index = segments[k + 1].parse::<usize>().is_ok();
                    if !t.contains_key(*seg) {
                        if next_is_index {
                            return Err(bad(&self.arg, format!("{at} has no `{seg}` to index")));
                        }
                        t.insert(seg.to_string(), toml::Value::Table(toml::Table::new()));
                    }
                    descend(t.get_mut(*seg).expect("present"), &self.arg, &segments[..=k].join("."))?
                }
                TableOrArray::Array(a) => {
                    let Ok(i) = seg.parse::<usize>() else {
                        return Err(bad(&self.arg, format!("{at} is an array: `{seg}` must be an index 0..{}", a.len())));
                    };
                    if i > a.len() {
                        return Err(bad(&self.arg, format!("{at} has {} element(s); index {i} is out of range (index {} appends one)", a.len(), a.len())));
                    }
                    if last {
                        if i == a.len() {
                            a.push(self.value.clone());
                        } else {
                            a[i] = self.value.clone();
                        }
                        return Ok(());
                    }
                    if i == a.len() {
                        a.push(toml::Value::Table(toml::Table::new()));
                    }
                    descend(&mut a[i], &self.arg, &segments[..=k].join("."))?
                }
            };
        }
        unreachable!("the loop returns at the last segment")
    }

    /// Whether a validation error's field (`cracks[0].contact`, `grid.cell[1]`) lies under
    /// this override's path.
    fn covers(&self, field: &str) -> bool {
        let dotted = field.replace('[', ".").replace(']', "");
        dotted == self.path || dotted.starts_with(&format!("{}.", self.path))
    }
}

enum TableOrArray<'a> {
    Table(&'a mut toml::Table),
    Array(&'a mut Vec<toml::Value>),
}

fn descend<'a>(v: &'a mut toml::Value, arg: &str, path: &str) -> Result<TableOrArray<'a>, SceneError> {
    match v {
        toml::Value::Table(t) => Ok(TableOrArray::Table(t)),
        toml::Value::Array(a) => Ok(TableOrArray::Array(a)),
        other => Err(bad(arg, format!("`{path}` is a {}, not a table or an array", other.type_str()))),
    }
}

/// A scene text with overrides applied, as TOML text (the input of the usual parser).
/// Comments are not kept; `origin` names the file in errors.
pub fn apply_all(text: &str, origin: &str, overrides: &[Override]) -> Result<String, SceneError> {
    let mut table: toml::Table = text.parse().map_err(|e: toml::de::Error| SceneError::Parse { path: origin.to_string(), message: e.to_string() })?;
    for o in overrides {
        o.apply(&mut table)?;
    }
    Ok(toml::to_string(&table).expect("a TOML table serializes"))
}

/// Read a scene (2D or 3D) from text with overrides: the overridden text goes through
/// [`AnyScene::from_toml`], so validation and messages are those of a file; errors caused
/// by an override name it (see the module documentation).
pub fn scene_with(text: &str, origin: &str, base_dir: Option<&Path>, overrides: &[Override]) -> Result<AnyScene, SceneError> {
    if overrides.is_empty() {
        return AnyScene::from_toml(text, origin, base_dir);
    }
    let merged = apply_all(text, origin, overrides)?;
    match AnyScene::from_toml(&merged, origin, base_dir) {
        Ok(s) => Ok(s),
        Err(SceneError::Invalid { field, message }) => match overrides.iter().rev().find(|o| o.covers(&field)) {
            Some(o) => Err(SceneError::Invalid { field, message: format!("{message} (set by `--set {}`)", o.arg) }),
            // Not a field an override set (e.g. the dimension changed by a `grid.cell`
            // override): name every override the scene was read with.
            None => Err(SceneError::Invalid { field, message: format!("{message} (the scene read with {})", overrides.iter().map(|o| format!("`--set {}`", o.arg)).collect::<Vec<_>>().join(", ")) }),
        },
        Err(SceneError::Parse { path, message }) => {
            // Name the first override after which the text no longer parses (the file
            // alone may be fine).
            for k in 0..overrides.len() {
                let partial = apply_all(text, origin, &overrides[..=k])?;
                if let Err(SceneError::Parse { message, .. }) = parse_only(&partial, origin) {
                    return Err(bad(&overrides[k].arg, message));
                }
            }
            Err(SceneError::Parse { path, message })
        }
        Err(e) => Err(e),
    }
}

/// Parse without validating (to find which override breaks parsing).
fn parse_only(text: &str, origin: &str) -> Result<(), SceneError> {
    let parse = |message: String| SceneError::Parse { path: origin.to_string(), message };
    let value: toml::Value = toml::from_str(text).map_err(|e| parse(e.to_string()))?;
    match crate::scene3d::detect_dimension(&value).map_err(parse)? {
        3 => toml::from_str::<crate::scene3d::Scene3>(text).map(drop).map_err(|e| parse(e.to_string())),
        _ => toml::from_str::<crate::scene::Scene>(text).map(drop).map_err(|e| parse(e.to_string())),
    }
}

/// [`scene_with`] for a file.
pub fn scene_file_with(path: &Path, overrides: &[Override]) -> Result<AnyScene, SceneError> {
    let text = std::fs::read_to_string(path).map_err(|e| SceneError::Io { path: path.display().to_string(), source: e })?;
    scene_with(&text, &path.display().to_string(), path.parent(), overrides)
}

#[cfg(test)]
mod tests {
    use super::*;

    const BAR: &str = include_str!("../verification/vibrating_bar.toml");

    fn d2(s: AnyScene) -> crate::scene::Scene {
        match s {
            AnyScene::D2(s) => s,
            AnyScene::D3(_) => panic!("2D expected"),
        }
    }

    fn set(args: &[&str]) -> Vec<Override> {
        args.iter().map(|a| Override::parse(a).unwrap()).collect()
    }

    #[test]
    fn overrides_set_values_at_dotted_paths() {
        let s = d2(scene_with(BAR, "bar", None, &set(&["grid.cell=[0.5, 0.5]", "solver.shape=linear", "boundary.1.vy=0.0", "output.archive_interval=2"])).unwrap());
        assert_eq!(s.grid.cell, [0.5, 0.5]);
        assert_eq!(s.solver.shape, crate::shape::ShapeKind::Linear);
        assert_eq!(s.output.archive_interval, Some(2.0));
        let s = d2(scene_with(BAR, "bar", None, &set(&["grid.cell.1=0.5"])).unwrap());
        assert_eq!(s.grid.cell, [1.0, 0.5]);
        // Index = length appends a table to an array of tables.
        let s = d2(scene_with(BAR, "bar", None, &set(&["boundary.3={ nodes = { line = { from = [25.0, 0.0], to = [25.0, 2.0] } }, vy = 0.0 }", "boundary.4.nodes.line={ from = [0.0, 1.0], to = [1.0, 1.0] }", "boundary.4.vx=0.0"])).unwrap());
        assert_eq!(s.boundary.len(), 5);
        assert_eq!(s.boundary[4].vx, Some(crate::motion::Component::Number(0.0)));
        // No override: the file as is.
        assert_eq!(d2(scene_with(BAR, "bar", None, &[]).unwrap()), d2(AnyScene::from_toml(BAR, "bar", None).unwrap()));
    }

    #[test]
    fn bad_overrides_name_the_flag() {
        let err = |args: &[&str]| match args.iter().map(|a| Override::parse(a)).collect::<Result<Vec<_>, _>>() {
            Err(e) => e.to_string(),
            Ok(o) => scene_with(BAR, "bar.toml", None, &o).unwrap_err().to_string(),
        };
        assert!(err(&["grid.cell"]).contains("--set grid.cell"), "{}", err(&["grid.cell"]));
        assert!(err(&["grid..cell=1"]).contains("dotted path"));
        assert!(err(&["boundary.7.vx=0"]).contains("has 3 element(s); index 7 is out of range"), "{}", err(&["boundary.7.vx=0"]));
        assert!(err(&["grid.cell.x=1"]).contains("must be an index"));
        assert!(err(&["cracks.0.contact=none"]).contains("no `cracks` to index"));
        assert!(err(&["solver.cfl.x=1"]).contains("`solver.cfl` is a float"), "{}", err(&["solver.cfl.x=1"]));
        assert!(err(&["grid.cell=[1, 1"]).contains("is not a TOML value"));
        // Wrong type and unknown key: the parser's message, naming the --set.
        let e = err(&["solver.cfl=[1, 2]"]);
        assert!(e.contains("--set solver.cfl=[1, 2]") && e.contains("cfl"), "{e}");
        let e = err(&["solver.speed=2"]);
        assert!(e.contains("--set solver.speed=2") && e.contains("unknown field"), "{e}");
        // Validation: the file's message, with the --set that set the field.
        let e = err(&["materials.0.nu=0.5"]);
        assert!(e.contains("materials[0].nu") && e.contains("Poisson") && e.contains("set by `--set materials.0.nu=0.5`"), "{e}");
        let e = err(&["grid.cell=[-1.0, 1.0]"]);
        assert!(e.contains("grid.cell[0]") && e.contains("set by `--set grid.cell=[-1.0, 1.0]`"), "{e}");
    }
}
