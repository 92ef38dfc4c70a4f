//! Scenes: what to simulate around a fabric, and with which parameters.
//!
//! A scene is data (JSON), so a run is reproducible from its files alone.
//! Obstacles are signed distance fields with a stiff penalty; a scene that
//! has none costs nothing for them (no stencils are built).

pub mod obstacle;

pub use obstacle::{ObstaclePenalty, Shape};

use crate::sim::SimParams;
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
    let p = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read {
        path: p.clone(),
        source,
    })?;
    let params: SimParams = serde_json::from_str(&text).map_err(|e| SceneError::Parse {
        path: p.clone(),
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })?;
    let r = &params.rod;
    for (name, v) in [
        ("ks", r.ks),
        ("kb", r.kb),
        ("rho", r.rho),
        ("radius", r.radius),
        ("kf", r.kf),
        ("mu", r.mu),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(SceneError::Invalid {
                path: p,
                message: format!("rod.{name} must be a finite non-negative number, got {v}"),
            });
        }
    }
    Ok(params)
}
