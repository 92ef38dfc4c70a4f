//! Where each stencil's `N x N` Hessian block lands in the CSR values.
//!
//! Why not a binary search per entry: every relaxation step rebuilds its
//! stencil sets (the EIL assignment changes the discretization), and a
//! 40x40 linen stitch has about 8 million block entries. Searching each
//! one in its row took 0.35 to 0.42 s per step, more than a Newton
//! iteration. Here the entries are grouped by row: each row's columns are
//! stamped once into a dense position map, and every stencil row in it
//! reads its `N` slots from that map, so the work is one pass over the
//! touched rows plus one lookup per entry.

use crate::sparse::CsrMatrix;

/// The value position of entry `(dofs[k][i], dofs[k][j])` at index
/// `(k N + i) N + j`, or the first entry missing from `h`'s pattern as
/// `Err((row, col))`. Every index in `dofs` must be below `h.n`, and `h`
/// must have fewer than `2^32` entries (the caller checks).
///
/// Positions are `u32`: the scatter streams them every Newton iteration
/// (31 MB of `usize` slots for a 40x40 linen stitch's bending and
/// wrapping stencils), and half the bytes is half that traffic.
pub fn block_slots<const N: usize>(dofs: &[[u32; N]], h: &CsrMatrix) -> Result<Vec<u32>, (usize, usize)> {
    // The stencil rows in each matrix row, by a counting sort: entry
    // `k N + i` is local row `i` of stencil `k`.
    let mut start = vec![0usize; h.n + 1];
    for &r in dofs.iter().flatten() {
        start[r as usize + 1] += 1;
    }
    for r in 0..h.n {
        start[r + 1] += start[r];
    }
    let mut fill = start[..h.n].to_vec();
    let mut members = vec![0u32; dofs.len() * N];
    for (e, &r) in dofs.iter().flatten().enumerate() {
        members[fill[r as usize]] = e as u32;
        fill[r as usize] += 1;
    }
    let mut slots = vec![0u32; dofs.len() * N * N];
    // `pos[c]` is the slot of column `c` in the row whose index `owner[c]` holds.
    let mut pos = vec![0u32; h.n];
    let mut owner = vec![usize::MAX; h.n];
    for r in 0..h.n {
        let rows = &members[start[r]..start[r + 1]];
        if rows.is_empty() {
            continue;
        }
        for s in h.row_ptr[r]..h.row_ptr[r + 1] {
            let c = h.col_idx[s] as usize;
            pos[c] = s as u32;
            owner[c] = r;
        }
        for &e in rows {
            let (k, i) = (e as usize / N, e as usize % N);
            let out = &mut slots[(k * N + i) * N..(k * N + i + 1) * N];
            for (slot, &c) in out.iter_mut().zip(&dofs[k]) {
                if owner[c as usize] != r {
                    return Err((r, c as usize));
                }
                *slot = pos[c as usize];
            }
        }
    }
    Ok(slots)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The slots agree with a binary search of every entry, on stencils
    /// that repeat a coordinate and share rows in any order.
    #[test]
    fn slots_match_a_search_per_entry() {
        let dofs: Vec<[u32; 3]> = vec![[4, 0, 2], [2, 2, 5], [1, 3, 0], [5, 4, 1]];
        let entries = dofs
            .iter()
            .flat_map(|d| d.iter().flat_map(move |&r| d.iter().map(move |&c| (r, c))));
        let h = CsrMatrix::from_pattern(6, entries);
        let slots = block_slots(&dofs, &h).unwrap();
        let mut expect = Vec::new();
        for d in &dofs {
            for &r in d {
                for &c in d {
                    expect.push(h.find(r as usize, c as usize).unwrap() as u32);
                }
            }
        }
        assert_eq!(slots, expect);
    }

    #[test]
    fn an_entry_outside_the_pattern_is_named() {
        let h = CsrMatrix::from_pattern(4, [(0, 0), (1, 1), (2, 2), (3, 3), (0, 1), (1, 0)]);
        assert_eq!(block_slots(&[[0u32, 1]], &h).map(|s| s.len()), Ok(4));
        assert_eq!(block_slots(&[[0u32, 1], [1, 3]], &h), Err((1, 3)));
    }
}
