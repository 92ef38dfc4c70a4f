//! Bad patterns give errors, never panics.

use knitsim::pattern::{Construction, Side};
use knitsim::topology::sample::chart_pattern;
use knitsim::topology::{compile, CompileOptions, TopologyError};
use proptest::prelude::*;

fn flat(chart: &[&str]) -> knitsim::pattern::Pattern {
    chart_pattern(chart, None, Construction::Flat).unwrap()
}

#[test]
fn malformed_patterns_are_errors() {
    let opts = CompileOptions::default();
    let mut p = flat(&["kk", "kk"]);
    p.rows[1].stitches.pop();
    assert!(matches!(
        compile(&p, &opts),
        Err(TopologyError::RowWidth { row: 2, .. })
    ));

    let mut p = flat(&["kk"]);
    p.rows[0].stitches[1].yarn = 3;
    assert!(matches!(
        compile(&p, &opts),
        Err(TopologyError::UnknownYarn { yarn: 3, .. })
    ));

    let mut p = flat(&["kk"]);
    p.meta.gauge.rows_per_10cm = 0.0;
    assert!(matches!(compile(&p, &opts), Err(TopologyError::BadGauge { .. })));

    let mut p = flat(&["kk"]);
    p.meta.yarns[0].radius = f64::NAN;
    assert!(matches!(compile(&p, &opts), Err(TopologyError::BadRadius { .. })));

    let mut p = flat(&["kk"]);
    p.meta.looseness = -1.0;
    assert!(matches!(compile(&p, &opts), Err(TopologyError::BadLooseness(_))));

    let mut p = chart_pattern(&["kk", "kk"], None, Construction::Round).unwrap();
    p.rows[1].side = Side::Ws;
    assert!(matches!(
        compile(&p, &opts),
        Err(TopologyError::WsRowInRound { row: 2 })
    ));

    let mut p = flat(&["kk"]);
    p.rows.clear();
    assert!(matches!(compile(&p, &opts), Err(TopologyError::Empty { .. })));
}

#[test]
fn impossible_needle_configurations_are_errors() {
    let opts = CompileOptions::default();
    // Two tucks on one needle: cast-on loop + 2 tucks = 3 loops > 2.
    let p = flat(&["kt", "kt"]);
    assert!(matches!(
        compile(&p, &opts),
        Err(TopologyError::NeedleOverfull {
            row: 2,
            col: 1,
            loops: 3,
            max: 2
        })
    ));
    // Slipping the cast-on loop for 4 rows makes it span 5 rows > 4.
    let p = flat(&["wk", "vk", "wk", "vk"]);
    assert!(matches!(
        compile(&p, &opts),
        Err(TopologyError::HeldTooLong {
            row: 4,
            col: 0,
            rows: 5,
            max: 4
        })
    ));
    // ... which is fine when allowed.
    let loose = CompileOptions {
        max_rows_per_loop: 5,
        ..CompileOptions::default()
    };
    assert!(compile(&p, &loose).is_ok());
}

fn symbol() -> impl Strategy<Value = char> {
    prop::sample::select(vec!['k', 'p', 'v', 'w', 't'])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Any chart of any stitches and up to three colours compiles or gives an
    /// error; when it compiles, every contact node has two yarn points.
    #[test]
    fn arbitrary_charts_never_panic(
        w in 1usize..6, h in 1usize..6,
        cells in prop::collection::vec((symbol(), 0u32..3), 36),
        round in any::<bool>(),
    ) {
        let rows: Vec<String> = (0..h).map(|r| (0..w).map(|c| cells[r * w + c].0).collect()).collect();
        let cols: Vec<String> = (0..h)
            .map(|r| (0..w).map(|c| char::from_digit(cells[r * w + c].1, 10).unwrap()).collect())
            .collect();
        let rows: Vec<&str> = rows.iter().map(String::as_str).collect();
        let cols: Vec<&str> = cols.iter().map(String::as_str).collect();
        let cons = if round { Construction::Round } else { Construction::Flat };
        let p = chart_pattern(&rows, Some(&cols), cons).unwrap();
        if let Ok(f) = compile(&p, &CompileOptions::default()) {
            let refs = f.node_refcounts();
            for c in &f.contacts {
                prop_assert_eq!(refs[c.node], 2);
            }
        }
    }
}
