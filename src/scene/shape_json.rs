//! Reading an obstacle ([`Shape`]) from a scene, with its values checked.
//!
//! A derived internally tagged enum buffers the whole object before it
//! looks at the `"type"`, so a bad value inside would be reported at the end
//! of the object. This reader takes the keys in any order and checks each
//! value as it is read, so the error points at the value itself:
//! - `center` and `point`: three numbers;
//! - `radius` (sphere): above 0;
//! - `normal` (plane): three numbers, not all 0 (it is normalized);
//! - `half_extents` (box): three numbers above 0.
//!
//! A key the shape does not have, a missing key or an unknown `"type"` is an
//! error at the object.

use std::fmt;

use serde::de::{Deserialize, Deserializer, Error, MapAccess, SeqAccess, Visitor};

use crate::checked;
use crate::rod::obstacle::Shape;
use crate::rod::trimesh::TriMesh;
use std::sync::Arc;

const KEYS: &[&str] = &[
    "type",
    "center",
    "radius",
    "point",
    "normal",
    "half_extents",
    "axis",
    "path",
    "scale",
    "translate",
];

thread_local! {
    /// The folder a mesh's `path` is relative to: the scene file's, while
    /// `scene::parse_params` reads it (the current folder otherwise).
    pub(super) static BASE_DIR: std::cell::RefCell<std::path::PathBuf> = std::cell::RefCell::new(std::path::PathBuf::new());
}

/// Reads the OBJ file of a mesh obstacle.
fn load_mesh(path: &str, scale: f64, translate: [f64; 3]) -> Result<TriMesh, String> {
    let full = BASE_DIR.with(|b| b.borrow().join(path));
    let text = std::fs::read_to_string(&full).map_err(|e| format!("cannot read mesh {}: {e}", full.display()))?;
    TriMesh::from_obj(&text, scale, nalgebra::Vector3::from(translate))
        .map_err(|e| format!("mesh {}: {e}", full.display()))
}

/// Which check the three numbers of an array get.
#[derive(Clone, Copy)]
enum Three {
    Any,
    Positive,
    NonZero,
}

impl<'de> serde::de::DeserializeSeed<'de> for Three {
    type Value = [f64; 3];

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<[f64; 3], D::Error> {
        d.deserialize_seq(self)
    }
}

/// One number of an array, checked for `Three::Positive`.
struct Item(Three);

impl<'de> serde::de::DeserializeSeed<'de> for Item {
    type Value = f64;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<f64, D::Error> {
        match self.0 {
            Three::Positive => checked::positive(d),
            Three::Any | Three::NonZero => checked::number(d),
        }
    }
}

impl<'de> Visitor<'de> for Three {
    type Value = [f64; 3];

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(match self {
            Three::Any => "an array of three numbers",
            Three::Positive => "an array of three numbers above 0",
            Three::NonZero => "an array of three numbers, not all 0",
        })
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<[f64; 3], A::Error> {
        let mut out = [0.0; 3];
        for (i, slot) in out.iter_mut().enumerate() {
            *slot = seq
                .next_element_seed(Item(self))?
                .ok_or_else(|| A::Error::invalid_length(i, &self))?;
        }
        if seq.next_element::<serde::de::IgnoredAny>()?.is_some() {
            return Err(A::Error::invalid_length(4, &self));
        }
        if matches!(self, Three::NonZero) && out.iter().all(|v| *v == 0.0) {
            return Err(A::Error::custom("expected a direction, got [0, 0, 0]"));
        }
        Ok(out)
    }
}

struct Radius(f64);

impl<'de> Deserialize<'de> for Radius {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        checked::positive(d).map(Radius)
    }
}

#[derive(serde::Deserialize)]
#[serde(rename_all = "snake_case")]
enum Type {
    Sphere,
    Plane,
    Box,
    Cylinder,
    Mesh,
}

struct ShapeVisitor;

fn once<T, E: Error>(slot: &mut Option<T>, value: T, key: &'static str) -> Result<(), E> {
    if slot.is_some() {
        return Err(E::duplicate_field(key));
    }
    *slot = Some(value);
    Ok(())
}

impl<'de> Visitor<'de> for ShapeVisitor {
    type Value = Shape;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("an obstacle object with a \"type\" (sphere, plane, box, cylinder or mesh)")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Shape, A::Error> {
        let mut kind = None;
        let (mut center, mut radius, mut point, mut normal, mut half) = (None, None, None, None, None);
        let (mut axis, mut path, mut scale, mut translate) = (None, None, None, None);
        let mut given: Vec<&'static str> = Vec::new();
        while let Some(key) = map.next_key::<String>()? {
            match key.as_str() {
                "type" => once(&mut kind, map.next_value::<Type>()?, "type")?,
                "center" => once(&mut center, map.next_value_seed(Three::Any)?, "center")?,
                "radius" => once(&mut radius, map.next_value::<Radius>()?.0, "radius")?,
                "point" => once(&mut point, map.next_value_seed(Three::Any)?, "point")?,
                "normal" => once(&mut normal, map.next_value_seed(Three::NonZero)?, "normal")?,
                "half_extents" => once(&mut half, map.next_value_seed(Three::Positive)?, "half_extents")?,
                "axis" => once(&mut axis, map.next_value_seed(Three::NonZero)?, "axis")?,
                "path" => once(&mut path, map.next_value::<String>()?, "path")?,
                "scale" => once(&mut scale, map.next_value::<Radius>()?.0, "scale")?,
                "translate" => once(&mut translate, map.next_value_seed(Three::Any)?, "translate")?,
                other => return Err(A::Error::unknown_field(other, KEYS)),
            }
            given.extend(KEYS.iter().find(|k| **k == key));
        }
        let kind = kind.ok_or_else(|| A::Error::missing_field("type"))?;
        let (name, keys): (&str, &[&str]) = match kind {
            Type::Sphere => ("sphere", &["type", "center", "radius"]),
            Type::Plane => ("plane", &["type", "point", "normal"]),
            Type::Box => ("box", &["type", "center", "half_extents"]),
            Type::Cylinder => ("cylinder", &["type", "point", "axis", "radius"]),
            Type::Mesh => ("mesh", &["type", "path", "scale", "translate"]),
        };
        if let Some(extra) = given.iter().find(|k| !keys.contains(k)) {
            return Err(A::Error::custom(format!(
                "a {name} has no `{extra}` (its keys are {})",
                keys.join(", ")
            )));
        }
        let need = |v: Option<[f64; 3]>, key| v.ok_or_else(|| A::Error::missing_field(key));
        Ok(match kind {
            Type::Sphere => Shape::Sphere {
                center: need(center, "center")?,
                radius: radius.ok_or_else(|| A::Error::missing_field("radius"))?,
            },
            Type::Plane => Shape::Plane {
                point: need(point, "point")?,
                normal: need(normal, "normal")?,
            },
            Type::Box => Shape::Box {
                center: need(center, "center")?,
                half_extents: need(half, "half_extents")?,
            },
            Type::Cylinder => Shape::Cylinder {
                point: need(point, "point")?,
                axis: need(axis, "axis")?,
                radius: radius.ok_or_else(|| A::Error::missing_field("radius"))?,
            },
            Type::Mesh => {
                let path = path.ok_or_else(|| A::Error::missing_field("path"))?;
                let (scale, translate) = (scale.unwrap_or(1.0), translate.unwrap_or([0.0; 3]));
                let mesh = load_mesh(&path, scale, translate).map_err(A::Error::custom)?;
                Shape::Mesh {
                    path,
                    scale,
                    translate,
                    mesh: Arc::new(mesh),
                }
            }
        })
    }
}

impl<'de> Deserialize<'de> for Shape {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_map(ShapeVisitor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Shape, serde_json::Error> {
        serde_json::from_str(text)
    }

    #[test]
    fn every_shape_reads_back_what_it_writes() {
        for s in [
            Shape::Sphere {
                center: [0.0, 1.0, -2.0],
                radius: 0.5,
            },
            Shape::Plane {
                point: [0.0; 3],
                normal: [0.0, 0.0, 1.0],
            },
            Shape::Box {
                center: [1.0, 2.0, 3.0],
                half_extents: [0.1, 0.2, 0.3],
            },
        ] {
            let text = serde_json::to_string(&s).unwrap();
            assert_eq!(read(&text).unwrap(), s, "{text}");
        }
        // Keys in any order, the type last.
        let s = read(r#"{"radius": 2, "center": [0, 0, 0], "type": "sphere"}"#).unwrap();
        assert!(matches!(s, Shape::Sphere { radius, .. } if radius == 2.0));
    }

    #[test]
    fn bad_values_are_errors_at_the_value() {
        for (text, column, words) in [
            (
                r#"{"type": "sphere", "center": [0, 0, 0], "radius": -1}"#,
                53,
                "above 0",
            ),
            (r#"{"type": "sphere", "radius": 0, "center": [0, 0, 0]}"#, 30, "above 0"),
            (
                r#"{"type": "plane", "normal": [0, 0, 0], "point": [0, 0, 0]}"#,
                37,
                "[0, 0, 0]",
            ),
            (
                r#"{"type": "box", "half_extents": [1, 0, 1], "center": [0, 0, 0]}"#,
                39,
                "above 0",
            ),
            (r#"{"type": "sphere", "radius": "nan", "center": [0, 0, 0]}"#, 34, "NaN"),
            (
                r#"{"type": "sphere", "radius": true, "center": [0, 0, 0]}"#,
                33,
                "expected a number",
            ),
            (
                r#"{"type": "sphere", "center": [0, 0], "radius": 1}"#,
                35,
                "three numbers",
            ),
        ] {
            let e = read(text).unwrap_err();
            assert_eq!((e.line(), e.column()), (1, column), "{text}: {e}");
            assert!(e.to_string().contains(words), "{text}: {e}");
        }
    }

    #[test]
    fn keys_must_fit_the_type() {
        for (text, words) in [
            (
                r#"{"type": "plane", "point": [0, 0, 0], "normal": [0, 0, 1], "radius": 1}"#,
                "no `radius`",
            ),
            (r#"{"type": "sphere", "center": [0, 0, 0]}"#, "missing field `radius`"),
            (r#"{"center": [0, 0, 0], "radius": 1}"#, "missing field `type`"),
            (r#"{"type": "cone"}"#, "unknown variant `cone`"),
            (
                r#"{"type": "cylinder", "point": [0, 0, 0], "radius": 1}"#,
                "missing field `axis`",
            ),
            (r#"{"type": "mesh", "path": "no-such-file.obj"}"#, "cannot read mesh"),
            (r#"{"type": "sphere", "colour": 1}"#, "unknown field `colour`"),
            (r#"{"type": "sphere", "type": "box"}"#, "duplicate field `type`"),
        ] {
            let e = read(text).unwrap_err();
            assert!(e.to_string().contains(words) && e.line() == 1, "{text}: {e}");
        }
    }
}
