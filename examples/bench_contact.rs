//! Broad + narrow phase timing for yarn-like segment soups.
//!
//! `cargo run --release --no-default-features --example bench_contact [max_segments]`
//!
//! Yarns are smooth random walks of (at most) unit-length segments packed in
//! a slab (like a fabric layer, 0.5 segments per unit volume, whatever the size), with the activation
//! distance h = 0.5 segment lengths (the resolutions of the thickness-contact paper put several
//! segments per thickness; the broad phase cost depends on h / length).
//! The broad phase returns candidate pairs; the narrow phase computes every
//! candidate's segment distance and keeps those closer than h.

use knitsim::contact::broad_phase::edge_edge_candidates;
use knitsim::contact::distance::edge_edge_distance_sq;
use nalgebra::Vector3;
use std::time::Instant;

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn unit(&mut self) -> Vector3<f64> {
        Vector3::new(self.next() - 0.5, self.next() - 0.5, self.next() - 0.5)
    }
}

fn yarn_soup(segments: usize) -> (Vec<Vector3<f64>>, Vec<[usize; 2]>) {
    let per_yarn = 200;
    let density = 0.5;
    let slab = 8.0;
    let side = (segments as f64 / (density * slab)).sqrt();
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    let mut x = Vec::with_capacity(segments + segments / per_yarn + 1);
    let mut segs = Vec::with_capacity(segments);
    while segs.len() < segments {
        let mut p = Vector3::new(rng.next() * side, rng.next() * side, rng.next() * slab);
        let mut dir = rng.unit().normalize();
        x.push(p);
        for _ in 0..per_yarn.min(segments - segs.len()) {
            dir = (dir + rng.unit() * 0.5).normalize();
            p += dir;
            // Stay in the box (same density at every size): reflect off its faces.
            for (k, hi) in [side, side, slab].into_iter().enumerate() {
                if p[k] < 0.0 || p[k] > hi {
                    dir[k] = -dir[k];
                    p[k] = p[k].clamp(0.0, hi);
                }
            }
            x.push(p);
            segs.push([x.len() - 2, x.len() - 1]);
        }
    }
    (x, segs)
}

fn main() {
    let max: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1_000_000);
    let h = 0.5;
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    println!("activation h = {h} (segment length 1), {threads} threads");
    println!(
        "{:>10} {:>12} {:>10} {:>10} {:>10} {:>10}",
        "segments", "candidates", "active", "broad s", "narrow s", "us/seg"
    );
    let mut prev: Option<(usize, f64)> = None;
    for n in [10_000, 100_000, 1_000_000].into_iter().filter(|&n| n <= max) {
        let (x, segs) = yarn_soup(n);
        let t0 = Instant::now();
        let pairs = edge_edge_candidates(&x, &segs, h);
        let broad = t0.elapsed().as_secs_f64();
        let t1 = Instant::now();
        let active = pairs
            .iter()
            .filter(|&&[i, j]| {
                let (a, b) = (segs[i as usize], segs[j as usize]);
                edge_edge_distance_sq(&x[a[0]], &x[a[1]], &x[b[0]], &x[b[1]]) < h * h
            })
            .count();
        let narrow = t1.elapsed().as_secs_f64();
        let total = broad + narrow;
        println!(
            "{n:>10} {:>12} {active:>10} {broad:>10.3} {narrow:>10.3} {:>10.3}",
            pairs.len(),
            1e6 * total / n as f64
        );
        if let Some((pn, pt)) = prev {
            let exponent = (total / pt).ln() / (n as f64 / pn as f64).ln();
            println!("{:>10} scaling exponent vs {pn}: {exponent:.2} (1.00 = linear)", "");
        }
        prev = Some((n, total));
    }
}
