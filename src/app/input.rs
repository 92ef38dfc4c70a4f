//! Inputs: a pattern file (compiled on the fly) or a saved fabric/state JSON.

use crate::io::IoError;
use crate::pattern::{PatternError, Warning};
use crate::topology::{compile, CompileOptions, Fabric, TopologyError};
use std::path::Path;

#[derive(Debug, thiserror::Error)]
pub enum InputError {
    #[error(transparent)]
    Pattern(#[from] Box<PatternError>),
    #[error("{path}: cannot build the yarn topology")]
    Topology { path: String, source: TopologyError },
    #[error(transparent)]
    Io(#[from] IoError),
}

/// A loaded fabric and, when it came from a pattern, the parser's warnings.
pub struct Loaded {
    pub fabric: Fabric,
    pub pattern: Option<crate::pattern::Pattern>,
    pub warnings: Vec<Warning>,
}

/// `.json` is a saved fabric or simulation state; anything else is a pattern.
pub fn load_fabric(path: &Path) -> Result<Loaded, InputError> {
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("json")) {
        let fabric = crate::io::load_json(path)?;
        return Ok(Loaded {
            fabric,
            pattern: None,
            warnings: vec![],
        });
    }
    let parsed = crate::pattern::load(path).map_err(Box::new)?;
    let fabric = compile(&parsed.pattern, &CompileOptions::default()).map_err(|source| InputError::Topology {
        path: path.display().to_string(),
        source,
    })?;
    Ok(Loaded {
        fabric,
        pattern: Some(parsed.pattern),
        warnings: parsed.warnings,
    })
}
