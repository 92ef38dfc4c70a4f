//! Times compiling a 200 x 200 stockinette (and a slip-stitch honeycomb of
//! the same size) and checking its clearance. Not a test: run it with
//! `cargo run --release --no-default-features --example bench_compile`.

use knitsim::pattern::Construction;
use knitsim::topology::sample::{chart_pattern, tile};
use knitsim::topology::{clearance, compile, stats, ClearanceOptions, CompileOptions};
use std::time::Instant;

fn main() -> anyhow::Result<()> {
    let cases: [(&str, &[&str]); 2] = [
        ("stockinette", &["k"]),
        ("honeycomb", &["kkkk", "kwkw", "kkkk", "wkwk"]),
    ];
    for (name, t) in cases {
        let rows = tile(t, 200, 200);
        let rows: Vec<&str> = rows.iter().map(String::as_str).collect();
        let p = chart_pattern(&rows, None, Construction::Flat)?;
        let opts = CompileOptions::default();
        let best = (0..5)
            .map(|_| {
                let t0 = Instant::now();
                let f = compile(&p, &opts);
                (t0.elapsed().as_secs_f64(), f)
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .ok_or_else(|| anyhow::anyhow!("no run"))?;
        let f = best.1?;
        let t0 = Instant::now();
        let report = clearance(&f, &ClearanceOptions::default());
        let t_clear = t0.elapsed().as_secs_f64();
        let s = stats(&p, &f);
        println!(
            "{name} 200x200: compile {:.1} ms (best of 5), clearance {:.1} ms; \
             {} nodes, {} contacts, min clearance {:.3} d, {} violations",
            best.0 * 1e3,
            t_clear * 1e3,
            f.nodes.len(),
            s.contact_nodes,
            report.min_distance / (2.0 * p.meta.yarns[0].radius),
            report.violation_count
        );
    }
    Ok(())
}
