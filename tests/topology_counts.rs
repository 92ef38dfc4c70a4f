//! Hand-counted contacts, loops, floats and yarn pieces: for the shipped
//! pattern files behind `knitsim compile PATTERN --stats` (stockinette,
//! 1x1 rib, linen stitch, jacquard), and for small inline patches. Every
//! expected number is derived in the comments from the chart and the
//! contact rules (`topology` module docs, docs/MODEL.md, "Stitch contact layout"), not from the
//! program's output. Inline charts are drawn top row first (see
//! `topology::sample`).

mod common;

use knitsim::pattern::{Construction, Pattern};
use knitsim::topology::sample::chart_pattern;
use knitsim::topology::{compile, stats, CompileOptions, Fabric, Stats};

fn build(chart: &[&str], colours: Option<&[&str]>, c: Construction) -> (Pattern, Fabric, Stats) {
    let p = chart_pattern(chart, colours, c).expect("chart");
    let f = compile(&p, &CompileOptions::default()).expect("compile");
    let s = stats(&p, &f);
    (p, f, s)
}

/// What `knitsim compile PATTERN --stats` prints for a shipped file.
fn shipped_stats(stem: &str) -> (Fabric, Stats) {
    let p = common::shipped(stem);
    let f = compile(&p, &CompileOptions::default()).expect(stem);
    let s = stats(&p, &f);
    (f, s)
}

#[test]
fn shipped_stockinette() {
    // stockinette.knit: 16 sts x 16 rows, every cell a knit.
    // 16 x 16 = 256 knit loops, plus a 16-loop cast-on: 272 loops.
    // Every knit loop is pulled through exactly one parent (the loop below),
    // 2 stitch contacts (one per leg) of 2 nodes: 256 x 4 = 1024 nodes.
    // No slips, no colours: no floats, no float nodes. One yarn turning at
    // each edge: 1 piece.
    let (_, s) = shipped_stats("stockinette");
    assert_eq!(s.yarns, 1);
    assert_eq!((s.knit, s.purl, s.slip_front, s.slip_back, s.tuck), (256, 0, 0, 0, 0));
    assert_eq!((s.loops, s.cast_on_loops), (272, 16));
    assert_eq!(s.stitch_contacts, 1024);
    assert_eq!(s.float_contacts + s.tuck_contacts + s.layer_contacts, 0);
    assert_eq!(s.contact_nodes, 1024);
    assert_eq!(s.floats, 0);
    assert_eq!(s.longest_float_per_row, vec![0; 16]);
}

#[test]
fn shipped_rib_1x1() {
    // rib-1x1.knit: chart `[. -] .` at width 17: 8 repeats of knit, purl
    // and a closing knit, so each row has 9 knit and 8 purl columns.
    // 16 rows: 144 knit, 128 purl; loops 272 + 17 cast-on = 289.
    // Each of the 272 chart loops has one parent: 272 x 4 = 1088 stitch
    // nodes. A knit child is the front point of its contacts, a purl child
    // the back point, and (one yarn) the child is worked after its parent:
    // 144 x 4 = 576 contacts with front.u > back.u, 128 x 4 = 512 with <.
    let (f, s) = shipped_stats("rib-1x1");
    assert_eq!(s.yarns, 1);
    assert_eq!((s.knit, s.purl), (144, 128));
    assert_eq!((s.loops, s.cast_on_loops), (289, 17));
    assert_eq!(s.stitch_contacts, 1088);
    assert_eq!(s.contact_nodes, 1088);
    assert_eq!(s.floats, 0);
    let u = |r: knitsim::topology::PointRef| f.yarns[r.yarn].points[r.point].u;
    let knit_like = f.contacts.iter().filter(|c| u(c.front) > u(c.back)).count();
    assert_eq!((knit_like, f.contacts.len() - knit_like), (576, 512));
}

#[test]
fn shipped_linen_stitch() {
    // linen-stitch.knit: 20 sts x 16 rows. Row 1 `. [. v] .`: edge knit,
    // 9 x (knit, slip), edge knit -> 9 slips (cols 2, 4, .., 18), 11 knits.
    // Row 2 `. [v .] .`: 9 slips (cols 1, 3, .., 17), 11 knits.
    // 16 rows: 176 knit, 144 slips with the float on the RS (wyif on RS
    // rows, wyib on WS rows, both RS floats in fabric view).
    // Loops: 176 + 20 cast-on = 196. Each knit loop has one parent (the
    // loop below, or the one held through the slip): 176 x 4 = 704 stitch
    // nodes. Each slip's float crosses the 2 legs of the held loop: 288
    // float nodes; 992 contact nodes in all.
    // Floats: every slip is a single-stitch run between knits: 9 per row,
    // 144 floats, longest 1 in every row.
    let (_, s) = shipped_stats("linen-stitch");
    assert_eq!(s.yarns, 1);
    assert_eq!((s.knit, s.slip_front, s.slip_back), (176, 144, 0));
    assert_eq!((s.loops, s.cast_on_loops), (196, 20));
    assert_eq!(s.stitch_contacts, 704);
    assert_eq!(s.float_contacts, 288);
    assert_eq!(s.contact_nodes, 992);
    assert_eq!(s.floats, 144);
    assert_eq!(s.longest_float_per_row, vec![1; 16]);
}

#[test]
fn shipped_jacquard() {
    // jacquard.knit: 18 sts x 12 rows, all knit; the 6 x 6 chart (no
    // brackets, so the whole row repeats 3 times) has CC (`x`) at, per
    // repeat and bottom row first:
    //   row 1: col 2         row 2: cols 1-3     row 3: cols 0-4
    //   row 4: cols 1-3      row 5: col 2        row 6: none (MC only)
    // and rows 7-12 repeat rows 1-6.
    // Stitches: 18 x 12 = 216 knit; loops 216 + 18 cast-on = 234; each
    // has one parent: 216 x 4 = 864 stitch nodes.
    // Float nodes: in a two-colour row each yarn travels the whole row
    // (it turns at the edges), so each of the 18 columns has one loop and
    // the other yarn's strand behind it crossing its 2 legs: 36 nodes per
    // two-colour row; rows 1-5 and 7-11: 10 x 36 = 360.
    // Floats (per yarn and row, maximal no-loop runs, edge runs included):
    //   row 1: MC {2},{8},{14}; CC 0-1, 3-7, 9-13, 15-17   -> 7, longest 5
    //   row 2: MC 1-3, 7-9, 13-15; CC 0, 4-6, 10-12, 16-17 -> 7, longest 3
    //   row 3: MC 0-4, 6-10, 12-16; CC {5},{11},{17}       -> 6, longest 5
    //   rows 4, 5 as rows 2, 1; row 6 none. Per 6 rows 34; 68 in all.
    // Yarn pieces: MC works every row and turns at each edge: 1 piece. CC
    // ends RS row 5 at the left edge, skips row 6, and RS row 7 starts at
    // the right edge: cut and rejoined, 2 pieces; 3 in all.
    let (f, s) = shipped_stats("jacquard");
    assert_eq!(s.yarns, 3);
    assert_eq!((s.knit, s.purl), (216, 0));
    assert_eq!((s.loops, s.cast_on_loops), (234, 18));
    assert_eq!(s.stitch_contacts, 864);
    assert_eq!(s.float_contacts, 360);
    assert_eq!(s.contact_nodes, 1224);
    assert_eq!(s.floats, 68);
    assert_eq!(
        s.longest_float_per_row,
        [[5, 3, 5, 3, 5, 0], [5, 3, 5, 3, 5, 0]].concat()
    );
    // A strand is the back point and never the loop's own colour.
    for c in f
        .contacts
        .iter()
        .filter(|c| c.kind == knitsim::topology::ContactKind::Float)
    {
        assert_ne!(f.yarns[c.front.yarn].spec, f.yarns[c.back.yarn].spec);
    }
}

#[test]
fn stockinette_4x3() {
    // 12 knit loops + 4 cast-on loops. Every chart loop has one parent:
    // 2 stitch contacts x 2 nodes = 4 nodes each -> 48 stitch nodes.
    // One yarn: the cast-on ends at the right where RS row 1 starts, row 1
    // ends left where WS row 2 starts, and so on.
    for c in [Construction::Flat, Construction::Round] {
        let (_, f, s) = build(&["kkkk", "kkkk", "kkkk"], None, c);
        assert_eq!(s.yarns, 1, "{c:?}");
        assert_eq!(s.knit, 12);
        assert_eq!(s.loops, 16);
        assert_eq!(s.stitch_contacts, 48);
        assert_eq!(s.float_contacts + s.tuck_contacts + s.layer_contacts, 0);
        assert_eq!(s.contact_nodes, 48);
        assert_eq!(f.contacts.len(), 48);
        assert_eq!(s.floats, 0);
        assert_eq!(s.longest_float_per_row, vec![0, 0, 0]);
    }
}

#[test]
fn rib_1x1_4x2() {
    // Fabric view "kpkp" on both rows: 4 knit + 4 purl loops, 8 x 4 = 32
    // stitch nodes. With one yarn the child of a contact is worked after its
    // parent, so it has the larger u. A knit child is the front point, a
    // purl child the back point: 16 contacts with front.u > back.u (knit),
    // 16 with front.u < back.u (purl).
    let (_, f, s) = build(&["kpkp", "kpkp"], None, Construction::Flat);
    assert_eq!((s.knit, s.purl, s.yarns), (4, 4, 1));
    assert_eq!(s.stitch_contacts, 32);
    let u = |r: knitsim::topology::PointRef| f.yarns[r.yarn].points[r.point].u;
    let knit_like = f.contacts.iter().filter(|c| u(c.front) > u(c.back)).count();
    assert_eq!(knit_like, 16);
    assert_eq!(f.contacts.len() - knit_like, 16);
}

#[test]
fn linen_stitch_4x2() {
    // Linen stitch in fabric view: row 1 "kvkv", row 2 "vkvk" (RS: k1, sl1
    // wyif; WS: p1, sl1 wyib; both floats lie on the RS).
    // Loops: 4 knit + 4 cast-on = 8. Each knit loop has one parent (the one
    // below, or the loop held through the slip): 4 x 4 = 16 stitch nodes.
    // Slips: 4, each float crossing the 2 legs of the held loop -> 8 float
    // nodes. Floats per row: 2 single-stitch runs -> 4 floats, longest 1.
    let (_, _, s) = build(&["vkvk", "kvkv"], None, Construction::Flat);
    assert_eq!(s.yarns, 1);
    assert_eq!((s.knit, s.slip_front, s.slip_back), (4, 4, 0));
    assert_eq!(s.loops, 8);
    assert_eq!(s.stitch_contacts, 16);
    assert_eq!(s.float_contacts, 8);
    assert_eq!(s.contact_nodes, 24);
    assert_eq!(s.floats, 4);
    assert_eq!(s.longest_float_per_row, vec![1, 1]);
}

#[test]
fn jacquard_two_colours_4x2() {
    // Colours (bottom row first): row 1 = 1001, row 2 = 0110, all knit.
    // Yarns: yarn 1 casts on (it starts row 1) and turns at each edge; yarn 0
    // joins at row 1's right edge and also turns: 2 pieces.
    // Loops: 8 + 4 cast-on = 12; stitch nodes 8 x 4 = 32.
    // Each row each column has one loop and one strand behind it crossing
    // its 2 legs: 2 rows x 4 columns x 2 = 16 float nodes.
    // Floats: row 1 yarn 0 skips cols 0 and 3 (2 runs), yarn 1 skips cols
    // 1-2 (1 run of 2): 3 floats, longest 2; row 2 likewise.
    let (_, f, s) = build(&["kkkk", "kkkk"], Some(&["0110", "1001"]), Construction::Flat);
    assert_eq!(s.yarns, 2);
    assert_eq!(s.loops, 12);
    assert_eq!(s.stitch_contacts, 32);
    assert_eq!(s.float_contacts, 16);
    assert_eq!(s.floats, 6);
    assert_eq!(s.longest_float_per_row, vec![2, 2]);
    // A strand is always the back yarn and never the loop's own colour.
    for c in f
        .contacts
        .iter()
        .filter(|c| c.kind == knitsim::topology::ContactKind::Float)
    {
        assert_ne!(f.yarns[c.front.yarn].spec, f.yarns[c.back.yarn].spec);
    }
}

#[test]
fn tuck_3x2() {
    // Row 1 "ktk": the tuck sits on cast-on loop 1 and crosses its 2 legs
    // (2 tuck nodes). Row 2's middle child passes through both heads: 8
    // stitch nodes; the other 4 knit loops have one parent each: 16.
    // Loops: 5 knit + 1 tuck + 3 cast-on = 9.
    let (_, _, s) = build(&["kkk", "ktk"], None, Construction::Flat);
    assert_eq!((s.knit, s.tuck), (5, 1));
    assert_eq!(s.loops, 9);
    assert_eq!(s.stitch_contacts, 24);
    assert_eq!(s.tuck_contacts, 2);
    assert_eq!(s.floats, 0);
}

#[test]
fn stripes_cut_and_carry() {
    // One-row stripes 0,1,0 (bottom first). Flat: yarn 0 ends RS row 1 at the
    // left but row 3 (RS) starts at the right -> cut and rejoin: 3 pieces.
    // Round: yarn 0 skips row 2 -> cut and rejoin too: 3 pieces.
    let stripes = ["kkkk", "kkkk", "kkkk"];
    let colours = ["0000", "1111", "0000"];
    for c in [Construction::Flat, Construction::Round] {
        let (_, _, s) = build(&stripes, Some(&colours), c);
        assert_eq!(s.yarns, 3, "{c:?}");
    }
    // Two-row stripes, flat: yarn 0 ends WS row 2 at the right, where RS
    // row 5 starts: carried up the side, so only 2 pieces.
    let tall = ["kkkk"; 6];
    let colours2 = ["0000", "0000", "1111", "1111", "0000", "0000"];
    let (_, _, s) = build(&tall, Some(&colours2), Construction::Flat);
    assert_eq!(s.yarns, 2);
}

#[test]
fn stats_table_names_every_count() {
    let (_, _, s) = build(&["vkvk", "kvkv"], None, Construction::Flat);
    let text = s.to_string();
    for needle in [
        "yarn pieces",
        "slip, yarn in front",
        "contact nodes",
        "floats",
        "rest yarn length",
    ] {
        assert!(text.contains(needle), "{text}");
    }
    assert!(text.contains("4 (1 sts)"), "{text}");
}
