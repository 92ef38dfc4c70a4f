//! knitsim's contact building blocks against ipc-toolkit (ipctk 1.6.1)
//! reference values; regenerate with `python3 scripts/ipctk_fixtures.py`.
//!
//! Mapping of conventions:
//! - Barrier: ipctk's scalar `barrier(d, dhat)` (and derivatives) is compared
//!   1:1 with `barrier(d, a)`, both on the unsquared distance. ipctk's
//!   `BarrierPotential` evaluates `b(d^2, dhat^2)`; that value is checked too.
//! - Distances: ipctk returns squared distances, compared with our `*_sq`.
//!   Types are compared by ipctk name, except two documented differences
//!   (see `contact::distance::classify`): near-parallel edges below our
//!   `PARALLEL_SIN2` use an endpoint type where ipctk may still use EA_EB,
//!   and a zero-length edge that projects outside the other edge, where
//!   ipctk's point-line type underestimates the distance; there we check
//!   the true distance instead.
//! - CCD: both are additive CCD with rescaling 0.9; ours must never be later
//!   than ipctk's time (plus 1e-9) and not absurdly earlier (>= 0.8x).

use knitsim::contact::barrier::{barrier, barrier_d1, barrier_d2};
use knitsim::contact::ccd::{edge_edge_toi, point_edge_toi, CcdParams};
use knitsim::contact::distance::{
    edge_edge_distance_sq, edge_edge_type, point_edge_distance_sq, point_edge_type, PARALLEL_SIN2,
};
use nalgebra::Vector3;
use serde_json::Value;

type V3 = Vector3<f64>;

fn load(name: &str) -> Value {
    let path = format!("{}/tests/fixtures/ipctk/{name}.json", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    serde_json::from_str(&text).expect("fixture is valid JSON")
}

fn f(v: &Value) -> f64 {
    v.as_f64().expect("number")
}

fn points(v: &Value) -> Vec<V3> {
    v.as_array()
        .expect("point list")
        .iter()
        .map(|p| {
            let c: Vec<f64> = p.as_array().expect("point").iter().map(f).collect();
            V3::new(c[0], c[1], c[2])
        })
        .collect()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(1e-300)
}

#[test]
fn barrier_matches_ipctk() {
    let fx = load("barrier");
    let rows = fx["rows"].as_array().expect("rows");
    assert!(rows.len() >= 50);
    for r in rows {
        let (d, a) = (f(&r["d"]), f(&r["dhat"]));
        for (ours, theirs, what) in [
            (barrier(d, a), f(&r["b"]), "b"),
            (barrier_d1(d, a), f(&r["db"]), "b'"),
            (barrier_d2(d, a), f(&r["d2b"]), "b''"),
        ] {
            // Absolute floor for values that vanish at d = dhat.
            let err = (ours - theirs).abs() / theirs.abs().max(ours.abs()).max(1e-12 * a * a);
            assert!(err < 1e-10, "{what}({d}, {a}): {ours} vs ipctk {theirs}");
        }
    }
    // ipctk's BarrierPotential is b(d^2, dhat^2) with our scalar function.
    let p = &fx["barrier_potential"];
    let (d, dhat) = (f(&p["distance"]), f(&p["dhat"]));
    assert!(rel(f(&p["stiffness"]) * barrier(d * d, dhat * dhat), f(&p["value"])) < 1e-12);
    assert!(
        rel(barrier(d, dhat), f(&p["value"])) > 0.1,
        "the two conventions differ"
    );
}

fn sin2(p: &[V3]) -> f64 {
    let (u, v) = (p[1] - p[0], p[3] - p[2]);
    u.cross(&v).norm_squared() / (u.norm_squared() * v.norm_squared())
}

/// Segment distance by dense sampling plus the endpoint cases (reference
/// for the cases where ipctk's degenerate handling is not the true distance).
fn sampled_sq(p: &[V3]) -> f64 {
    let n = 400;
    let mut best = f64::INFINITY;
    for i in 0..=n {
        let a = p[0] + (p[1] - p[0]) * (i as f64 / n as f64);
        best = best.min(point_edge_distance_sq(&a, &p[2], &p[3]));
    }
    best
}

#[test]
fn edge_edge_distances_match_ipctk() {
    let fx = load("distance");
    let cases = fx["edge_edge"].as_array().expect("cases");
    let (mut same_type, mut parallel_fallback, mut degenerate) = (0, 0, 0);
    for c in cases {
        let p = points(&c["points"]);
        let label = c["label"].as_str().unwrap_or("");
        let theirs = f(&c["distance_sq"]);
        let ours = edge_edge_distance_sq(&p[0], &p[1], &p[2], &p[3]);
        let ty = edge_edge_type(&p[0], &p[1], &p[2], &p[3]).ipctk_name();
        let ipctk_ty = c["type"].as_str().unwrap_or("");
        let zero_len = (p[1] - p[0]).norm() == 0.0 || (p[3] - p[2]).norm() == 0.0;
        if ty != ipctk_ty {
            eprintln!("type differs: {label}: ours {ty}, ipctk {ipctk_ty}");
        }
        if ty == ipctk_ty {
            same_type += 1;
            assert!(
                (ours - theirs).abs() <= 1e-10 * theirs.max(1e-12),
                "{label}: {ours} vs {theirs}"
            );
        } else if zero_len {
            // ipctk uses point-line for a degenerate edge; we use the true distance.
            degenerate += 1;
            assert!(
                (ours - sampled_sq(&p)).abs() < 1e-12,
                "{label}: {ours} not the true distance"
            );
            assert!(
                ours >= theirs - 1e-15,
                "{label}: true distance below ipctk's point-line value"
            );
        } else {
            parallel_fallback += 1;
            assert!(
                sin2(&p) < PARALLEL_SIN2,
                "{label}: type {ty} vs ipctk {ipctk_ty}, not near-parallel"
            );
            assert!((ours - theirs).abs() <= 1e-10 * theirs, "{label}: {ours} vs {theirs}");
        }
    }
    assert!(
        same_type >= cases.len() - 5,
        "{same_type} of {} types agree",
        cases.len()
    );
    eprintln!("edge-edge: {same_type} same type, {parallel_fallback} parallel fallback, {degenerate} degenerate");
}

#[test]
fn point_edge_distances_match_ipctk() {
    let fx = load("distance");
    for c in fx["point_edge"].as_array().expect("cases") {
        let p = points(&c["points"]);
        let label = c["label"].as_str().unwrap_or("");
        let ours = point_edge_distance_sq(&p[0], &p[1], &p[2]);
        let theirs = f(&c["distance_sq"]);
        assert_eq!(
            point_edge_type(&p[0], &p[1], &p[2]).ipctk_name(),
            c["type"].as_str().unwrap_or(""),
            "{label}"
        );
        assert!(
            (ours - theirs).abs() <= 1e-10 * theirs.max(1e-12),
            "{label}: {ours} vs {theirs}"
        );
    }
}

#[test]
fn additive_ccd_is_never_later_than_ipctk() {
    let fx = load("ccd");
    assert_eq!(f(&fx["conservative_rescaling"]), 0.9);
    let params = CcdParams {
        conservative_rescaling: 0.9,
        ..CcdParams::default()
    };
    let mut compared = 0;
    for (key, n) in [("edge_edge", 4), ("point_edge", 3)] {
        for c in fx[key].as_array().expect("cases") {
            let (x0, x1) = (points(&c["x0"]), points(&c["x1"]));
            let dx: Vec<V3> = x0.iter().zip(&x1).map(|(a, b)| b - a).collect();
            let xi = f(&c["min_distance"]);
            let ours = if n == 4 {
                edge_edge_toi(
                    [&x0[0], &x0[1], &x0[2], &x0[3]],
                    [&dx[0], &dx[1], &dx[2], &dx[3]],
                    xi,
                    &params,
                )
            } else {
                point_edge_toi([&x0[0], &x0[1], &x0[2]], [&dx[0], &dx[1], &dx[2]], xi, &params)
            };
            let theirs = f(&c["toi"]);
            let label = c["label"].as_str().unwrap_or("");
            assert!(ours <= theirs + 1e-9, "{key} {label}: {ours} later than ipctk {theirs}");
            assert!(
                ours >= 0.8 * theirs,
                "{key} {label}: {ours} far earlier than ipctk {theirs}"
            );
            compared += 1;
        }
    }
    assert!(compared >= 30);
}
