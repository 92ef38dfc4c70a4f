//! Rest lengths: how much yarn each loop and float gets, and the material
//! coordinate `u` along each yarn.
//!
//! **Yarn model.** A `yarn` line states the yarn's free thickness. In a
//! knit the yarn is squashed where loops press on each other and its
//! fibres nest, so the model, whose yarns are incompressible tubes around
//! their centre lines, simulates an *effective* radius
//! `CompileOptions::yarn_compression` (0.6) times the stated one.
//! [`effective_meta`] applies it once, in [`super::compile`]: every radius
//! of a compiled [`Fabric`](super::Fabric) is a model radius.
//!
//! **Stitch (loop) length.** The `gauge` line follows the ball-band
//! convention: it is the gauge of this yarn *in stockinette* on the
//! needles used, so it fixes the loop length, and other stitch patterns
//! relax to their own size with the same loops (rib narrower, garter
//! shorter). Munden's relations (Munden 1959; docs/MODEL.md, "Real-fabric
//! references") give, for a relaxed plain knit with pitches `w` (wale) and
//! `h` (course), `l = k_w w = k_c h`; we take the geometric mean, scaled by
//! a calibration `k_l` so that the simulator's own relaxed stockinette
//! measures the gauge (Munden's constants describe real yarn, not this
//! model), and floor it at the tightest loop a yarn of the effective
//! diameter forms (about 12 d in the tightest real knits; Peirce's
//! geometrically jammed loop of a round incompressible yarn, 16.6 d, is
//! longer, since real yarns flatten):
//!
//! ```text
//! l = looseness * max( k_l sqrt(k_c k_w w h),  l_jam = 12 d_eff )
//! ```
//!
//! `k_l = 0.72` (`CompileOptions::loop_calibration`): a 16 x 16
//! stockinette at 24 x 32 sts/rows per 10 cm, effective radius 0.45 mm,
//! relaxed with the default settings, measures 22.5 x 30.2 at `k_l = 0.77`
//! (`topology::measure`), and `l` scales the stitch pitches. When the floor
//! binds the yarn is too thick for the gauge: the pattern gets a warning
//! naming [`jam_gauge`], the tightest gauge the yarn reaches. Looseness
//! scales the result, floor included.
//! A slipped loop keeps its length: it is the same yarn, laid out over two
//! rows (or more) instead of one.
//!
//! **Float length**: `w (1 + slack)`, one stitch width plus a slack
//! (`slip_float_slack` for slips, `strand_float_slack` for colourwork).
//!
//! **Connectors** (edge turns, carried strands) have no stitch model: their
//! rest length is their layout length scaled back by the layout expansion.
//!
//! Within an element the budget is spread over its segments in proportion to
//! their weighted layout length, so `u` is strictly increasing along a
//! yarn. Every weight is 1 except on the head of a loop laid out over more
//! than one row ([`segment_weights`]): spread by plain length, a slipped
//! loop's long legs would take most of its yarn and leave its head about a
//! third of an ordinary head's, too short to let its child's two legs
//! pass a diameter apart. The head is weighted so that it gets the yarn an
//! ordinary loop's head gets, and the legs share the rest.

use super::knit_graph::FloatKind;
use super::options::CompileOptions;
use super::path::Owner;
use crate::pattern::{Gauge, Meta};

/// The loop length the gauge pitches `w`, `h` (m) ask for, before the jam
/// floor and looseness.
pub fn gauge_loop_length(w: f64, h: f64, opts: &CompileOptions) -> f64 {
    opts.loop_calibration * (opts.munden_kc * opts.munden_kw * w * h).sqrt()
}

/// Rest yarn length of one loop, from the gauge pitches `w`, `h` (m), the
/// effective yarn diameter `d` (m) and the pattern's looseness.
pub fn stitch_length(w: f64, h: f64, d: f64, looseness: f64, opts: &CompileOptions) -> f64 {
    looseness * gauge_loop_length(w, h, opts).max(opts.jammed_loop_diameters * d)
}

/// The tightest gauge (same stitch-to-row ratio as `gauge`) at which a
/// yarn of effective diameter `d` still forms the loops the gauge asks
/// for; `None` when `gauge` itself is within reach.
pub fn jam_gauge(gauge: Gauge, d: f64, opts: &CompileOptions) -> Option<Gauge> {
    let asked = gauge_loop_length(gauge.stitch_width(), gauge.row_height(), opts);
    let jam = opts.jammed_loop_diameters * d;
    // Loop length is linear in the pitches' scale.
    (asked < jam).then(|| Gauge {
        stitches_per_10cm: gauge.stitches_per_10cm * asked / jam,
        rows_per_10cm: gauge.rows_per_10cm * asked / jam,
    })
}

/// The gauge a relaxed stockinette of this compiled fabric's yarns knits
/// at: the declared one, or the jam gauge of its thickest yarn when that
/// yarn is too thick for it. `meta` holds model (effective) radii, as a
/// compiled [`Fabric`](super::Fabric)'s does.
pub fn predicted_gauge(meta: &Meta, opts: &CompileOptions) -> Gauge {
    let d = 2.0 * meta.yarns.iter().map(|y| y.radius).fold(0.0, f64::max);
    jam_gauge(meta.gauge, d, opts).unwrap_or(meta.gauge)
}

/// `meta` with every yarn radius replaced by its model (effective) radius.
pub fn effective_meta(meta: &Meta, opts: &CompileOptions) -> Meta {
    let mut m = meta.clone();
    for y in &mut m.yarns {
        y.radius *= opts.yarn_compression;
    }
    m
}

/// Rest length of a float over one stitch of width `w`.
pub fn float_length(w: f64, kind: FloatKind, opts: &CompileOptions) -> f64 {
    let slack = match kind {
        FloatKind::Slip => opts.slip_float_slack,
        FloatKind::Strand => opts.strand_float_slack,
    };
    w * (1.0 + slack)
}

/// The contiguous runs of segments with one owner, as `(owner, start, end)`.
fn runs(owners: &[Owner]) -> impl Iterator<Item = (Owner, usize, usize)> + '_ {
    let mut start = 0;
    std::iter::from_fn(move || {
        let owner = *owners.get(start)?;
        let mut end = start;
        while end < owners.len() && owners[end] == owner {
            end += 1;
        }
        let run = (owner, start, end);
        start = end;
        Some(run)
    })
}

/// The layout length of every loop that `ordinary` accepts, one per run,
/// over several polylines (`(lengths, owners)` each).
pub fn ordinary_loop_lengths<'a>(
    paths: impl IntoIterator<Item = (&'a [f64], &'a [Owner])>,
    ordinary: impl Fn(usize) -> bool,
) -> Vec<f64> {
    let mut out = Vec::new();
    for (lengths, owners) in paths {
        for (owner, start, end) in runs(owners) {
            if matches!(owner, Owner::Loop(id) if ordinary(id)) {
                out.push(lengths[start..end].iter().sum());
            }
        }
    }
    out
}

/// The spreading weight of every segment (module docs): 1, except on the
/// head of a loop that `elongated` names (laid out longer than an
/// ordinary loop: drawn over more than one row, or a tuck's layers).
/// `head[i]` says whether segment `i` lies on its loop's head, and
/// `reference` is an ordinary loop's layout length (the median of
/// [`ordinary_loop_lengths`]). With layout lengths `H` (head) and `T`
/// (loop), the head weight `W = (T - H) / (reference - H)` gives the head
/// the share `H / reference` of the budget, an ordinary loop's.
///
/// The reference is measured rather than derived from the row height: an
/// elongated loop's legs also bend around the floats that cross them, so
/// a loop slipped for one row is laid out more than twice as long as an
/// ordinary one.
pub fn segment_weights(
    lengths: &[f64],
    owners: &[Owner],
    head: &[bool],
    elongated: impl Fn(usize) -> bool,
    reference: f64,
) -> Vec<f64> {
    let mut w = vec![1.0; lengths.len()];
    for (owner, start, end) in runs(owners) {
        if !matches!(owner, Owner::Loop(id) if elongated(id)) {
            continue;
        }
        let total: f64 = lengths[start..end].iter().sum();
        let h: f64 = (start..end).filter(|&i| head[i]).map(|i| lengths[i]).sum();
        if h <= 0.0 || reference <= h || total <= reference {
            continue;
        }
        let weight = (total - h) / (reference - h);
        for i in (start..end).filter(|&i| head[i]) {
            w[i] = weight;
        }
    }
    w
}

/// Material coordinates of a polyline: `lengths[i]` is the layout length of
/// segment `i`, `weights[i]` its spreading weight ([`segment_weights`]),
/// `owners[i]` its element, and `budget(owner, layout_total)` the rest
/// length of an element whose segments add up to `layout_total`. Each
/// element is a contiguous run of segments.
pub fn assign_u(lengths: &[f64], weights: &[f64], owners: &[Owner], budget: impl Fn(Owner, f64) -> f64) -> Vec<f64> {
    let mut u = Vec::with_capacity(lengths.len() + 1);
    u.push(0.0);
    for (owner, start, end) in runs(owners) {
        let total: f64 = lengths[start..end].iter().sum();
        let weighted: f64 = (start..end).map(|i| lengths[i] * weights[i]).sum();
        let rest = budget(owner, total);
        for i in start..end {
            let share = if weighted > 0.0 {
                rest * lengths[i] * weights[i] / weighted
            } else {
                rest / (end - start) as f64
            };
            let last = u.last().copied().unwrap_or(0.0);
            u.push(last + share);
        }
    }
    u
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn munden_length_for_a_worsted_gauge() {
        // 22 sts and 30 rows per 10 cm: w = 4.545 mm, h = 3.333 mm.
        // sqrt(5.0 * 3.8 * 4.545e-3 * 3.333e-3) = sqrt(2.8788e-4) = 16.97 mm,
        // calibrated: 0.72 * 16.97 = 12.22 mm.
        let opts = CompileOptions::default();
        let l = stitch_length(0.1 / 22.0, 0.1 / 30.0, 0.6e-3, 1.0, &opts);
        assert!((l - 0.72 * 16.967e-3).abs() < 1e-5, "{l}");
        // Tight (0.85) scales it.
        let tight = stitch_length(0.1 / 22.0, 0.1 / 30.0, 0.6e-3, 0.85, &opts);
        assert!((tight - 0.85 * 0.72 * 16.967e-3).abs() < 1e-5, "{tight}");
        // A 1.2 mm yarn's jam floor (14.4 mm) binds, and looseness scales it.
        let loose = stitch_length(0.1 / 22.0, 0.1 / 30.0, 1.2e-3, 1.2, &opts);
        assert!((loose - 1.2 * 12.0 * 1.2e-3).abs() < 1e-12, "{loose}");
    }

    #[test]
    fn the_jam_gauge_is_where_the_floor_starts_to_bind() {
        let opts = CompileOptions::default();
        let asked = Gauge {
            stitches_per_10cm: 24.0,
            rows_per_10cm: 32.0,
        };
        // 0.9 mm effective diameter: 12 d = 10.8 mm, the gauge asks for
        // 0.72 * sqrt(19 * 4.167 * 3.125) = 11.3 mm: within reach.
        assert!(jam_gauge(asked, 0.9e-3, &opts).is_none());
        // 1.2 mm: the floor (14.4 mm) binds; at the jam gauge it just does not.
        let jam = jam_gauge(asked, 1.2e-3, &opts).expect("too thick");
        assert!(jam.stitches_per_10cm < 24.0 && jam.rows_per_10cm < 32.0);
        assert!((jam.rows_per_10cm / jam.stitches_per_10cm - 32.0 / 24.0).abs() < 1e-12);
        let l = gauge_loop_length(jam.stitch_width(), jam.row_height(), &opts);
        assert!((l - 12.0 * 1.2e-3).abs() < 1e-12, "{l}");
    }

    #[test]
    fn a_slipped_loop_gives_its_head_an_ordinary_heads_share() {
        // An ordinary loop: legs 2 + 2, head 1 (layout total 5). Its
        // slipped twin has legs 4 + 4. Same budget 10 for both.
        let loop0 = [Owner::Loop(0); 3];
        let loop1 = [Owner::Loop(1); 3];
        let head = [false, true, false];
        let elongated = |id: usize| id == 1;
        let budget = |_: Owner, _: f64| 10.0;

        let ordinary = [2.0, 1.0, 2.0];
        let slipped = [4.0, 1.0, 4.0];
        let reference = ordinary_loop_lengths([(&ordinary[..], &loop0[..]), (&slipped[..], &loop1[..])], |id| {
            !elongated(id)
        });
        assert_eq!(reference, vec![5.0]);

        let w0 = segment_weights(&ordinary, &loop0, &head, elongated, 5.0);
        assert_eq!(w0, vec![1.0; 3]);
        let u0 = assign_u(&ordinary, &w0, &loop0, budget);
        assert_eq!(u0, vec![0.0, 4.0, 6.0, 10.0]);

        let w1 = segment_weights(&slipped, &loop1, &head, elongated, 5.0);
        let u1 = assign_u(&slipped, &w1, &loop1, budget);
        // Spread by length the head would get 10 / 9; weighted it gets the
        // ordinary head's 2, and the legs share the other 8.
        assert!((u1[2] - u1[1] - 2.0).abs() < 1e-12, "{u1:?}");
        assert!((u1[1] - 4.0).abs() < 1e-12 && (u1[3] - 10.0).abs() < 1e-12, "{u1:?}");
    }

    #[test]
    fn budgets_are_spread_by_length() {
        // Two segments of one loop (lengths 1 and 3) get 2 and 6 of a budget
        // of 8; a connector of length 2 keeps 2.
        let u = assign_u(
            &[1.0, 3.0, 2.0],
            &[1.0; 3],
            &[Owner::Loop(0), Owner::Loop(0), Owner::Connector],
            |o, total| match o {
                Owner::Loop(_) => 8.0,
                _ => total,
            },
        );
        assert_eq!(u, vec![0.0, 2.0, 8.0, 10.0]);
    }
}
