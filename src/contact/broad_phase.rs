//! Broad phase: candidate edge-edge pairs from a spatial hash over segment
//! bounding boxes.
//!
//! Each segment's box is inflated by half the activation distance, so two
//! segments closer than the activation distance have overlapping boxes
//! (per axis, their gap is at most their distance). Following docs/MODEL.md,
//! "Thickness contact", it builds the hash with the *unfiltered* activation distance (the material
//! thickness), so one structure serves every contact mode.
//!
//! Design, for a million segments on a few cores:
//! - Uniform grid, cell size = twice the mean box extent, so a box covers
//!   one to a few cells. Cells are hashed into a power-of-two table; collisions only cost
//!   extra box tests.
//! - The table is built by counting sort (two passes, no per-cell
//!   allocation); since segments are inserted in index order every bucket is
//!   sorted by segment index.
//! - Each pair is reported once, from the cell holding the lower corner of
//!   the two boxes' intersection: both boxes cover that cell, so it is found
//!   there and nowhere else, without a hash set.
//! - Queries are independent per segment; threads take contiguous index
//!   ranges and their outputs are concatenated, so the result is sorted by
//!   `(i, j)` whatever the thread count: deterministic order.

use nalgebra::Vector3;

/// Axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub lo: [f64; 3],
    pub hi: [f64; 3],
}

impl Aabb {
    /// Box of a set of points, inflated by `margin` on every side.
    pub fn of_points(points: &[&Vector3<f64>], margin: f64) -> Self {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in points {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        for k in 0..3 {
            lo[k] -= margin;
            hi[k] += margin;
        }
        Self { lo, hi }
    }

    pub fn overlaps(&self, other: &Aabb) -> bool {
        (0..3).all(|k| self.lo[k] <= other.hi[k] && other.lo[k] <= self.hi[k])
    }
}

/// Segment boxes at positions `x`, inflated by `activation / 2`.
pub fn segment_boxes(x: &[Vector3<f64>], segments: &[[usize; 2]], activation: f64) -> Vec<Aabb> {
    segments
        .iter()
        .map(|s| Aabb::of_points(&[&x[s[0]], &x[s[1]]], 0.5 * activation))
        .collect()
}

/// Boxes of the segments swept from `x` to `x + dx` (for CCD), inflated by
/// `margin / 2`.
pub fn swept_segment_boxes(x: &[Vector3<f64>], dx: &[Vector3<f64>], segments: &[[usize; 2]], margin: f64) -> Vec<Aabb> {
    segments
        .iter()
        .map(|s| {
            let (a, b) = (x[s[0]], x[s[1]]);
            let (a1, b1) = (a + dx[s[0]], b + dx[s[1]]);
            Aabb::of_points(&[&a, &b, &a1, &b1], 0.5 * margin)
        })
        .collect()
}

/// Candidate edge-edge pairs `(i, j)`, `i < j`, of segments whose inflated
/// boxes overlap and that share no node; sorted by `(i, j)`.
pub fn edge_edge_candidates(x: &[Vector3<f64>], segments: &[[usize; 2]], activation: f64) -> Vec<[u32; 2]> {
    overlapping_pairs(&segment_boxes(x, segments, activation), segments)
}

/// Pairs of overlapping boxes, excluding segments that share a node.
pub fn overlapping_pairs(boxes: &[Aabb], segments: &[[usize; 2]]) -> Vec<[u32; 2]> {
    if boxes.len() < 2 {
        return Vec::new();
    }
    let grid = Grid::build(boxes);
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).min(16);
    // Several chunks per thread balance uneven density without a work queue.
    let chunk = boxes.len().div_ceil(threads * 4).max(1024);
    let ranges: Vec<(usize, usize)> = (0..boxes.len())
        .step_by(chunk)
        .map(|s| (s, (s + chunk).min(boxes.len())))
        .collect();
    let next = std::sync::atomic::AtomicUsize::new(0);
    let mut parts: Vec<(usize, Vec<[u32; 2]>)> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut done = Vec::new();
                    loop {
                        let r = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        let Some(&(s, e)) = ranges.get(r) else { break };
                        let mut out = Vec::new();
                        for i in s..e {
                            grid.query(i, boxes, segments, &mut out);
                        }
                        done.push((r, out));
                    }
                    done
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .collect()
    });
    parts.sort_unstable_by_key(|p| p.0);
    let total = parts.iter().map(|p| p.1.len()).sum();
    let mut pairs = Vec::with_capacity(total);
    for (_, p) in parts {
        pairs.extend(p);
    }
    pairs
}

/// Hashed uniform grid holding every box in every cell it covers.
struct Grid {
    origin: [f64; 3],
    inv_cell: f64,
    mask: usize,
    /// `starts[b]..starts[b + 1]` indexes `entries` for bucket `b`.
    starts: Vec<u32>,
    entries: Vec<u32>,
}

impl Grid {
    fn build(boxes: &[Aabb]) -> Self {
        let mut origin = [f64::INFINITY; 3];
        let mut extent_sum = 0.0;
        let mut extent_max: f64 = 0.0;
        for b in boxes {
            for (o, lo) in origin.iter_mut().zip(b.lo) {
                *o = o.min(lo);
            }
            let extent = (0..3).map(|k| b.hi[k] - b.lo[k]).fold(0.0, f64::max);
            extent_sum += extent;
            extent_max = extent_max.max(extent);
        }
        // A few outsized boxes must not cover millions of cells.
        // Twice the mean extent: measured on 1M yarn-like segments, fewer
        // (cache-missing) bucket lookups beat the extra box tests (1.3 s vs
        // 2.5 s at 1x, no gain at 3x).
        let cell = (2.0 * extent_sum / boxes.len() as f64)
            .max(extent_max / 32.0)
            .max(f64::MIN_POSITIVE);
        let mut grid = Grid {
            origin,
            inv_cell: 1.0 / cell,
            mask: 0,
            starts: Vec::new(),
            entries: Vec::new(),
        };
        let covered: usize = boxes.iter().map(|b| grid.cell_count(b)).sum();
        let buckets = (2 * covered).next_power_of_two().max(16);
        grid.mask = buckets - 1;
        let mut counts = vec![0u32; buckets + 1];
        for b in boxes {
            grid.for_cells(b, |_, h| counts[h] += 1);
        }
        let mut acc = 0u32;
        for c in counts.iter_mut() {
            let n = *c;
            *c = acc;
            acc += n;
        }
        let mut fill = counts.clone();
        let mut entries = vec![0u32; acc as usize];
        for (i, b) in boxes.iter().enumerate() {
            grid.for_cells(b, |_, h| {
                entries[fill[h] as usize] = i as u32;
                fill[h] += 1;
            });
        }
        grid.starts = counts;
        grid.entries = entries;
        grid
    }

    fn cell_of(&self, p: f64, k: usize) -> i64 {
        ((p - self.origin[k]) * self.inv_cell).floor() as i64
    }

    fn cell_range(&self, b: &Aabb) -> [(i64, i64); 3] {
        std::array::from_fn(|k| (self.cell_of(b.lo[k], k), self.cell_of(b.hi[k], k)))
    }

    fn cell_count(&self, b: &Aabb) -> usize {
        self.cell_range(b).iter().map(|(l, h)| (h - l + 1) as usize).product()
    }

    fn hash(&self, c: [i64; 3]) -> usize {
        let h = (c[0].wrapping_mul(73_856_093)) ^ (c[1].wrapping_mul(19_349_663)) ^ (c[2].wrapping_mul(83_492_791));
        (h as usize) & self.mask
    }

    fn for_cells(&self, b: &Aabb, mut f: impl FnMut([i64; 3], usize)) {
        let r = self.cell_range(b);
        for ix in r[0].0..=r[0].1 {
            for iy in r[1].0..=r[1].1 {
                for iz in r[2].0..=r[2].1 {
                    let c = [ix, iy, iz];
                    f(c, self.hash(c));
                }
            }
        }
    }

    /// Appends the pairs `(i, j)`, `j > i`, sorted by `j`.
    fn query(&self, i: usize, boxes: &[Aabb], segments: &[[usize; 2]], out: &mut Vec<[u32; 2]>) {
        let bi = &boxes[i];
        let si = segments[i];
        let first = out.len();
        self.for_cells(bi, |cell, h| {
            let bucket = &self.entries[self.starts[h] as usize..self.starts[h + 1] as usize];
            // Buckets are sorted by index: skip to the indices above i.
            let from = bucket.partition_point(|&j| j as usize <= i);
            let mut prev = u32::MAX;
            for &j in &bucket[from..] {
                if j == prev {
                    continue;
                }
                prev = j;
                let bj = &boxes[j as usize];
                if !bi.overlaps(bj) {
                    continue;
                }
                let owner: [i64; 3] = std::array::from_fn(|k| self.cell_of(bi.lo[k].max(bj.lo[k]), k));
                if owner != cell {
                    continue;
                }
                let sj = segments[j as usize];
                if sj.contains(&si[0]) || sj.contains(&si[1]) {
                    continue;
                }
                out.push([i as u32, j]);
            }
        });
        out[first..].sort_unstable();
    }
}

#[cfg(test)]
mod tests;
