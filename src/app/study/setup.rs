//! The study's configuration, its errors, and the pattern resized to the
//! study's size.
//!
//! A study relaxes one pattern a few dozen times, so `--size N` rewrites
//! the pattern's `width:` and `height:` lines to `N` before parsing: the
//! same chart, repeated over a swatch small enough to relax many times.

use crate::app::{load_fabric, InputError};
use crate::io::IoError;
use crate::pattern::{PatternError, Warning};
use crate::scene::SceneError;
use crate::sim::SimError;
use crate::solver::linear::SolverChoice;
use crate::topology::{compile, CompileOptions, Fabric, TopologyError};
use std::path::{Path, PathBuf};

/// The default tolerance ladder, loosest first.
pub const DEFAULT_TOLS: [f64; 4] = [10.0, 1.0, 0.1, 0.01];

#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    #[error(transparent)]
    Input(#[from] InputError),
    #[error("{path}: cannot read the pattern")]
    Read { path: String, source: std::io::Error },
    #[error(transparent)]
    Pattern(#[from] Box<PatternError>),
    #[error("{path}: cannot build the yarn topology")]
    Topology { path: String, source: TopologyError },
    #[error("--size applies to a pattern, not to the saved fabric {0}")]
    SizeOfSavedFabric(String),
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error(transparent)]
    Sim(#[from] SimError),
    #[error("linear solver: {0}")]
    Solver(String),
    #[error(transparent)]
    Io(#[from] IoError),
    #[error("cannot create output directory {path}")]
    OutDir { path: String, source: std::io::Error },
    #[error("invalid study settings: {0}")]
    Settings(String),
}

/// What to run and where to write it.
#[derive(Clone, Debug)]
pub struct StudyConfig {
    /// A pattern file (or a saved fabric JSON when `size` is `None`).
    pub pattern: PathBuf,
    /// Resize the pattern to `N x N` stitches.
    pub size: Option<usize>,
    /// The tolerance ladder.
    pub tols: Vec<f64>,
    /// Step cap of each ladder run.
    pub max_steps: usize,
    /// Reference tolerance; `None`: the smallest of `tols` over 10.
    pub ref_tol: Option<f64>,
    pub ref_max_steps: usize,
    /// Linear solvers to try; those that cannot run here are skipped.
    pub solvers: Vec<SolverChoice>,
    /// EIL settings to try (`true`: EIL on).
    pub eil: Vec<bool>,
    pub compile: CompileOptions,
    pub scene: Option<PathBuf>,
    /// Material samples per point-to-point segment of the reference.
    pub samples_per_segment: usize,
    pub out_dir: PathBuf,
    /// The command that started the study, quoted in `study.md`.
    pub command_line: String,
    /// A description of the machine, quoted in `study.md`.
    pub machine: String,
}

impl StudyConfig {
    /// The defaults of `knitsim study`.
    pub fn new(pattern: PathBuf, out_dir: PathBuf) -> Self {
        StudyConfig {
            pattern,
            size: None,
            tols: DEFAULT_TOLS.to_vec(),
            max_steps: 100,
            ref_tol: None,
            ref_max_steps: 400,
            solvers: vec![SolverChoice::CpuDirect, SolverChoice::CpuCg, SolverChoice::Gpu],
            eil: vec![true, false],
            compile: CompileOptions::default(),
            scene: None,
            samples_per_segment: 8,
            out_dir,
            command_line: String::new(),
            machine: machine_description(),
        }
    }

    /// The reference's tolerance.
    pub fn reference_tol(&self) -> f64 {
        self.ref_tol
            .unwrap_or_else(|| self.tols.iter().copied().fold(f64::INFINITY, f64::min) / 10.0)
    }

    pub fn validate(&self) -> Result<(), StudyError> {
        let bad = |m: String| Err(StudyError::Settings(m));
        if self.tols.is_empty() {
            return bad("the tolerance ladder is empty".into());
        }
        if let Some(t) = self
            .tols
            .iter()
            .chain(&self.ref_tol)
            .find(|t| !(t.is_finite() && **t > 0.0))
        {
            return bad(format!("tolerances must be positive numbers, got {t}"));
        }
        if self.solvers.is_empty() || self.eil.is_empty() {
            return bad("no solver or no EIL setting to run".into());
        }
        if self.max_steps == 0 || self.ref_max_steps == 0 {
            return bad("step caps must be at least 1".into());
        }
        if self.size == Some(0) {
            return bad("--size must be at least 1".into());
        }
        Ok(())
    }
}

/// CPU model and core count, from `/proc/cpuinfo` where there is one.
pub fn machine_description() -> String {
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string());
    format!("{model}, {cores} cores available")
}

/// The pattern text with its `width:` and `height:` lines set to `n`.
pub fn resize_text(text: &str, n: usize) -> String {
    text.lines()
        .map(|l| {
            if l.starts_with("width:") {
                format!("width: {n}")
            } else if l.starts_with("height:") {
                format!("height: {n}")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The fabric of `path`, resized to `size x size` stitches when given,
/// with the parser's warnings.
pub fn load_resized(
    path: &Path,
    size: Option<usize>,
    opts: &CompileOptions,
) -> Result<(Fabric, Vec<Warning>), StudyError> {
    let Some(n) = size else {
        let loaded = load_fabric(path, opts)?;
        return Ok((loaded.fabric, loaded.warnings));
    };
    let name = path.display().to_string();
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("json")) {
        return Err(StudyError::SizeOfSavedFabric(name));
    }
    let text = std::fs::read_to_string(path).map_err(|source| StudyError::Read {
        path: name.clone(),
        source,
    })?;
    let parsed = crate::pattern::parse_str(&resize_text(&text, n), &name).map_err(Box::new)?;
    let fabric = compile(&parsed.pattern, opts).map_err(|source| StudyError::Topology { path: name, source })?;
    Ok((fabric, parsed.warnings))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resizing_rewrites_only_the_size_lines() {
        let text = "name: X\nwidth: 16\nheight: 20\nchart:\n  .";
        assert_eq!(resize_text(text, 4), "name: X\nwidth: 4\nheight: 4\nchart:\n  .");
    }

    #[test]
    fn the_reference_defaults_to_a_tenth_of_the_tightest_tolerance() {
        let mut c = StudyConfig::new("p.knit".into(), "out".into());
        c.tols = vec![1e-2, 1e-4, 1e-3];
        assert!((c.reference_tol() - 1e-5).abs() < 1e-20);
        c.ref_tol = Some(3e-6);
        assert_eq!(c.reference_tol(), 3e-6);
    }

    #[test]
    fn bad_settings_are_refused() {
        let mut c = StudyConfig::new("p.knit".into(), "out".into());
        assert!(c.validate().is_ok());
        c.tols = vec![1e-3, -1.0];
        assert!(matches!(c.validate(), Err(StudyError::Settings(_))));
        c.tols = vec![];
        assert!(c.validate().is_err());
    }
}
