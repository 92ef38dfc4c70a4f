//! Scenes: what to simulate around a fabric, and with which parameters.
//!
//! A scene is data (JSON), so a run is reproducible from its files alone.
//! Obstacles are signed distance fields with a stiff penalty; a scene that
//! has none costs nothing for them (no stencils are built). The obstacle
//! energy itself is `rod::obstacle`.
//!
//! A scene is checked as it is read, and every error names the file, line
//! and column of the offending value (a UTF-8 byte-order mark is allowed):
//! - unknown keys, malformed JSON, a byte that is not UTF-8 and values of
//!   the wrong type (`"radius": true`, `"obstacles": {}`) are refused by
//!   serde_json at their position;
//! - JSON has no NaN or infinity: `"nan"` or `"inf"` as a string where a
//!   number belongs is refused with that reason, `1e999` is out of range;
//! - stiffnesses, radii and densities (`rod.radius`, `ks`, `kb`, `rho`,
//!   `kc_factor`, `obstacle_stiffness`, `contact.thickness`,
//!   `stiffness_scale`, `max_stiffness_factor`, `penalty_stiffness`) are
//!   above 0; the other scalars (`mu`, `kf`, `kw_factor`, `ksh_factor`, `kp`, the shear
//!   jamming pair, the `assign` fractions, `separation.min_pull`, the
//!   remaining `contact` factors) are 0 or above (`crate::checked`);
//! - obstacles: a sphere's and a cylinder's radius and a box's half
//!   extents are above 0, a plane's normal and a cylinder's axis are not
//!   `[0, 0, 0]`, a mesh's OBJ file (its `path` relative to the scene file)
//!   is read and checked as the obstacle is read (`shape_json`);
//! - `dynamics` (the settings of `knitsim drape`, `sim::dynamics_settings`):
//!   time step, duration, frame rate, damping and friction values are
//!   checked like the others; pins and motions are checked against the
//!   fabric when a run starts (`sim::dynamics::pins`);
//! - `assign.stop_fraction` and `assign.close_fraction` are below
//!   `assign.safety_fraction` (unless 0); this rule compares two keys and is
//!   located at the key in the text (`locate`).
//!
//! Pins are part of the fabric (`Node::pinned`); a scene's `dynamics.pins`
//! selects nodes to pin by corners, edges, stitches, yarn ends or index.
//! The keys are listed in docs/SCENES.md.

mod locate;
mod shape_json;

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
/// their defaults; unknown keys, malformed JSON, values of the wrong type or
/// out of range (see the module docs) are errors naming the file, line and
/// column.
pub fn load_params(path: &Path) -> Result<SimParams, SceneError> {
    parse_params(&read_scene(path)?, path)
}

fn read_scene(path: &Path) -> Result<Vec<u8>, SceneError> {
    std::fs::read(path).map_err(|source| SceneError::Read {
        path: path.display().to_string(),
        source,
    })
}

/// The scene text after a UTF-8 byte-order mark, if it has one.
fn without_bom(bytes: &[u8]) -> &[u8] {
    bytes.strip_prefix(b"\xef\xbb\xbf".as_slice()).unwrap_or(bytes)
}

/// A located serde_json error (a byte that is not UTF-8 included).
fn parse_error(path: &str, e: &serde_json::Error) -> SceneError {
    let message = e.to_string();
    let suffix = format!(" at line {} column {}", e.line(), e.column());
    SceneError::Parse {
        path: path.to_string(),
        line: e.line(),
        column: e.column(),
        message: message.strip_suffix(&suffix).unwrap_or(&message).to_string(),
    }
}

/// [`load_params`] on the bytes of a scene file; `path` is the name used
/// in errors.
pub fn parse_params(bytes: &[u8], path: &Path) -> Result<SimParams, SceneError> {
    let p = path.display().to_string();
    let bytes = without_bom(bytes);
    // A mesh obstacle's OBJ path is relative to the scene file.
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    shape_json::BASE_DIR.with(|b| *b.borrow_mut() = dir);
    let parsed = serde_json::from_slice::<SimParams>(bytes);
    shape_json::BASE_DIR.with(|b| b.borrow_mut().clear());
    let params: SimParams = parsed.map_err(|e| parse_error(&p, &e))?;
    let a = &params.assign;
    // A point stopped, or a segment tripped, outside the safety distance
    // would not be handed to EIL by the next re-assignment: a stop would
    // hold it forever, a tripwire would end every step at once.
    for (name, v, why) in [
        ("stop_fraction", a.stop_fraction, "a stopped point"),
        ("close_fraction", a.close_fraction, "a closed segment"),
    ] {
        if v >= a.safety_fraction && v > 0.0 {
            let message = format!(
                "assign.{name} ({v}) must be below assign.safety_fraction ({}): {why} outside the \
                 safety distance would never be handed to EIL",
                a.safety_fraction
            );
            return Err(locate::at_key(bytes, &p, &[name, "safety_fraction"], message));
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
///
/// Thickness contact between yarns is on (`filtered`) unless the scene
/// says otherwise with a `"contact"` key (`{"contact": {"mode": "none"}}`
/// turns it off): without it nothing stops two yarns that are not knitted
/// together from passing through each other.
pub fn params_for(fabric: &Fabric, scene: Option<&Path>) -> Result<SimParams, SceneError> {
    let (mut params, scene_radius, scene_radii, scene_contact) = match scene {
        None => (SimParams::default(), false, false, false),
        Some(path) => {
            let bytes = read_scene(path)?;
            let params = parse_params(&bytes, path)?;
            // The typed parse succeeded, so this one does too.
            let value: serde_json::Value = serde_json::from_slice(without_bom(&bytes)).unwrap_or_default();
            let has = |key| value.pointer(key).is_some();
            (params, has("/rod/radius"), has("/radii"), has("/contact"))
        }
    };
    if !scene_contact {
        params.contact = Some(crate::sim::ContactParams::default());
    }
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

    /// The error of `text` must be at `(line, column)` and say `words`.
    fn refused_at(text: &str, line: usize, column: usize, words: &str) {
        let (r, path) = load(text);
        let e = r.expect_err(text);
        let shown = e.to_string();
        assert!(
            matches!(&e, SceneError::Parse { line: l, column: c, .. } if (*l, *c) == (line, column)),
            "{text}: {shown}"
        );
        assert!(shown.starts_with(&format!("{path}:{line}:{column}: ")), "{shown}");
        assert!(shown.contains(words), "{text}: {shown}");
    }

    #[test]
    fn out_of_range_parameters_are_errors_at_the_value() {
        for (text, column, words) in [
            (r#"{"rod": {"ks": -1.0}}"#, 20, "above 0"),
            (r#"{"rod": {"kb": 0}}"#, 17, "above 0"),
            (r#"{"rod": {"radius": 0}}"#, 21, "above 0"),
            (r#"{"rod": {"rho": -5e-4}}"#, 22, "above 0"),
            (r#"{"rod": {"mu": -0.1}}"#, 20, "0 or above"),
            (r#"{"obstacle_stiffness": 0}"#, 25, "above 0"),
            (r#"{"separation": {"min_pull": -0.1}}"#, 33, "0 or above"),
            (r#"{"assign": {"stop_fraction": -0.05}}"#, 35, "0 or above"),
            (r#"{"assign": {"close_fraction": -1e-5}}"#, 36, "0 or above"),
            (r#"{"contact": {"thickness": -1}}"#, 29, "above 0"),
        ] {
            refused_at(text, 1, column, words);
        }
        // The mu of a frictionless yarn and a contact without a thickness are fine.
        let (p, _) = load(r#"{"rod": {"mu": 0}, "contact": {"thickness": null}}"#);
        assert_eq!(p.unwrap().rod.mu, 0.0);
    }

    #[test]
    fn non_finite_numbers_and_wrong_types_are_errors_at_the_value() {
        refused_at("{\n  \"rod\": {\"ks\": \"nan\"}\n}", 2, 21, "no NaN or infinity");
        refused_at(r#"{"rod": {"kb": "-inf"}}"#, 1, 21, "no NaN or infinity");
        refused_at(r#"{"rod": {"kb": 1e999}}"#, 1, 20, "out of range");
        refused_at(
            r#"{"rod": {"radius": true}}"#,
            1,
            23,
            "invalid type: boolean `true`, expected a number",
        );
        refused_at(r#"{"obstacles": {}}"#, 1, 14, "invalid type: map, expected a sequence");
        refused_at(r#"{"obstacles": [1]}"#, 1, 16, "expected an obstacle object");
        refused_at(
            r#"{"rod": 5}"#,
            1,
            9,
            "invalid type: integer `5`, expected struct RodParams",
        );
    }

    #[test]
    fn degenerate_obstacles_are_errors_at_the_value() {
        let sphere = "{\"obstacles\": [\n  {\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": -0.1}\n]}";
        refused_at(sphere, 2, 57, "above 0");
        let zero = r#"{"obstacles": [{"type": "sphere", "center": [0, 0, 0], "radius": 0}]}"#;
        refused_at(zero, 1, 67, "above 0");
        let plane = r#"{"obstacles": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 0, 0]}]}"#;
        refused_at(plane, 1, 72, "[0, 0, 0]");
        let (p, _) = load(r#"{"obstacles": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 0, 2]}]}"#);
        assert_eq!(p.unwrap().obstacles.len(), 1);
    }

    #[test]
    fn fractions_beyond_the_safety_distance_point_at_the_key() {
        refused_at(
            "{\"assign\": {\n  \"stop_fraction\": 0.1\n}}",
            2,
            20,
            "assign.stop_fraction (0.1) must be below assign.safety_fraction",
        );
        refused_at(
            "{\"assign\": {\"close_fraction\": 0.2}}",
            1,
            31,
            "assign.close_fraction",
        );
        // The default close_fraction against a tiny safety distance.
        refused_at("{\"assign\": {\"safety_fraction\": 1e-6}}", 1, 32, "close_fraction");
    }

    #[test]
    fn a_byte_order_mark_is_accepted_and_a_byte_that_is_not_utf8_is_located() {
        let (p, _) = load("\u{feff}{\"rod\": {\"ks\": 50}}");
        assert_eq!(p.unwrap().rod.ks, 50.0);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("latin1.json");
        std::fs::write(&path, b"{\n  \"rod\": {\"ks\": 1\xd7}\n}").unwrap();
        let e = load_params(&path).unwrap_err();
        assert!(matches!(e, SceneError::Parse { line: 2, .. }), "{e}");
    }
}
