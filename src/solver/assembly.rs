//! Generic assembly: gather, evaluate and scatter every stencil of every
//! energy into one global gradient and sparse Hessian (the ipc-toolkit
//! pattern, see `energy` module docs).
//!
//! Design decisions:
//! - **The global vector holds every coordinate**, fixed ones included. A
//!   stencil's local coordinate `i` is global coordinate `dofs[i]`; a separate
//!   `free` mask says which rows are unknowns. Cancelled rows (pinned
//!   coordinates, Lagrangian coordinates of an EIL node) get zero gradient
//!   and an identity row and column, so the system size and the sparsity
//!   pattern never change when a node switches (docs/MODEL.md,
//!   "Fixed system size"). Because the pattern ignores the mask, the direct solver's
//!   symbolic analysis survives EIL switches too.
//! - **Precomputed value slots.** After the pattern is built, [`bind`] looks
//!   up once, per stencil, where each of its `N*N` local entries lives in
//!   `CsrMatrix::values`. Every Newton iteration then scatters without a
//!   search, and the lookup itself goes row by row (`slots`), since each
//!   relaxation step binds a new problem.
//! - **Parallel evaluation, serial scatter.** Stencils are evaluated in
//!   blocks on [`threads`] threads (spawned once per call, see
//!   [`ordered_map`]); the results are scattered, and energies summed, in
//!   stencil order on the calling thread. So the assembled system is
//!   bit-identical for any thread count: a run is reproducible on any
//!   machine, and evaluating (which is where the time goes: PSD
//!   projection, bending, wrapping jets) still uses every core.
//! - **Type erasure per set.** A [`StencilSet`] is generic over its stencil
//!   type and size; [`AnyStencilSet`] hides both so the caller holds all
//!   energies in one `Vec<Box<dyn AnyStencilSet>>`.
//!
//! [`bind`]: AnyStencilSet::bind

mod slots;
pub mod timing;

use crate::energy::{Derivatives, Stencil};
use crate::parallel::{ordered_map, threads};
use crate::sparse::CsrMatrix;
use nalgebra::SVector;
use std::time::Instant;
use timing::TermTimes;

/// Stencils per block of the parallel evaluation: small enough that the
/// threads share uneven work (PSD projections run only for indefinite
/// stencils), large enough that handing a block over (a channel message)
/// costs little against evaluating it (about 0.1 to 10 us per stencil).
const BLOCK: usize = 64;

/// `f(k)` for every `k` in `0..n`, evaluated on [`threads`] threads; `emit`
/// receives the results block by block, in index order.
fn for_each_block<T: Send, F>(n: usize, f: F, emit: impl FnMut(usize, &[T]))
where
    F: Fn(usize) -> T + Sync,
{
    ordered_map(threads(), BLOCK, n, f, emit)
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum AssemblyError {
    #[error("stencil set '{set}': entry ({row}, {col}) is not in the Hessian pattern")]
    MissingEntry { set: String, row: usize, col: usize },
    #[error("stencil set '{set}' was not bound to the current Hessian pattern")]
    Unbound { set: String },
    #[error("stencil set '{set}': {stencils} stencils but {dofs} dof maps")]
    LengthMismatch { set: String, stencils: usize, dofs: usize },
    #[error("stencil set '{set}': coordinate {index} out of range for {n} coordinates")]
    OutOfRange { set: String, index: usize, n: usize },
    #[error("stencil set '{set}': the Hessian has {nnz} entries, more than the 2^32 a value slot can address")]
    TooManyEntries { set: String, nnz: usize },
}

/// A type-erased stencil set, as the Newton problem holds it. `Send` so
/// that sets can be bound on several threads ([`bind_all`]).
pub trait AnyStencilSet: Send + Sync {
    /// Name for error messages and timing reports.
    fn name(&self) -> &str;
    fn len(&self) -> usize;
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Checks the dof maps against a system of `n` coordinates.
    fn validate(&self, n: usize) -> Result<(), AssemblyError>;
    /// Local size `N` and the dof maps of all stencils, flattened (`N` per
    /// stencil): every (row, col) pair within one map is a Hessian entry.
    fn dof_maps(&self) -> (usize, &[u32]);
    /// Caches the value slot of every local entry in `h` (call after the pattern changes).
    fn bind(&mut self, h: &CsrMatrix) -> Result<(), AssemblyError>;
    /// Sum of the stencil values at `q`.
    fn energy(&self, q: &[f64]) -> f64;
    /// Adds the gradient into the free rows only; needs no binding.
    fn gradient(&self, q: &[f64], free: &[bool], grad: &mut [f64]);
    /// Adds gradient and Hessian into the free rows and columns only.
    fn accumulate(
        &self,
        q: &[f64],
        free: &[bool],
        grad: &mut [f64],
        h: &mut CsrMatrix,
        project_psd: bool,
    ) -> Result<(), AssemblyError>;
}

/// Many stencils of one kind and their global coordinate maps.
pub struct StencilSet<S, const N: usize> {
    pub name: String,
    pub stencils: Vec<S>,
    /// `dofs[k][i]`: global coordinate of local coordinate `i` of stencil `k`.
    pub dofs: Vec<[u32; N]>,
    /// `N*N` value positions per stencil, row-major; empty until bound.
    slots: Vec<u32>,
    /// `(n, nnz)` of the matrix bound to: a cheap guard against scattering
    /// into a different pattern (a full comparison would cost as much as the scatter).
    bound_shape: (usize, usize),
}

impl<S: Stencil<N>, const N: usize> StencilSet<S, N> {
    pub fn new(name: impl Into<String>, stencils: Vec<S>, dofs: Vec<[u32; N]>) -> Self {
        StencilSet {
            name: name.into(),
            stencils,
            dofs,
            slots: Vec::new(),
            bound_shape: (0, 0),
        }
    }

    fn gather(q: &[f64], dofs: &[u32; N]) -> SVector<f64, N> {
        SVector::<f64, N>::from_fn(|i, _| q[dofs[i] as usize])
    }

    fn is_bound_to(&self, h: &CsrMatrix) -> bool {
        self.slots.len() == self.stencils.len() * N * N && self.bound_shape == (h.n, h.nnz())
    }
}

impl<S: Stencil<N> + Send + Sync, const N: usize> AnyStencilSet for StencilSet<S, N> {
    fn name(&self) -> &str {
        &self.name
    }

    fn len(&self) -> usize {
        self.stencils.len()
    }

    fn validate(&self, n: usize) -> Result<(), AssemblyError> {
        if self.stencils.len() != self.dofs.len() {
            return Err(AssemblyError::LengthMismatch {
                set: self.name.clone(),
                stencils: self.stencils.len(),
                dofs: self.dofs.len(),
            });
        }
        match self.dofs.iter().flatten().find(|&&d| d as usize >= n) {
            Some(&d) => Err(AssemblyError::OutOfRange {
                set: self.name.clone(),
                index: d as usize,
                n,
            }),
            None => Ok(()),
        }
    }

    fn dof_maps(&self) -> (usize, &[u32]) {
        (N, self.dofs.as_flattened())
    }

    fn bind(&mut self, h: &CsrMatrix) -> Result<(), AssemblyError> {
        self.validate(h.n)?;
        if u32::try_from(h.nnz()).is_err() {
            return Err(AssemblyError::TooManyEntries {
                set: self.name.clone(),
                nnz: h.nnz(),
            });
        }
        let slots = slots::block_slots(&self.dofs, h).map_err(|(row, col)| AssemblyError::MissingEntry {
            set: self.name.clone(),
            row,
            col,
        })?;
        self.slots = slots;
        self.bound_shape = (h.n, h.nnz());
        Ok(())
    }

    fn energy(&self, q: &[f64]) -> f64 {
        let value = |k: usize| self.stencils[k].value(&Self::gather(q, &self.dofs[k]));
        let mut total = 0.0;
        for_each_block(self.stencils.len(), value, |_, values: &[f64]| {
            total = values.iter().fold(total, |t, v| t + v);
        });
        total
    }

    fn gradient(&self, q: &[f64], free: &[bool], grad: &mut [f64]) {
        let gradient = |k: usize| self.stencils[k].gradient(&Self::gather(q, &self.dofs[k]));
        let scatter = |start: usize, block: &[SVector<f64, N>]| {
            for (k, g) in (start..).zip(block) {
                for (i, &r) in self.dofs[k].iter().enumerate() {
                    if free[r as usize] {
                        grad[r as usize] += g[i];
                    }
                }
            }
        };
        for_each_block(self.stencils.len(), gradient, scatter);
    }

    fn accumulate(
        &self,
        q: &[f64],
        free: &[bool],
        grad: &mut [f64],
        h: &mut CsrMatrix,
        project_psd: bool,
    ) -> Result<(), AssemblyError> {
        if !self.is_bound_to(h) {
            return Err(AssemblyError::Unbound { set: self.name.clone() });
        }
        // Evaluated in pairs, so that each work item is two stencils; an
        // odd last stencil is paired with itself and its twin dropped.
        let n = self.stencils.len();
        let pair = |p: usize| {
            let (a, b) = (2 * p, (2 * p + 1).min(n - 1));
            let (xa, xb) = (Self::gather(q, &self.dofs[a]), Self::gather(q, &self.dofs[b]));
            [
                self.stencils[a].derivatives(&xa, project_psd),
                self.stencils[b].derivatives(&xb, project_psd),
            ]
        };
        let scatter = |start: usize, block: &[[Derivatives<N>; 2]]| {
            for (k, (g, hl)) in (2 * start..n).zip(block.iter().flatten()) {
                let d = &self.dofs[k];
                let slots = &self.slots[k * N * N..(k + 1) * N * N];
                let is_free = d.map(|r| free[r as usize]);
                for i in 0..N {
                    if !is_free[i] {
                        continue;
                    }
                    grad[d[i] as usize] += g[i];
                    for j in 0..N {
                        if is_free[j] {
                            h.values[slots[i * N + j] as usize] += hl[(i, j)];
                        }
                    }
                }
            }
        };
        ordered_map(threads(), BLOCK / 2, n.div_ceil(2), pair, scatter);
        Ok(())
    }
}

/// Hessian pattern of `n` coordinates for the given sets, with every diagonal
/// entry present so cancelled rows can hold their identity.
pub fn hessian_pattern(n: usize, sets: &[Box<dyn AnyStencilSet>]) -> CsrMatrix {
    // Two passes over the dof maps straight into CSR storage: count each
    // row's (duplicated) entries, fill, then sort and deduplicate row by
    // row. A list of (row, col) pairs would hold every stencil's `N^2`
    // entries at once (160 MB on a 40x40 linen stitch) before merging.
    let mut count = vec![1usize; n];
    for s in sets {
        let (width, maps) = s.dof_maps();
        for &r in maps {
            count[r as usize] += width;
        }
    }
    let mut start = Vec::with_capacity(n + 1);
    start.push(0usize);
    for c in &count {
        start.push(start.last().copied().unwrap_or(0) + c);
    }
    let mut cols = vec![0u32; start[n]];
    let mut fill = start[..n].to_vec();
    for (r, f) in fill.iter_mut().enumerate() {
        cols[*f] = r as u32;
        *f += 1;
    }
    for s in sets {
        let (width, maps) = s.dof_maps();
        for map in maps.chunks_exact(width) {
            for &r in map {
                let f = &mut fill[r as usize];
                cols[*f..*f + width].copy_from_slice(map);
                *f += width;
            }
        }
    }
    // Each row sorted and its duplicates dropped within its own range (the
    // rows' halves on two threads when there are two), then the rows
    // packed together in order.
    let unique_in_rows = |rows: std::ops::Range<usize>, cols: &mut [u32], offset: usize| -> Vec<usize> {
        rows.map(|r| {
            let row = &mut cols[start[r] - offset..start[r + 1] - offset];
            row.sort_unstable();
            let mut kept = 0;
            for k in 0..row.len() {
                if kept == 0 || row[k] != row[kept - 1] {
                    row[kept] = row[k];
                    kept += 1;
                }
            }
            kept
        })
        .collect()
    };
    let mid = n / 2;
    let unique: Vec<usize> = if crate::parallel::threads() > 1 && n > 1 {
        let (low, high) = cols.split_at_mut(start[mid]);
        let (mut a, b) = std::thread::scope(|scope| {
            let upper = scope.spawn(|| unique_in_rows(mid..n, high, start[mid]));
            let lower = unique_in_rows(0..mid, low, 0);
            (lower, upper.join().expect("pattern thread panicked"))
        });
        a.extend(b);
        a
    } else {
        unique_in_rows(0..n, &mut cols, 0)
    };
    let mut row_ptr = Vec::with_capacity(n + 1);
    row_ptr.push(0);
    let mut len = 0;
    for (r, &kept) in unique.iter().enumerate() {
        cols.copy_within(start[r]..start[r] + kept, len);
        len += kept;
        row_ptr.push(len);
    }
    cols.truncate(len);
    cols.shrink_to_fit();
    let nnz = cols.len();
    CsrMatrix {
        n,
        row_ptr,
        col_idx: cols,
        values: vec![0.0; nnz],
    }
}

/// Binds every set to `h` (after [`hessian_pattern`] or any pattern change).
///
/// The sets are independent, so on two or more threads each is bound by
/// whichever thread is free, largest first (11 to 33 ms per relaxation
/// step of a 40x40 linen stitch on one thread). The first failing set in
/// `sets` order is the error reported, as on one thread.
pub fn bind_all(sets: &mut [Box<dyn AnyStencilSet>], h: &CsrMatrix) -> Result<(), AssemblyError> {
    let workers = crate::parallel::threads().min(sets.len());
    if workers <= 1 {
        return sets.iter_mut().try_for_each(|s| s.bind(h));
    }
    let mut queue: Vec<(usize, &mut Box<dyn AnyStencilSet>)> = sets.iter_mut().enumerate().collect();
    // Popped from the back: largest (by Hessian entries) last in the list.
    queue.sort_by_key(|(_, s)| {
        let (width, maps) = s.dof_maps();
        maps.len() * width
    });
    let queue = std::sync::Mutex::new(queue);
    let errors = std::sync::Mutex::new(Vec::new());
    let work = || {
        while let Some((i, set)) = queue.lock().ok().and_then(|mut q| q.pop()) {
            if let Err(e) = set.bind(h) {
                if let Ok(mut errors) = errors.lock() {
                    errors.push((i, e));
                }
            }
        }
    };
    std::thread::scope(|scope| {
        for _ in 1..workers {
            scope.spawn(work);
        }
        work();
    });
    let errors = errors.into_inner().unwrap_or_else(|e| e.into_inner());
    match errors.into_iter().min_by_key(|(i, _)| *i) {
        Some((_, e)) => Err(e),
        None => Ok(()),
    }
}

/// Total energy of all sets at `q`.
pub fn total_energy(sets: &[Box<dyn AnyStencilSet>], q: &[f64]) -> f64 {
    sets.iter().map(|s| s.energy(q)).sum()
}

/// [`total_energy`], adding each set's time to `times`.
pub fn total_energy_timed(sets: &[Box<dyn AnyStencilSet>], q: &[f64], times: &mut TermTimes) -> f64 {
    let mut e = 0.0;
    for s in sets {
        let start = Instant::now();
        e += s.energy(q);
        times.add(s.name(), start.elapsed().as_secs_f64(), s.len());
    }
    e
}

/// Free-row gradient of all sets at `q`, fixed rows zero: what [`assemble`]
/// puts in `grad`, without the Hessian (no pattern or binding needed).
pub fn gradient(sets: &[Box<dyn AnyStencilSet>], q: &[f64], free: &[bool]) -> Vec<f64> {
    let mut grad = vec![0.0; q.len()];
    for s in sets {
        s.gradient(q, free, &mut grad);
    }
    grad
}

/// Zeroes `grad` and `h`, sums every set, then cancels the fixed rows.
pub fn assemble(
    sets: &[Box<dyn AnyStencilSet>],
    q: &[f64],
    free: &[bool],
    grad: &mut [f64],
    h: &mut CsrMatrix,
    project_psd: bool,
) -> Result<(), AssemblyError> {
    assemble_timed(sets, q, free, grad, h, project_psd, &mut TermTimes::default())
}

/// [`assemble`], adding each set's time to `times`.
pub fn assemble_timed(
    sets: &[Box<dyn AnyStencilSet>],
    q: &[f64],
    free: &[bool],
    grad: &mut [f64],
    h: &mut CsrMatrix,
    project_psd: bool,
    times: &mut TermTimes,
) -> Result<(), AssemblyError> {
    grad.fill(0.0);
    h.values.fill(0.0);
    for s in sets {
        let start = Instant::now();
        s.accumulate(q, free, grad, h, project_psd)?;
        times.add(s.name(), start.elapsed().as_secs_f64(), s.len());
    }
    cancel_fixed_rows(free, grad, h);
    Ok(())
}

/// Puts 1 on the diagonal of every non-free row (whose other entries the
/// scatter left at zero) and zeroes its gradient, so `dq` is 0 there.
pub fn cancel_fixed_rows(free: &[bool], grad: &mut [f64], h: &mut CsrMatrix) {
    for (r, _) in free.iter().enumerate().filter(|(_, &f)| !f) {
        grad[r] = 0.0;
        if let Some(k) = h.find(r, r) {
            h.values[k] = 1.0;
        }
    }
}

#[cfg(test)]
mod tests;
