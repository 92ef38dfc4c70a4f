//! `knitsim study` end to end on a 4 x 4 stockinette: two tolerances, one
//! solver, EIL on. The three outputs are written, every run is compared
//! with the reference, and the tighter tolerance lands no farther from the
//! reference than the looser one.
//!
//! Why this can fail: a study that dropped a run, wrote an unreadable
//! plot, or measured the error against the wrong state (node indices
//! instead of material points, or another run instead of the reference)
//! would break the file checks or the ordering of the errors.

use knitsim::app::study::{run_study, StudyConfig};
use knitsim::solver::linear::SolverChoice;
use std::path::PathBuf;

#[test]
fn a_small_study_writes_its_outputs_and_tightening_brings_the_state_closer() {
    let dir = tempfile::tempdir().unwrap();
    let pattern = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("patterns/stockinette.knit");
    let mut config = StudyConfig::new(pattern, dir.path().join("out"));
    config.size = Some(4);
    config.tols = vec![300.0, 3.0];
    config.solvers = vec![SolverChoice::CpuDirect];
    config.eil = vec![true];
    config.command_line = "knitsim study patterns/stockinette.knit --size 4".into();
    let mut calls = Vec::new();
    let report = run_study(&config, None, &mut |done, total, _| calls.push((done, total))).unwrap();
    assert_eq!(calls, vec![(1, 3), (2, 3), (3, 3)]);

    let reference = report.reference.as_ref().unwrap();
    assert!(reference.converged, "reference residual {:.3e}", reference.residual);
    assert_eq!(report.runs.len(), 2);
    let rms: Vec<f64> = report.runs.iter().map(|r| r.errors.unwrap().rms_radii).collect();
    assert!(rms.iter().all(|e| e.is_finite() && *e >= 0.0), "{rms:?}");
    assert!(
        rms[1] <= rms[0],
        "tol 3 is {} radii from the reference, 300 {}",
        rms[1],
        rms[0]
    );

    let out = dir.path().join("out");
    let csv = std::fs::read_to_string(out.join("study.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 1 + 2, "{csv}");
    assert!(csv.lines().nth(1).unwrap().starts_with("reference,"));
    let md = std::fs::read_to_string(out.join("study.md")).unwrap();
    assert!(md.contains("knitsim study patterns/stockinette.knit --size 4"));
    assert!(md.contains("| cpu-direct | on | "), "{md}");
    let png = image::open(out.join("study.png")).unwrap();
    assert_eq!((png.width(), png.height()), knitsim::app::study::report::PLOT_SIZE);
}
