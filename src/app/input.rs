//! Inputs: a pattern file (compiled on the fly) or a saved fabric/state JSON.

use crate::io::IoError;
use crate::pattern::{Meta, PatternError, Site, Warning, WarningKind};
use crate::topology::rest_length::jam_gauge;
use crate::topology::{compile, thin_shape_points, CompileOptions, Fabric, TopologyError};
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

/// `.json` is a saved fabric or simulation state; anything else is a
/// pattern, compiled with `opts`. A saved fabric gets `opts.shape_gap`'s
/// thinning too (the other options only act while compiling).
pub fn load_fabric(path: &Path, opts: &CompileOptions) -> Result<Loaded, InputError> {
    let topology_error = |source| InputError::Topology {
        path: path.display().to_string(),
        source,
    };
    opts.validate().map_err(topology_error)?;
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("json")) {
        let mut fabric = crate::io::load_json(path)?;
        thin_shape_points(&mut fabric, opts.shape_gap);
        return Ok(Loaded {
            fabric,
            pattern: None,
            warnings: vec![],
        });
    }
    let parsed = crate::pattern::load(path).map_err(Box::new)?;
    let fabric = compile(&parsed.pattern, opts).map_err(topology_error)?;
    let mut warnings = parsed.warnings;
    warnings.extend(jam_warnings(&parsed.pattern.meta, &parsed.yarn_sites, opts));
    Ok(Loaded {
        fabric,
        pattern: Some(parsed.pattern),
        warnings,
    })
}

/// A warning at each yarn line whose yarn is too thick for the gauge: its
/// loops would have to be shorter than the tightest loop it forms
/// (`topology::rest_length::jam_gauge`), so they are made longer and the
/// fabric comes out larger than the gauge.
pub fn jam_warnings(meta: &Meta, sites: &[Site], opts: &CompileOptions) -> Vec<Warning> {
    meta.yarns
        .iter()
        .zip(sites)
        .filter_map(|(y, site)| {
            let d = 2.0 * y.radius * opts.yarn_compression;
            let jam = jam_gauge(meta.gauge, d, opts)?;
            Some(site.warning(WarningKind::YarnJams {
                yarn: y.name.clone(),
                jam_sts: jam.stitches_per_10cm,
                jam_rows: jam.rows_per_10cm,
                sts: meta.gauge.stitches_per_10cm,
                rows: meta.gauge.rows_per_10cm,
            }))
        })
        .collect()
}
