use super::*;
use crate::contact::test_util::Rng;

fn v(x: f64, y: f64, z: f64) -> V3 {
    V3::new(x, y, z)
}

/// First time on a fine grid where the distance drops to `xi` (1 if never),
/// and whether the distance stays above `xi` on `[0, toi]`.
fn sampled_impact(p: &[V3; 4], dp: &[V3; 4], xi: f64) -> f64 {
    let n = 20_000;
    for k in 0..=n {
        let t = k as f64 / n as f64;
        let q: [V3; 4] = std::array::from_fn(|i| p[i] + dp[i] * t);
        if edge_edge_distance_sq(&q[0], &q[1], &q[2], &q[3]).sqrt() <= xi {
            return t;
        }
    }
    1.0
}

fn toi(p: &[V3; 4], dp: &[V3; 4], xi: f64) -> f64 {
    edge_edge_toi(
        [&p[0], &p[1], &p[2], &p[3]],
        [&dp[0], &dp[1], &dp[2], &dp[3]],
        xi,
        &CcdParams::default(),
    )
}

#[test]
fn head_on_edges_stop_short_by_the_rescaling() {
    // B falls onto A at speed 2: contact at t = 0.5. The first additive step
    // covers 0.9 of the gap, the next would cross the 10% target: 0.45.
    let p = [v(-1.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, -1.0, 1.0), v(0.0, 1.0, 1.0)];
    let z = V3::zeros();
    let dp = [z, z, v(0.0, 0.0, -2.0), v(0.0, 0.0, -2.0)];
    let t = toi(&p, &dp, 0.0);
    assert!((t - 0.45).abs() < 1e-12, "{t}");
    // With a hard core of 0.2 the impact is at t = 0.4.
    let t = toi(&p, &dp, 0.2);
    assert!((0.8 * 0.4..=0.4).contains(&t), "{t}");
    // Moving apart, or a pure translation of both: no impact.
    let up = [z, z, v(0.0, 0.0, 2.0), v(0.0, 0.0, 2.0)];
    assert_eq!(toi(&p, &up, 0.0), 1.0);
    let all = [v(3.0, 1.0, 0.0); 4];
    assert_eq!(toi(&p, &all, 0.0), 1.0);
}

#[test]
fn never_later_than_sampled_impact() {
    let mut rng = Rng::new(11);
    let mut hits = 0;
    for _ in 0..300 {
        let p: [V3; 4] = std::array::from_fn(|_| v(rng.next(), rng.next(), rng.next()));
        // Rotating and translating edges: interior points move non-linearly
        // relative to each other.
        let dp: [V3; 4] = std::array::from_fn(|_| v(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5) * 2.0);
        let xi = 0.02 * rng.next();
        let d0 = edge_edge_distance_sq(&p[0], &p[1], &p[2], &p[3]).sqrt();
        if d0 <= xi {
            continue;
        }
        let t = toi(&p, &dp, xi);
        let truth = sampled_impact(&p, &dp, xi);
        assert!(t <= truth + 1e-4, "toi {t} after impact {truth}");
        // Everything up to the returned time is feasible.
        let q: [V3; 4] = std::array::from_fn(|i| p[i] + dp[i] * t);
        assert!(edge_edge_distance_sq(&q[0], &q[1], &q[2], &q[3]).sqrt() > xi);
        if truth < 1.0 {
            hits += 1;
            assert!(t >= 0.5 * truth, "too timid: {t} vs {truth}");
        }
    }
    assert!(hits > 20, "only {hits} impacts sampled");
}

#[test]
fn point_edge_and_step_fraction() {
    let z = V3::zeros();
    let t = point_edge_toi(
        [&v(0.5, 1.0, 0.0), &v(0.0, 0.0, 0.0), &v(1.0, 0.0, 0.0)],
        [&v(0.0, -4.0, 0.0), &z, &z],
        0.0,
        &CcdParams::default(),
    );
    // Impact at t = 0.25; additive CCD stops at 0.9 of it.
    assert!((t - 0.225).abs() < 1e-12, "{t}");
    let x = vec![
        v(-1.0, 0.0, 0.0),
        v(1.0, 0.0, 0.0),
        v(0.0, -1.0, 1.0),
        v(0.0, 1.0, 1.0),
        v(5.0, 5.0, 5.0),
        v(6.0, 5.0, 5.0),
    ];
    let dx = vec![z, z, v(0.0, 0.0, -2.0), v(0.0, 0.0, -2.0), z, z];
    let segs = [[0, 1], [2, 3], [4, 5]];
    let pairs = [([0, 1], 0.0), ([0, 2], 0.0), ([1, 2], 0.0)];
    let f = max_step_fraction(&x, &dx, &segs, &pairs, &CcdParams::default());
    assert!((f - 0.45).abs() < 1e-12);
}
