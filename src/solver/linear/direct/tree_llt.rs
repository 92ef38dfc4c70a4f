//! Supernodal LLT on several threads, over the elimination tree.
//!
//! faer's supernodal kernel is left-looking and visits the supernodes one
//! after another; its `Par` only splits the dense operations inside one
//! supernode. A yarn patch's factor has some 18000 supernodes, most of
//! them a few columns wide, so on two cores that parallelism costs more in
//! synchronisation than it wins (the factorization was no faster).
//! Supernodes in disjoint subtrees of the elimination tree do not touch
//! each other, though: each one reads only its own descendants' columns.
//! Here workers take supernodes whose children are all done, depth first,
//! and each supernode runs the same operations as in faer's kernel: the
//! matrix's columns added into zeroed storage, every descendant's update
//! (a product of two of its row blocks, subtracted entry by entry), a
//! dense Cholesky of the diagonal block and a triangular solve below it,
//! through faer's dense routines, each product over at most 512 of the
//! descendant's columns at a time as faer's x86 kernel forms it. So the
//! factor is faer's bit for bit (tests; 16% less time per 40x40 linen
//! relaxation, docs/RELAX.md, "Parallel factorization"), and it does not depend on the
//! number of threads or on which worker took which supernode.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch, LltRegularization};
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::SparseColMatRef;
use faer::{Accum, MatMut, MatRef, Par};
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::{Mutex, OnceLock};

/// One descendant's update of a supernode: `d`'s pattern rows from
/// position `first` on, of which the first `mid` fall in the supernode.
#[derive(Clone, Copy, Debug)]
struct Update {
    d: usize,
    first: usize,
    mid: usize,
}

/// The elimination tree and update lists of a supernodal structure, fixed
/// with the pattern.
pub(super) struct TreePlan {
    parent: Vec<Option<usize>>,
    children: Vec<u32>,
    update_ptr: Vec<usize>,
    updates: Vec<Update>,
    /// Widest supernode (for the dense Cholesky's workspace), longest
    /// pattern below a supernode, and most entries of one update product:
    /// the sizes of each worker's scratch.
    max_width: usize,
    max_rows: usize,
    max_product: usize,
    /// Scratch of earlier factorizations, kept with the pattern that sized
    /// it: allocating and filling it per call (a row map of every unknown
    /// and the largest update product, per worker) is work a
    /// refactorization need not repeat.
    scratch: Mutex<Vec<Scratch>>,
}

impl TreePlan {
    pub fn new(sn: &SymbolicSupernodalCholesky<usize>) -> Self {
        let ns = sn.n_supernodes();
        let (begin, end) = (sn.supernode_begin(), sn.supernode_end());
        let mut owner = vec![0; sn.nrows()];
        for s in 0..ns {
            owner[begin[s]..end[s]].fill(s);
        }
        let mut children = vec![0u32; ns];
        let mut per_target: Vec<Vec<Update>> = vec![Vec::new(); ns];
        let mut max_product = 0;
        let mut parent = Vec::with_capacity(ns);
        for d in 0..ns {
            let pattern = sn.supernode(d).pattern();
            parent.push(pattern.first().map(|&first| owner[first]));
            if let Some(&first) = pattern.first() {
                children[owner[first]] += 1;
            }
            let mut i = 0;
            while i < pattern.len() {
                let t = owner[pattern[i]];
                let mut j = i;
                while j < pattern.len() && owner[pattern[j]] == t {
                    j += 1;
                }
                max_product = max_product.max((pattern.len() - i) * (j - i));
                per_target[t].push(Update {
                    d,
                    first: i,
                    mid: j - i,
                });
                i = j;
            }
        }
        let mut update_ptr = vec![0];
        let mut updates = Vec::new();
        for list in per_target {
            updates.extend(list);
            update_ptr.push(updates.len());
        }
        let max_width = (0..ns).map(|s| end[s] - begin[s]).max().unwrap_or(0);
        TreePlan {
            parent,
            children,
            update_ptr,
            updates,
            max_width,
            max_rows: (0..ns).map(|s| sn.supernode(s).pattern().len()).max().unwrap_or(0),
            max_product,
            scratch: Mutex::new(Vec::new()),
        }
    }

    /// A worker's scratch: one kept from an earlier call, or a new one.
    fn take_scratch(&self, n: usize) -> Scratch {
        let kept = self.scratch.lock().ok().and_then(|mut pool| pool.pop());
        kept.unwrap_or_else(|| Scratch {
            local: vec![usize::MAX; n],
            target: vec![0; self.max_rows],
            product: vec![0.0; self.max_product],
            chol: MemBuffer::new(cholesky_in_place_scratch::<f64>(
                self.max_width,
                Par::Seq,
                Default::default(),
            )),
        })
    }

    fn keep_scratch(&self, scratch: Scratch) {
        if let Ok(mut pool) = self.scratch.lock() {
            pool.push(scratch);
        }
    }
}

/// The most descendant columns one update product spans: the depth block
/// of the x86 kernel behind faer's sparse Cholesky (`private-gemm-x86`
/// 0.1, `kc = min(depth, 512)`). Updates deeper than this occur from about
/// 80x80 stitches on; without the blocking their entries differed from
/// faer's in the last bit.
const DEPTH_CHUNK: usize = 512;

/// Per-worker scratch: the pattern-row-to-local-row map, where an
/// update's rows land, its product, and the dense Cholesky's workspace.
struct Scratch {
    local: Vec<usize>,
    target: Vec<usize>,
    product: Vec<f64>,
    chol: MemBuffer,
}

/// Factors the lower CSC matrix `a` (already in the factor's order) into
/// `l_values` on `workers` threads. `Err(column)` at a non-positive pivot.
pub(super) fn factorize(
    sn: &SymbolicSupernodalCholesky<usize>,
    plan: &TreePlan,
    a: SparseColMatRef<'_, usize, f64>,
    l_values: &mut [f64],
    workers: usize,
) -> Result<(), usize> {
    let ns = sn.n_supernodes();
    let val_ptr = sn.col_ptr_for_val();
    // Each supernode's storage, handed out once to the worker that factors it.
    let mut slots: Vec<Mutex<Option<&mut [f64]>>> = Vec::with_capacity(ns);
    let mut rest = l_values;
    for s in 0..ns {
        let (head, tail) = rest.split_at_mut(val_ptr[s + 1] - val_ptr[s]);
        slots.push(Mutex::new(Some(head)));
        rest = tail;
    }
    let done: Vec<OnceLock<&[f64]>> = (0..ns).map(|_| OnceLock::new()).collect();
    let remaining: Vec<AtomicU32> = plan.children.iter().map(|&c| AtomicU32::new(c)).collect();
    // Leaves in increasing order from the back: a worker climbs from each
    // leaf as far as the supernodes whose last child it has just finished,
    // so no supernode is ever queued twice and nothing waits.
    let leaves = Mutex::new((0..ns).rev().filter(|&s| plan.children[s] == 0).collect::<Vec<_>>());
    let failed = Mutex::new(None::<usize>);
    let stop = AtomicBool::new(false);
    let climb = |scratch: &mut Scratch| {
        while let Some(mut s) = leaves.lock().ok().and_then(|mut l| l.pop()) {
            loop {
                if stop.load(Ordering::Relaxed) {
                    return;
                }
                let taken = slots[s].lock().ok().and_then(|mut slot| slot.take());
                let result = match taken {
                    Some(ls) => factor_supernode(sn, plan, a, &done, s, ls, scratch),
                    None => Err(usize::MAX),
                };
                match result {
                    Ok(ls) => {
                        let _ = done[s].set(ls);
                    }
                    Err(column) => {
                        if let Ok(mut f) = failed.lock() {
                            f.get_or_insert(column);
                        }
                        stop.store(true, Ordering::Relaxed);
                        return;
                    }
                }
                match plan.parent[s] {
                    Some(p) if remaining[p].fetch_sub(1, Ordering::AcqRel) == 1 => s = p,
                    _ => break,
                }
            }
        }
    };
    let work = || {
        let mut scratch = plan.take_scratch(sn.nrows());
        climb(&mut scratch);
        // After a failure a row map may hold a supernode's entries: drop it.
        if !stop.load(Ordering::Relaxed) {
            plan.keep_scratch(scratch);
        }
    };
    if workers <= 1 {
        work();
    } else {
        std::thread::scope(|scope| {
            for _ in 1..workers {
                scope.spawn(|| {
                    // As on the calling thread (`DirectSolver::try_factor`):
                    // the same bits whichever thread factors a supernode.
                    let _flush = super::subnormals::FlushSubnormals::new();
                    work()
                });
            }
            work();
        });
    }
    match failed.into_inner().unwrap_or_else(|e| e.into_inner()) {
        Some(column) => Err(column),
        None => Ok(()),
    }
}

/// Factors supernode `s` into its storage `ls` (zeroed here), reading its
/// descendants from `done`.
fn factor_supernode<'a>(
    sn: &SymbolicSupernodalCholesky<usize>,
    plan: &TreePlan,
    a: SparseColMatRef<'_, usize, f64>,
    done: &[OnceLock<&'a [f64]>],
    s: usize,
    ls: &'a mut [f64],
    scratch: &mut Scratch,
) -> Result<&'a [f64], usize> {
    let (begin, end) = (sn.supernode_begin(), sn.supernode_end());
    let (s_start, s_end) = (begin[s], end[s]);
    let s_pattern = sn.supernode(s).pattern();
    let s_ncols = s_end - s_start;
    let s_nrows = s_ncols + s_pattern.len();
    for (i, &row) in s_pattern.iter().enumerate() {
        scratch.local[row] = s_ncols + i;
    }
    let local = |row: usize, map: &[usize]| if row < s_end { row - s_start } else { map[row] };
    ls.fill(0.0);
    for j in s_start..s_end {
        for (i, &v) in a.row_idx_of_col(j).zip(a.val_of_col(j)) {
            if i >= j {
                ls[local(i, &scratch.local) + (j - s_start) * s_nrows] += v;
            }
        }
    }
    for u in &plan.updates[plan.update_ptr[s]..plan.update_ptr[s + 1]] {
        let (d_start, d_end) = (begin[u.d], end[u.d]);
        let d_pattern = sn.supernode(u.d).pattern();
        let d_ncols = d_end - d_start;
        let d_nrows = d_ncols + d_pattern.len();
        let Some(&ld_values) = done[u.d].get() else {
            return Err(usize::MAX);
        };
        let rows = d_pattern.len() - u.first;
        let pattern = &d_pattern[u.first..];
        let target = &mut scratch.target[..rows];
        for (t, &row) in target.iter_mut().zip(pattern) {
            *t = local(row, &scratch.local);
        }
        let first_row = d_ncols + u.first;
        let ld = MatRef::from_column_major_slice(ld_values, d_nrows, d_ncols);
        // faer's kernel forms a product over at most `DEPTH_CHUNK` of the
        // descendant's columns at a time and adds each into the supernode
        // before the next; so does this loop, so that every entry is
        // rounded where faer's is.
        for k0 in (0..d_ncols).step_by(DEPTH_CHUNK) {
            let depth = DEPTH_CHUNK.min(d_ncols - k0);
            let below = ld.subrows(first_row, rows).subcols(k0, depth);
            let mid = ld.subrows(first_row, u.mid).subcols(k0, depth);
            let product = &mut scratch.product[..rows * u.mid];
            let t = MatMut::from_column_major_slice_mut(&mut *product, rows, u.mid);
            // The part of the product above the diagonal is never used, so
            // the top block is formed as a lower triangle (faer's kernel
            // does the same): the largest supernodes' updates took 20% less
            // time.
            let (t_top, t_bot) = t.split_at_row_mut(u.mid);
            let (b_top, b_bot) = below.split_at_row(u.mid);
            use faer::linalg::matmul::triangular::{matmul as tri_matmul, BlockStructure};
            tri_matmul(
                t_top,
                BlockStructure::TriangularLower,
                Accum::Replace,
                b_top,
                BlockStructure::Rectangular,
                mid.transpose(),
                BlockStructure::Rectangular,
                1.0,
                Par::Seq,
            );
            faer::linalg::matmul::matmul(t_bot, Accum::Replace, b_bot, mid.transpose(), 1.0, Par::Seq);
            for c in 0..u.mid {
                let col = target[c];
                let dst = &mut ls[col * s_nrows..(col + 1) * s_nrows];
                let src = &product[c * rows..(c + 1) * rows];
                for (&t, &v) in target[c..].iter().zip(&src[c..]) {
                    dst[t] -= v;
                }
            }
        }
    }
    for &row in s_pattern {
        scratch.local[row] = usize::MAX;
    }
    let l = MatMut::from_column_major_slice_mut(&mut *ls, s_nrows, s_ncols);
    let (mut top, bot) = l.split_at_row_mut(s_ncols);
    let stack = MemStack::new(&mut scratch.chol);
    if cholesky_in_place(
        top.as_mut(),
        LltRegularization::default(),
        Par::Seq,
        stack,
        Default::default(),
    )
    .is_err()
    {
        return Err(s_start);
    }
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(top.as_ref(), bot.transpose_mut(), Par::Seq);
    Ok(ls)
}

#[cfg(test)]
mod tests {
    use super::super::lower::LowerPattern;
    use super::super::permuted::PermutedLower;
    use super::*;
    use crate::sparse::CsrMatrix;
    use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, SymbolicCholeskyRaw, SymmetricOrdering};
    use faer::sparse::SymbolicSparseColMatRef;
    use faer::Side;

    /// A 7-point Laplacian on a `k^3` grid with seeded jitter on every
    /// entry, made diagonally dominant (SPD), plus `shift` on the diagonal.
    fn grid(k: usize, shift: f64) -> CsrMatrix {
        let id = |x: usize, y: usize, z: usize| (x * k + y) * k + z;
        let mut entries = Vec::new();
        for x in 0..k {
            for y in 0..k {
                for z in 0..k {
                    let i = id(x, y, z);
                    entries.push((i as u32, i as u32));
                    for (dx, dy, dz) in [(1, 0, 0), (0, 1, 0), (0, 0, 1)] {
                        if x + dx < k && y + dy < k && z + dz < k {
                            let j = id(x + dx, y + dy, z + dz);
                            entries.push((i as u32, j as u32));
                            entries.push((j as u32, i as u32));
                        }
                    }
                }
            }
        }
        let mut a = CsrMatrix::from_pattern(k * k * k, entries);
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for r in 0..a.n {
            for p in a.row_ptr[r]..a.row_ptr[r + 1] {
                let c = a.col_idx[p] as usize;
                if c > r {
                    let v = -0.5 - next();
                    a.values[p] = v;
                    let q = a.find(c, r).expect("symmetric pattern");
                    a.values[q] = v;
                }
            }
        }
        for r in 0..a.n {
            let off: f64 = (a.row_ptr[r]..a.row_ptr[r + 1])
                .filter(|&p| a.col_idx[p] as usize != r)
                .map(|p| a.values[p].abs())
                .sum();
            let d = a.find(r, r).expect("diagonal");
            a.values[d] = off + 0.1 + shift;
        }
        a
    }

    /// Two dense blocks, `a` unknowns then `b`, joined by a few couplings:
    /// the first block's supernode updates the second's with a depth of
    /// `a` columns.
    fn two_cliques(a: usize, b: usize) -> CsrMatrix {
        let mut entries: Vec<(u32, u32)> = Vec::new();
        for block in [0..a, a..a + b] {
            for i in block.clone() {
                for j in block.clone() {
                    entries.push((i as u32, j as u32));
                }
            }
        }
        for i in 0..a.min(b) / 10 {
            let (r, c) = ((10 * i) as u32, (a + 10 * i) as u32);
            entries.extend([(r, c), (c, r)]);
        }
        let mut m = CsrMatrix::from_pattern(a + b, entries);
        for r in 0..m.n {
            for p in m.row_ptr[r]..m.row_ptr[r + 1] {
                let c = m.col_idx[p] as usize;
                let w = ((r * 7 + c * 13) % 17) as f64 / 17.0;
                m.values[p] = if r == c { (a + b) as f64 } else { -0.5 - w / 2.0 };
            }
        }
        m
    }

    #[test]
    fn updates_deeper_than_the_kernels_depth_block_match_faer_bit_for_bit() {
        // Without the blocking, 4795 of the 1.78M entries differed.
        let a = two_cliques(1100, 700);
        for workers in [1, 2] {
            let deepest = assert_faers_factor(&a, workers);
            assert!(deepest > DEPTH_CHUNK, "deepest update {deepest} columns");
        }
    }

    /// Asserts that our factor of the SPD matrix `a` on `workers` threads
    /// is faer's ([`differing`]); returns the deepest update's columns.
    fn assert_faers_factor(a: &CsrMatrix, workers: usize) -> usize {
        let (theirs, ours, deepest) = both_factors(a, workers);
        let ours = ours.expect("SPD matrix");
        let differ = differing(&theirs, &ours);
        assert_eq!(
            differ,
            0,
            "{workers} workers: {differ} of {} entries differ",
            ours.len()
        );
        deepest
    }

    /// How many entries of `ours` differ from `theirs`: in any bit where
    /// faer's sparse kernel is the x86 AVX2/FMA one whose blocking the tree
    /// kernel follows; elsewhere by more than 1e-12 relative.
    fn differing(theirs: &[f64], ours: &[f64]) -> usize {
        #[cfg(target_arch = "x86_64")]
        let exact = std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma");
        #[cfg(not(target_arch = "x86_64"))]
        let exact = false;
        theirs
            .iter()
            .zip(ours)
            .filter(|(t, o)| {
                if exact {
                    t.to_bits() != o.to_bits()
                } else {
                    (*t - *o).abs() > 1e-12 * t.abs().max(f64::MIN_POSITIVE)
                }
            })
            .count()
    }

    /// faer's own supernodal factor of `a` and ours on `workers` threads,
    /// and the most columns of any update.
    fn both_factors(a: &CsrMatrix, workers: usize) -> (Vec<f64>, Result<Vec<f64>, usize>, usize) {
        let lower = LowerPattern::new(a);
        let n = a.n;
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &lower.col_ptr, None, &lower.row_idx);
        let symbolic = factorize_symbolic_cholesky(sym, Side::Lower, SymmetricOrdering::Amd, Default::default())
            .expect("symbolic");
        let SymbolicCholeskyRaw::Supernodal(sn) = symbolic.raw() else {
            panic!("the test matrix should get a supernodal factor");
        };
        let values: Vec<f64> = lower.source.iter().map(|&k| a.values[k]).collect();
        let mat = faer::sparse::SparseColMatRef::new(sym, &values);
        let mut theirs = vec![0.0; symbolic.len_val()];
        let req = symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default());
        let mut mem = MemBuffer::new(req);
        let _ = symbolic.factorize_numeric_llt(
            &mut theirs,
            mat,
            Side::Lower,
            LltRegularization::default(),
            Par::Seq,
            MemStack::new(&mut mem),
            Default::default(),
        );
        let permuted = PermutedLower::new(&lower, symbolic.perm().expect("AMD permutes").arrays().1);
        let mut gathered = vec![0.0; permuted.source.len()];
        permuted.gather(&a.values, &mut gathered);
        let psym = SymbolicSparseColMatRef::new_checked(n, n, &permuted.col_ptr, None, &permuted.row_idx);
        let mut ours = vec![0.0; symbolic.len_val()];
        let plan = TreePlan::new(sn);
        let result = factorize(sn, &plan, SparseColMatRef::new(psym, &gathered), &mut ours, workers);
        let (begin, end) = (sn.supernode_begin(), sn.supernode_end());
        let deepest = plan.updates.iter().map(|u| end[u.d] - begin[u.d]).max().unwrap_or(0);
        (theirs, result.map(|()| ours), deepest)
    }

    #[test]
    fn the_tree_factor_is_faers_supernodal_factor_bit_for_bit_on_any_thread_count() {
        let a = grid(12, 0.0);
        for workers in [1, 2, 3] {
            assert_faers_factor(&a, workers);
        }
    }

    #[test]
    fn a_matrix_that_is_not_positive_definite_is_refused() {
        // Shifting every diagonal far down makes the matrix indefinite.
        let a = grid(12, -20.0);
        for workers in [1, 2] {
            assert!(both_factors(&a, workers).1.is_err());
        }
    }
}
