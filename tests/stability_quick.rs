//! The quick stability suite (`knitsim stability --quick`) through its
//! library entry point: every case runs to a row (no panic), no row has NaN
//! or inf in its final state, and no row is called converged while its own
//! state checks reject the state. An error row (a start state the
//! simulator refuses, say) is allowed but must say why. Also checks the report files exist and
//! carry one CSV row per case.
//!
//! Release mode: `cargo test --release --test stability_quick -- --nocapture`
//! prints the rows.

use knitsim::app::stability::{run_suite, CaseOutcome, SuiteOptions};

#[test]
fn quick_stability_suite_has_no_panic_no_nan_and_no_silent_wrong_answer() {
    let dir = tempfile::tempdir().unwrap();
    let opts = SuiteOptions { quick: true };
    let rows = run_suite(dir.path(), opts, &mut |r| {
        eprintln!(
            "{:<32} {:<14} steps {:>3} residual {:.2e} NaN {} overlaps {} strain {:.2}% {:.1} s {}",
            r.name,
            r.outcome.label(),
            r.steps,
            r.residual,
            r.checks.non_finite,
            r.checks.overlaps,
            100.0 * r.checks.max_strain,
            r.wall_s,
            r.outcome.detail()
        )
    })
    .expect("the suite writes its report");
    assert_eq!(rows.len(), opts.cases().len());
    for r in &rows {
        assert!(
            !matches!(r.outcome, CaseOutcome::Panic(_)),
            "{}: {:?}",
            r.name,
            r.outcome
        );
        if let CaseOutcome::Error(message) = &r.outcome {
            assert!(!message.is_empty(), "{}: an error without a message", r.name);
        }
        assert_eq!(r.checks.non_finite, 0, "{}: NaN/inf in the final state", r.name);
        if r.outcome == CaseOutcome::Converged {
            assert!(r.checks_pass(), "{}: called converged but {:?}", r.name, r.checks);
        }
        assert!(r.steps <= r.max_steps, "{}", r.name);
    }
    // Not vacuous: the default case relaxes to a converged state.
    let default = rows.iter().find(|r| r.name == "default").expect("a default row");
    assert_eq!(default.outcome, CaseOutcome::Converged, "{default:?}");

    let csv = std::fs::read_to_string(dir.path().join("stability.csv")).unwrap();
    assert_eq!(csv.lines().count(), rows.len() + 1, "{csv}");
    let md = std::fs::read_to_string(dir.path().join("stability.md")).unwrap();
    assert!(md.contains("| default | on | converged |"), "{md}");
}
