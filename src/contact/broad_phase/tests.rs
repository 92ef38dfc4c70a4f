use super::*;
use crate::contact::distance::edge_edge_distance_sq;
use crate::contact::test_util::polyline_soup;
use crate::contact::test_util::Rng;

fn brute_force(boxes: &[Aabb], segs: &[[usize; 2]]) -> Vec<[u32; 2]> {
    let mut out = Vec::new();
    for i in 0..boxes.len() {
        for j in i + 1..boxes.len() {
            let shared = segs[j].contains(&segs[i][0]) || segs[j].contains(&segs[i][1]);
            if !shared && boxes[i].overlaps(&boxes[j]) {
                out.push([i as u32, j as u32]);
            }
        }
    }
    out
}

#[test]
fn matches_brute_force_on_polyline_soups() {
    for (seed, yarns, len, step, activation) in [(1, 20, 40, 0.1, 0.05), (2, 60, 15, 0.1, 0.2), (3, 5, 200, 0.01, 0.02)]
    {
        let (x, segs) = polyline_soup(seed, yarns, len, step, 1.0);
        let boxes = segment_boxes(&x, &segs, activation);
        let fast = overlapping_pairs(&boxes, &segs);
        let slow = brute_force(&boxes, &segs);
        assert!(slow.len() > 20, "seed {seed}: only {} pairs", slow.len());
        assert_eq!(fast, slow, "seed {seed}");
        // Conservative: every pair closer than the activation distance is there.
        for (i, j) in (0..segs.len()).flat_map(|i| (i + 1..segs.len()).map(move |j| (i, j))) {
            let (a, b) = (segs[i], segs[j]);
            if b.contains(&a[0]) || b.contains(&a[1]) {
                continue;
            }
            let d = edge_edge_distance_sq(&x[a[0]], &x[a[1]], &x[b[0]], &x[b[1]]).sqrt();
            if d < activation {
                assert!(
                    fast.binary_search(&[i as u32, j as u32]).is_ok(),
                    "missed {i} {j} at {d}"
                );
            }
        }
    }
}

#[test]
fn matches_brute_force_on_mixed_sizes() {
    // Segments of very different lengths, including zero-length ones and
    // one spanning the whole box (stresses the cell-size choice).
    let mut rng = Rng::new(77);
    let mut x = Vec::new();
    let mut segs = Vec::new();
    for k in 0..300 {
        let p = Vector3::new(rng.next(), rng.next(), rng.next());
        let len = [0.0, 0.01, 0.1, 0.5][k % 4];
        let q = p + Vector3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5) * len;
        x.extend([p, q]);
        segs.push([2 * k, 2 * k + 1]);
    }
    x.extend([Vector3::zeros(), Vector3::new(1.0, 1.0, 1.0)]);
    segs.push([600, 601]);
    let boxes = segment_boxes(&x, &segs, 0.02);
    assert_eq!(overlapping_pairs(&boxes, &segs), brute_force(&boxes, &segs));
}

#[test]
fn excludes_neighbours_and_is_deterministic() {
    let (x, segs) = polyline_soup(5, 3, 50, 0.02, 0.2);
    let a = edge_edge_candidates(&x, &segs, 0.05);
    let b = edge_edge_candidates(&x, &segs, 0.05);
    assert_eq!(a, b);
    assert!(a.windows(2).all(|w| w[0] < w[1]));
    assert!(a
        .iter()
        .all(|&[i, j]| j != i + 1 || segs[i as usize][1] != segs[j as usize][0]));
}
