//! The case matrix of the stability suite: each case is a pattern written in
//! the `.knit` text format (patterns/README.md), compiled as the CLI
//! compiles it, with default parameters (`scene::params_for`) changed in one
//! direction, and optionally a perturbed start state.

use crate::pattern::parse_str;
use crate::scene::params_for;
use crate::sim::{ContactParams, SimParams};
use crate::topology::{compile, CompileOptions, Fabric};

/// Stitch width of the suite's gauge, 24 stitches / 10 cm (mm).
const STITCH_MM: f64 = 100.0 / 24.0;
/// The default yarn radius (mm): 0.18 stitch widths.
const RADIUS_MM: f64 = 0.75;

/// How a case changes the defaults.
#[derive(Clone, Debug)]
pub enum Change {
    None,
    Ks(f64),
    Kb(f64),
    Mu(f64),
    Gravity(f64),
    /// Start from the compiled fabric with one node moved onto its neighbour.
    CoincidentNodes,
    /// Start from the compiled fabric with two consecutive `u` equal.
    ZeroLengthSegment,
}

/// One row of the suite.
#[derive(Clone, Debug)]
pub struct Case {
    pub name: String,
    /// The pattern text.
    pub pattern: String,
    pub change: Change,
    /// Thickness contact (`filtered`) on.
    pub contact: bool,
    pub max_steps: usize,
    /// Wall-time cap (s): the run is stopped between iterations after it.
    pub time_cap_s: f64,
    /// Part of `--quick`.
    pub quick: bool,
}

/// A pattern: `chart` rows top first, `legend` lines, `yarns` as
/// `(name, radius mm)` (the first is the main yarn).
pub fn pattern(
    name: &str,
    w: usize,
    h: usize,
    looseness: f64,
    yarns: &[(&str, f64)],
    legend: &[&str],
    chart: &[&str],
) -> String {
    let mut s = format!("name: {name}\ngauge: 24 sts x 32 rows / 10 cm\n");
    for (y, r) in yarns {
        s += &format!("yarn {y}: radius {r} mm\n");
    }
    s += &format!("width: {w}\nheight: {h}\nlooseness: {looseness}\n\nlegend:\n");
    for l in legend {
        s += &format!("  {l}\n");
    }
    s += "\nchart:\n";
    for c in chart {
        s += &format!("  {c}\n");
    }
    s
}

fn stockinette(w: usize, h: usize, looseness: f64, radius_mm: f64) -> String {
    pattern(
        "stockinette",
        w,
        h,
        looseness,
        &[("MC", radius_mm)],
        &[". = knit"],
        &["."],
    )
}

/// The matrix. `n` is the swatch size (stitches each way) of the ordinary
/// cases; `steps` their step cap.
pub fn all(n: usize, steps: usize) -> Vec<Case> {
    let base = stockinette(n, n, 1.0, RADIUS_MM);
    let case = |name: String, pattern: &str, change: Change, quick: bool| Case {
        name,
        pattern: pattern.to_string(),
        change,
        contact: true,
        max_steps: steps,
        time_cap_s: 60.0,
        quick,
    };
    let mut v = vec![case("default".into(), &base, Change::None, true)];
    let mut no_contact = case("default, contact off".into(), &base, Change::None, true);
    no_contact.contact = false;
    v.push(no_contact);
    for k in [0.01, 100.0] {
        v.push(case(format!("ks x{k}"), &base, Change::Ks(k), true));
    }
    for k in [0.01, 100.0] {
        v.push(case(format!("kb x{k}"), &base, Change::Kb(k), true));
    }
    let mut kb_off = case("kb x100, contact off".into(), &base, Change::Kb(100.0), false);
    kb_off.contact = false;
    v.push(kb_off);
    for f in [0.05, 0.15, 0.25, 0.35, 0.45] {
        let quick = f == 0.05 || f == 0.45;
        let p = stockinette(n, n, 1.0, (f * STITCH_MM * 1000.0).round() / 1000.0);
        v.push(case(format!("radius {f} stitch widths"), &p, Change::None, quick));
    }
    for l in [0.6, 1.5, 2.0] {
        let p = stockinette(n, n, l, RADIUS_MM);
        v.push(case(format!("looseness {l}"), &p, Change::None, l != 1.5));
    }
    for mu in [0.0, 0.5, 2.0] {
        v.push(case(format!("friction mu {mu}"), &base, Change::Mu(mu), mu != 0.5));
    }
    for g in [0.0, 1.0, 100.0] {
        v.push(case(format!("gravity x{g}"), &base, Change::Gravity(g), g != 1.0));
    }
    v.push(case(
        "1x1 swatch".into(),
        &stockinette(1, 1, 1.0, RADIUS_MM),
        Change::None,
        true,
    ));
    for (w, h, what) in [(1000, 2, "strip"), (2, 400, "column")] {
        let mut c = case(
            format!("{w}x{h} {what}"),
            &stockinette(w, h, 1.0, RADIUS_MM),
            Change::None,
            false,
        );
        c.max_steps = steps.min(5);
        c.time_cap_s = 240.0;
        v.push(c);
    }
    v.push(case("slips held 3 rows".into(), &held_slips(n), Change::None, true));
    v.push(case(
        "tucks held on the needle".into(),
        &held_tucks(n),
        Change::None,
        true,
    ));
    v.push(case(
        "three yarns 0.5/0.75/1.0 mm".into(),
        &three_yarns(n),
        Change::None,
        true,
    ));
    v.push(case("coincident nodes".into(), &base, Change::CoincidentNodes, true));
    let mut coincident_off = case(
        "coincident nodes, contact off".into(),
        &base,
        Change::CoincidentNodes,
        true,
    );
    coincident_off.contact = false;
    v.push(coincident_off);
    v.push(case(
        "zero-length segment".into(),
        &base,
        Change::ZeroLengthSegment,
        true,
    ));
    v
}

/// A column slipped (float on the RS) for three rows, the longest hold the
/// compiler allows (`CompileOptions::max_rows_per_loop` = 4 rows a loop).
fn held_slips(n: usize) -> String {
    let w = n.div_ceil(4) * 4 + 1;
    let chart = ["[. . . .] .", "[. . . v] .", "[. . . v] .", "[. . . v] ."];
    pattern(
        "held slips",
        w,
        8,
        1.2,
        &[("MC", RADIUS_MM)],
        &[". = knit", "v = slip wyif"],
        &chart,
    )
}

/// Tucks in alternating columns: each tuck loop stays on the needle with
/// its parent, the most loops a needle holds
/// (`CompileOptions::max_loops_on_needle` = 2).
fn held_tucks(n: usize) -> String {
    let w = n.div_ceil(4) * 4 + 1;
    let chart = ["[. . . .] .", "[. . T .] .", "[. . . .] .", "[T . . .] ."];
    pattern(
        "held tucks",
        w,
        8,
        1.0,
        &[("MC", RADIUS_MM)],
        &[". = knit", "T = tuck"],
        &chart,
    )
}

/// Two-row stripes in three yarns of radii 0.5, 0.75 and 1.0 mm.
fn three_yarns(n: usize) -> String {
    let chart = [". | C", ". | C", ". | B", ". | B", ". | A", ". | A"];
    let yarns = [("A", 0.5), ("B", RADIUS_MM), ("C", 1.0)];
    pattern("three yarns", n, n.div_ceil(6) * 6, 1.0, &yarns, &[". = knit"], &chart)
}

/// The fabric and parameters of a case.
pub fn build(c: &Case) -> Result<(Fabric, SimParams), String> {
    let parsed = parse_str(&c.pattern, &format!("{}.knit", c.name)).map_err(|e| e.to_string())?;
    let mut fabric = compile(&parsed.pattern, &CompileOptions::default()).map_err(|e| e.to_string())?;
    let mut p = params_for(&fabric, None).map_err(|e| e.to_string())?;
    // `params_for` turns contact on; the "contact off" cases turn it off.
    p.contact = c.contact.then(ContactParams::default);
    match c.change {
        Change::None => {}
        Change::Ks(k) => p.rod.ks *= k,
        Change::Kb(k) => p.rod.kb *= k,
        Change::Mu(mu) => p.rod.mu = mu,
        Change::Gravity(g) => {
            p.terms.gravity = true;
            p.rod.gravity *= g;
        }
        Change::CoincidentNodes => coincident_nodes(&mut fabric)?,
        Change::ZeroLengthSegment => zero_length_segment(&mut fabric)?,
    }
    Ok((fabric, p))
}

/// A non-contact point in the middle of the first yarn and its next point:
/// the first point's node moves onto the second's.
fn coincident_nodes(f: &mut Fabric) -> Result<(), String> {
    let (a, b) = middle_pair(f)?;
    f.nodes[a].x = f.nodes[b].x;
    Ok(())
}

/// The same pair gets equal `u`: a segment without rest length.
fn zero_length_segment(f: &mut Fabric) -> Result<(), String> {
    let y = &mut f.yarns[0];
    let k = y.points.len() / 2;
    if k + 1 >= y.points.len() {
        return Err("yarn too short to perturb".into());
    }
    y.points[k + 1].u = y.points[k].u;
    Ok(())
}

fn middle_pair(f: &Fabric) -> Result<(usize, usize), String> {
    let y = f.yarns.first().ok_or("no yarn")?;
    let k = y.points.len() / 2;
    if k + 1 >= y.points.len() {
        return Err("yarn too short to perturb".into());
    }
    Ok((y.points[k].node, y.points[k + 1].node))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A case marked "contact off" runs without thickness contact, and the
    /// others with it, whatever `params_for` turns on by default.
    #[test]
    fn contact_off_cases_have_no_thickness_contact() {
        let all = super::all(4, 1);
        let off: Vec<_> = all.iter().filter(|c| !c.contact).collect();
        assert!(off.len() >= 3, "{} contact-off cases", off.len());
        for c in all.iter().filter(|c| matches!(c.change, Change::None) || !c.contact) {
            let Ok((_, p)) = build(c) else { continue };
            assert_eq!(p.contact.is_some(), c.contact, "{}", c.name);
        }
    }
}
