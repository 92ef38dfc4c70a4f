//! Rest lengths: how much yarn each loop and float gets, and the material
//! coordinate `u` along each yarn.
//!
//! **Stitch (loop) length**, from Munden's relations (docs/MODEL.md,
//! "Real-fabric references"): in a
//! relaxed plain knit the courses and wales per unit length are
//! `cpc = k_c / l` and `wpc = k_w / l`, so with the gauge pitches
//! `w = 1/wpc`, `h = 1/cpc` each alone predicts `l = k_w w` and `l = k_c h`.
//! We take their geometric mean, which is exact when the gauge obeys
//! Munden's ratio and splits the difference when it does not:
//!
//! ```text
//! l = looseness * max( sqrt(k_c k_w w h),  l_jam = 16.6 d )
//! ```
//!
//! The floor is the yarn-diameter term: Peirce's jammed loop is the
//! shortest loop an incompressible yarn of diameter `d` can form, whatever
//! the gauge says. Looseness scales the result, floor included: a designer
//! who asks for a tight knit of a yarn that is already at its jam length
//! for the gauge (every shipped pattern is: 0.75 mm radius at 24 sts)
//! gets a shorter loop, which a real, compressible yarn allows, rather
//! than a looseness that silently does nothing.
//! With the defaults (k_c = 5.0, k_w = 3.8) a 22 x 30 gauge gives
//! `l = sqrt(19 * 4.55 mm * 3.33 mm) = 16.9 mm`. A loop keeps its length when
//! it is slipped: a slipped loop is the same yarn, stretched over two rows
//! by the relaxation.
//!
//! **Float length**: `w (1 + slack)`, one stitch width plus a slack
//! (`slip_float_slack` for slips, `strand_float_slack` for colourwork).
//!
//! **Connectors** (edge turns, carried strands) have no stitch model: their
//! rest length is their layout length scaled back by the layout expansion.
//!
//! Within an element the budget is spread over its segments in proportion to
//! their layout length, so `u` is strictly increasing along a yarn.

use super::knit_graph::FloatKind;
use super::options::CompileOptions;
use super::path::Owner;

/// Rest yarn length of one loop, from the gauge pitches `w`, `h` (m), the
/// yarn diameter `d` (m) and the pattern's looseness.
pub fn stitch_length(w: f64, h: f64, d: f64, looseness: f64, opts: &CompileOptions) -> f64 {
    let munden = (opts.munden_kc * opts.munden_kw * w * h).sqrt();
    looseness * munden.max(opts.jammed_loop_diameters * d)
}

/// Rest length of a float over one stitch of width `w`.
pub fn float_length(w: f64, kind: FloatKind, opts: &CompileOptions) -> f64 {
    let slack = match kind {
        FloatKind::Slip => opts.slip_float_slack,
        FloatKind::Strand => opts.strand_float_slack,
    };
    w * (1.0 + slack)
}

/// Material coordinates of a polyline: `lengths[i]` is the layout length of
/// segment `i`, `owners[i]` its element, and `budget(owner, layout_total)`
/// the rest length of an element whose segments add up to `layout_total`.
/// Each element is a contiguous run of segments.
pub fn assign_u(lengths: &[f64], owners: &[Owner], budget: impl Fn(Owner, f64) -> f64) -> Vec<f64> {
    let mut u = Vec::with_capacity(lengths.len() + 1);
    u.push(0.0);
    let mut start = 0;
    while start < lengths.len() {
        let owner = owners[start];
        let mut end = start;
        while end < lengths.len() && owners[end] == owner {
            end += 1;
        }
        let total: f64 = lengths[start..end].iter().sum();
        let rest = budget(owner, total);
        for &len in &lengths[start..end] {
            let share = if total > 0.0 {
                rest * len / total
            } else {
                rest / (end - start) as f64
            };
            let last = u.last().copied().unwrap_or(0.0);
            u.push(last + share);
        }
        start = end;
    }
    u
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn munden_length_for_a_worsted_gauge() {
        // 22 sts and 30 rows per 10 cm: w = 4.545 mm, h = 3.333 mm.
        // sqrt(5.0 * 3.8 * 4.545e-3 * 3.333e-3) = sqrt(2.8788e-4) = 16.97 mm.
        let opts = CompileOptions::default();
        let l = stitch_length(0.1 / 22.0, 0.1 / 30.0, 1.0e-3, 1.0, &opts);
        assert!((l - 16.967e-3).abs() < 1e-5, "{l}");
        // Tight (0.85) scales it: 14.42 mm.
        let tight = stitch_length(0.1 / 22.0, 0.1 / 30.0, 1.0e-3, 0.85, &opts);
        assert!((tight - 0.85 * 16.967e-3).abs() < 1e-5, "{tight}");
        // A 1.2 mm yarn's jam floor (19.92 mm) binds, and looseness scales it.
        let loose = stitch_length(0.1 / 22.0, 0.1 / 30.0, 1.2e-3, 1.2, &opts);
        assert!((loose - 1.2 * 16.6 * 1.2e-3).abs() < 1e-12, "{loose}");
    }

    #[test]
    fn budgets_are_spread_by_length() {
        // Two segments of one loop (lengths 1 and 3) get 2 and 6 of a budget
        // of 8; a connector of length 2 keeps 2.
        let u = assign_u(
            &[1.0, 3.0, 2.0],
            &[Owner::Loop(0), Owner::Loop(0), Owner::Connector],
            |o, total| match o {
                Owner::Loop(_) => 8.0,
                _ => total,
            },
        );
        assert_eq!(u, vec![0.0, 2.0, 8.0, 10.0]);
    }
}
