//! Scenes: what to simulate around a fabric, and with which parameters.
//!
//! A scene is data (JSON), so a run is reproducible from its files alone.
//! Obstacles are signed distance fields with a stiff penalty; a scene that
//! has none costs nothing for them (no stencils are built). The obstacle
//! energy itself is `rod::obstacle`.

pub use crate::rod::obstacle::{ObstaclePenalty, Shape};

use crate::sim::{SimParams, YarnRadii};
use crate::topology::Fabric;
use std::path::Path;

#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("cannot read scene file {path}")]
    Read { path: String, source: std::io::Error },
    #[error("{path}:{line}:{column}: {message}")]
    Parse {
        path: String,
        line: usize,
        column: usize,
        message: String,
    },
    #[error("{path}: {message}")]
    Invalid { path: String, message: String },
}

/// Reads simulation parameters from a JSON scene file. Missing keys keep
/// their defaults; unknown keys, malformed JSON and non-finite or negative
/// stiffnesses are errors naming the file, line and column.
pub fn load_params(path: &Path) -> Result<SimParams, SceneError> {
    parse_params(&read_scene(path)?, path)
}

fn read_scene(path: &Path) -> Result<String, SceneError> {
    std::fs::read_to_string(path).map_err(|source| SceneError::Read {
        path: path.display().to_string(),
        source,
    })
}

/// [`load_params`] on the text of the scene file `path`.
fn parse_params(text: &str, path: &Path) -> Result<SimParams, SceneError> {
    let p = path.display().to_string();
    let params: SimParams = serde_json::from_str(text).map_err(|e| SceneError::Parse {
        path: p.clone(),
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })?;
    let (r, a) = (&params.rod, &params.assign);
    for (name, v) in [
        ("rod.ks", r.ks),
        ("rod.kb", r.kb),
        ("rod.rho", r.rho),
        ("rod.radius", r.radius),
        ("rod.kf", r.kf),
        ("rod.mu", r.mu),
        ("assign.safety_fraction", a.safety_fraction),
        ("assign.release_fraction", a.release_fraction),
        ("assign.stop_fraction", a.stop_fraction),
        ("assign.close_fraction", a.close_fraction),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(SceneError::Invalid {
                path: p,
                message: format!("{name} must be a finite non-negative number, got {v}"),
            });
        }
    }
    // A point stopped, or a segment tripped, outside the safety distance
    // would not be handed to EIL by the next re-assignment: a stop would
    // hold it forever, a tripwire would end every step at once.
    for (name, v, why) in [
        ("stop_fraction", a.stop_fraction, "a stopped point"),
        ("close_fraction", a.close_fraction, "a closed segment"),
    ] {
        if v >= a.safety_fraction && v > 0.0 {
            return Err(SceneError::Invalid {
                path: p,
                message: format!(
                    "assign.{name} ({v}) must be below assign.safety_fraction ({}): {why} outside the \
                     safety distance would never be handed to EIL",
                    a.safety_fraction
                ),
            });
        }
    }
    if let Some(sep) = &params.separation {
        if !(sep.min_pull.is_finite() && sep.min_pull >= 0.0) {
            return Err(SceneError::Invalid {
                path: p,
                message: format!(
                    "separation.min_pull must be a finite non-negative force (N), got {}",
                    sep.min_pull
                ),
            });
        }
    }
    Ok(params)
}

/// The radius of a fabric's thickest yarn (the pattern's `radius`), if any
/// yarn declares a positive finite one.
pub fn fabric_radius(fabric: &Fabric) -> Option<f64> {
    let r = fabric
        .meta
        .yarns
        .iter()
        .map(|y| y.radius)
        .filter(|r| r.is_finite() && *r > 0.0)
        .fold(0.0, f64::max);
    (r > 0.0).then_some(r)
}

/// The parameters to simulate `fabric` with: the scene's keys over the
/// defaults, and the fabric's own yarn radii unless the scene sets
/// `rod.radius`. The radii set the parallel-contact distance, the secured
/// ends' stop, the clearance over obstacles and the contact thickness, so
/// a pattern's yarns should set them:
///
/// - no `rod.radius` in the scene: every yarn has its own radius
///   ([`YarnRadii::Pattern`]), and `rod.radius` is the thickest (see
///   [`fabric_radius`]), which sets the one thickness of non-persistent
///   contact;
/// - `rod.radius` in the scene: that radius for every yarn
///   ([`YarnRadii::Uniform`]), unless the scene also sets `"radii"`.
pub fn params_for(fabric: &Fabric, scene: Option<&Path>) -> Result<SimParams, SceneError> {
    let (mut params, scene_radius, scene_radii) = match scene {
        None => (SimParams::default(), false, false),
        Some(path) => {
            let text = read_scene(path)?;
            let params = parse_params(&text, path)?;
            // The typed parse succeeded, so this one does too.
            let value: serde_json::Value = serde_json::from_str(&text).unwrap_or_default();
            let has = |key| value.pointer(key).is_some();
            (params, has("/rod/radius"), has("/radii"))
        }
    };
    if scene_radius {
        return Ok(params);
    }
    if let Some(r) = fabric_radius(fabric) {
        params.rod.radius = r;
    }
    if !scene_radii {
        params.radii = YarnRadii::Pattern;
    }
    Ok(params)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fabric_of_radius(radius: f64) -> Fabric {
        let mut f = crate::io::fixtures::crossing();
        for y in &mut f.meta.yarns {
            y.radius = radius;
        }
        f
    }

    #[test]
    fn the_fabric_sets_the_radius_unless_the_scene_does() {
        let f = fabric_of_radius(0.6e-3);
        let p = params_for(&f, None).unwrap();
        assert_eq!((p.rod.radius, p.radii), (0.6e-3, YarnRadii::Pattern));
        let dir = tempfile::tempdir().unwrap();
        let other = dir.path().join("other.json");
        std::fs::write(&other, r#"{"rod": {"ks": 50.0}}"#).unwrap();
        let p = params_for(&f, Some(&other)).unwrap();
        assert_eq!((p.rod.radius, p.rod.ks, p.radii), (0.6e-3, 50.0, YarnRadii::Pattern));
        // The scene's radius is every yarn's radius...
        let own = dir.path().join("own.json");
        std::fs::write(&own, r#"{"rod": {"radius": 0.001}}"#).unwrap();
        let p = params_for(&f, Some(&own)).unwrap();
        assert_eq!((p.rod.radius, p.radii), (0.001, YarnRadii::Uniform));
        // ...unless the scene asks for the pattern's radii too.
        std::fs::write(&own, r#"{"rod": {"radius": 0.001}, "radii": "pattern"}"#).unwrap();
        let p = params_for(&f, Some(&own)).unwrap();
        assert_eq!((p.rod.radius, p.radii), (0.001, YarnRadii::Pattern));
        // One radius for all, the fabric's thickest.
        std::fs::write(&own, r#"{"radii": "uniform"}"#).unwrap();
        let p = params_for(&f, Some(&own)).unwrap();
        assert_eq!((p.rod.radius, p.radii), (0.6e-3, YarnRadii::Uniform));
        // A fabric without a usable radius keeps the default.
        let bare = fabric_of_radius(f64::NAN);
        assert_eq!(
            params_for(&bare, None).unwrap().rod.radius,
            SimParams::default().rod.radius
        );
        // A broken scene is still an error.
        std::fs::write(&own, "{").unwrap();
        assert!(params_for(&f, Some(&own)).is_err());
    }

    fn load(text: &str) -> (Result<SimParams, SceneError>, String) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("scene.json");
        std::fs::write(&path, text).unwrap();
        (load_params(&path), path.display().to_string())
    }

    #[test]
    fn missing_keys_keep_their_defaults() {
        let (p, _) = load(r#"{"rod": {"ks": 50.0}, "separation": {}}"#);
        let p = p.unwrap();
        assert_eq!(p.rod.ks, 50.0);
        assert_eq!(p.rod.kb, SimParams::default().rod.kb);
        assert_eq!(p.separation, Some(crate::sim::SeparationParams::default()));
    }

    #[test]
    fn malformed_json_and_unknown_keys_name_file_line_and_column() {
        for (text, line, column) in [
            ("{\n  \"rod\": {\"ks\": 1.0,}\n}", 2, 21),
            ("{\n  \"separation\": {\"min_pul\": 1}\n}", 2, 26),
        ] {
            let (r, path) = load(text);
            let e = r.unwrap_err();
            assert!(
                matches!(&e, SceneError::Parse { line: l, column: c, .. } if (*l, *c) == (line, column)),
                "{e:?}"
            );
            assert!(e.to_string().starts_with(&format!("{path}:{line}:{column}: ")), "{e}");
        }
    }

    #[test]
    fn negative_or_non_finite_values_are_refused() {
        for (text, key) in [
            (r#"{"rod": {"ks": -1.0}}"#, "rod.ks"),
            (r#"{"separation": {"min_pull": -0.1}}"#, "separation.min_pull"),
            (r#"{"assign": {"stop_fraction": -0.05}}"#, "assign.stop_fraction"),
            (r#"{"assign": {"stop_fraction": 0.1}}"#, "assign.stop_fraction"),
            (r#"{"assign": {"close_fraction": -1e-5}}"#, "assign.close_fraction"),
            (r#"{"assign": {"close_fraction": 0.2}}"#, "assign.close_fraction"),
        ] {
            let (r, path) = load(text);
            let e = r.unwrap_err().to_string();
            assert!(e.starts_with(&path) && e.contains(key), "{e}");
        }
        // JSON has no NaN or infinity: an out-of-range number is a parse error.
        assert!(matches!(
            load(r#"{"rod": {"kb": 1e999}}"#).0,
            Err(SceneError::Parse { .. })
        ));
    }
}
