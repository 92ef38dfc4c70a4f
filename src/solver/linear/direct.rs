//! Sparse direct solver: faer's supernodal/simplicial Cholesky on the lower
//! triangle of the Newton matrix (docs/MODEL.md, "Linear solvers").
//!
//! Design decisions:
//! - **Symbolic analysis once per pattern.** The fill-reducing ordering
//!   (AMD on the unknowns or on their nodes, whichever fills less:
//!   [`Ordering`]) and the elimination structure depend only on where the
//!   nonzeros are. The Newton
//!   matrix keeps its pattern for as long as the node assignment does (EIL
//!   rows are cancelled in place, never removed), so every Newton iteration
//!   after the first is a numeric refactorization only. The pattern is
//!   compared entry by entry (a memcmp, negligible next to a factorization).
//! - **Cancelled rows leave the factor.** Rows the assembly turned into
//!   identity rows keep their couplings in the pattern as explicit zeros;
//!   the analysis leaves those out (`lower`), so they cost no fill, and is
//!   redone if a later matrix puts a nonzero there.
//! - **Lower triangle by a cached gather.** `CsrMatrix` stores both triangles,
//!   row-major. For a symmetric matrix, row `j` restricted to columns `>= j` is
//!   column `j` of the lower triangle, so the CSC lower triangle is the upper
//!   half of every CSR row, already sorted. Which CSR value goes where is
//!   computed once with the symbolic analysis; refills are a straight gather.
//! - **Fallbacks for a minimiser.** Plain LLT first. When it fails (a singular
//!   PSD matrix from free rigid modes, or an indefinite one), the diagonal is
//!   shifted by a growing multiple of its largest entry and LLT retried: a
//!   positive definite model keeps `dq` a descent direction, which is what
//!   Newton needs. An unshifted LDLT is the last resort, for symmetric
//!   indefinite but nonsingular systems. Every solve is checked by its
//!   residual against the matrix actually factored, because a pivot that is
//!   tiny rather than negative passes LLT and returns garbage.
//! - **faer's numeric factorization.** faer computes the ordering and the
//!   supernodes, refactors the lower triangle on every Newton iteration
//!   (`factorize_numeric_llt`, sequential unless [`DirectParams::parallel`])
//!   and solves with the factor.
//! - **Subnormals flushed to zero** while factoring and solving
//!   (`subnormals`): the factor of a heavily damped matrix fills with them,
//!   and x86 computes them in microcode.

use crate::sparse::CsrMatrix;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LdltRef, LltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Side};
use lower::LowerPattern;
pub use ordering::Ordering;
use subnormals::FlushSubnormals;

mod lower;
mod ordering;
mod subnormals;

/// Tuning of the fallback chain; see the module docs.
#[derive(Clone, Copy, Debug)]
pub struct DirectParams {
    /// Number of shifted LLT retries after a failed plain LLT.
    pub shift_tries: usize,
    /// First shift, relative to the largest absolute diagonal entry.
    pub initial_shift: f64,
    /// Factor between successive shifts.
    pub shift_growth: f64,
    /// Try an unshifted LDLT when every LLT failed.
    pub ldlt_last_resort: bool,
    /// Plain LLT only: a matrix that is not positive definite is an
    /// error, with no shifted or LDLT retry (Newton's exact-Hessian
    /// iterations, `LinearSolver::set_definite_only`).
    pub definite_only: bool,
    /// A solve whose `|A x - b| / |b|` exceeds this counts as a failed factorization.
    pub max_rel_residual: f64,
    /// Let faer factorize and solve on its rayon pool. Off by default:
    /// faer's parallel mode only splits the dense work inside one
    /// supernode, which on the 2-core machine made the factorization
    /// slower, and the pool's idle workers spin (`sched_yield`) while the
    /// stencil threads of the next assembly want the same cores. Worth
    /// turning on with many cores.
    pub parallel: bool,
    /// Fill-reducing ordering ([`Ordering`]): `None` analyses the scalar
    /// and, when groups are set, the grouped ordering, and keeps the one
    /// with the smaller factor; `Some` uses that one only (grouped falls
    /// back to scalar without groups).
    pub ordering: Option<Ordering>,
}

impl Default for DirectParams {
    fn default() -> Self {
        DirectParams {
            shift_tries: 6,
            initial_shift: 1e-10,
            shift_growth: 100.0,
            ldlt_last_resort: true,
            definite_only: false,
            max_rel_residual: 1e-6,
            parallel: false,
            ordering: None,
        }
    }
}

/// Which factorization produced the current factor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FactorKind {
    Llt,
    /// LLT of `A + shift I`.
    ShiftedLlt {
        shift: f64,
    },
    Ldlt,
}

#[derive(Debug, thiserror::Error)]
pub enum DirectError {
    #[error("matrix is {n}x{n} but the right-hand side has length {len}")]
    Dimension { n: usize, len: usize },
    #[error("symbolic Cholesky analysis failed: {0}")]
    Symbolic(String),
    #[error("no factorization succeeded (LLT, {shift_tries} shifted LLT, LDLT)")]
    NotFactorizable { shift_tries: usize },
    #[error("solve called before a successful factorization")]
    NotFactorized,
}

/// Lower-triangle CSC copy of a `CsrMatrix` plus its symbolic analysis.
struct Analysis {
    row_ptr: Vec<usize>,
    col_idx: Vec<u32>,
    lower: LowerPattern,
    symbolic: SymbolicCholesky<usize>,
    ordering: Ordering,
}

/// Sparse Cholesky with symbolic reuse; see the module docs.
pub struct DirectSolver {
    pub params: DirectParams,
    analysis: Option<Box<Analysis>>,
    lower_values: Vec<f64>,
    factor_values: Vec<f64>,
    factor: Option<FactorKind>,
    symbolic_count: usize,
    /// Group of each unknown for the grouped ordering (empty: none).
    groups: Vec<u32>,
}

impl Default for DirectSolver {
    fn default() -> Self {
        Self::new(DirectParams::default())
    }
}

impl DirectSolver {
    pub fn new(params: DirectParams) -> Self {
        DirectSolver {
            params,
            analysis: None,
            lower_values: Vec::new(),
            factor_values: Vec::new(),
            factor: None,
            symbolic_count: 0,
            groups: Vec::new(),
        }
    }

    /// Sets the group of each unknown (for a yarn model, the node it
    /// belongs to) for the grouped ordering; empty clears them. A change
    /// drops the current analysis.
    pub fn set_ordering_groups(&mut self, groups: &[u32]) {
        if self.groups != groups {
            self.groups = groups.to_vec();
            self.analysis = None;
            self.factor = None;
        }
    }

    /// The ordering of the current analysis, once analysed.
    pub fn ordering(&self) -> Option<Ordering> {
        self.analysis.as_ref().map(|a| a.ordering)
    }

    /// faer's parallelism for factorization and solves (see [`DirectParams::parallel`]).
    fn par(&self) -> faer::Par {
        if self.params.parallel {
            faer::get_global_parallelism()
        } else {
            faer::Par::Seq
        }
    }

    /// How many symbolic analyses have run (one per distinct pattern seen in a row).
    pub fn symbolic_count(&self) -> usize {
        self.symbolic_count
    }

    /// Number of stored entries of the Cholesky factor, once analysed (its memory is 8 bytes each).
    pub fn factor_len(&self) -> Option<usize> {
        self.analysis.as_ref().map(|a| a.symbolic.len_val())
    }

    /// Multiply-adds of one numeric factorization, once analysed
    /// (`ordering::factor_flops`).
    pub fn factor_flops(&self) -> Option<f64> {
        self.analysis.as_ref().map(|a| ordering::factor_flops(&a.symbolic))
    }

    /// Runs the symbolic analysis unless `a` has the pattern analysed last
    /// and is zero wherever that analysis left out an identity row's
    /// couplings (`lower`). Returns whether a new analysis was needed.
    pub fn analyze(&mut self, a: &CsrMatrix) -> Result<bool, DirectError> {
        if let Some(an) = &self.analysis {
            if an.row_ptr == a.row_ptr && an.col_idx == a.col_idx && an.lower.fits(a) {
                return Ok(false);
            }
        }
        self.analysis = None;
        self.factor = None;
        let lower = LowerPattern::new(a);
        let (symbolic, ordering) = self.symbolic(&lower.col_ptr, &lower.row_idx)?;
        self.symbolic_count += 1;
        // The buffers are refilled, not re-allocated: a fresh 70 MB factor
        // (40x40 linen stitch) is mapped page by page on its first
        // factorization; those were 37% of a relaxation's page faults
        // (`perf record -e page-faults`), though the wall time saved is
        // within the development machine's noise.
        refill_zeros(&mut self.lower_values, lower.row_idx.len());
        refill_zeros(&mut self.factor_values, symbolic.len_val());
        self.analysis = Some(Box::new(Analysis {
            row_ptr: a.row_ptr.clone(),
            col_idx: a.col_idx.clone(),
            lower,
            symbolic,
            ordering,
        }));
        Ok(true)
    }

    /// The symbolic factorization under the ordering rule of
    /// [`DirectParams::ordering`].
    fn symbolic(
        &self,
        col_ptr: &[usize],
        row_idx: &[usize],
    ) -> Result<(SymbolicCholesky<usize>, Ordering), DirectError> {
        let n = col_ptr.len() - 1;
        let sym = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx);
        let analyse = |ordering: SymmetricOrdering<'_, usize>| {
            factorize_symbolic_cholesky(sym, Side::Lower, ordering, Default::default())
                .map_err(|e| DirectError::Symbolic(format!("{e:?}")))
        };
        let grouped_analysis = || {
            let grouped = match self.params.ordering {
                Some(Ordering::Scalar) => None,
                _ => ordering::grouped_amd(col_ptr, row_idx, &self.groups),
            };
            // A grouped analysis that fails only leaves the scalar one.
            grouped.and_then(|(fwd, inv)| analyse(SymmetricOrdering::Custom(PermRef::new_checked(&fwd, &inv, n))).ok())
        };
        if self.params.ordering == Some(Ordering::Grouped) {
            if let Some(g) = grouped_analysis() {
                return Ok((g, Ordering::Grouped));
            }
        }
        // Under the default rule both analyses run, and on two or more
        // threads side by side (each is sequential; the result is the same).
        let scalar_analysis = || analyse(SymmetricOrdering::Amd);
        let (grouped, scalar) = if self.params.ordering.is_none() && crate::parallel::threads() > 1 {
            std::thread::scope(|scope| {
                let scalar = scope.spawn(scalar_analysis);
                let grouped = grouped_analysis();
                (grouped, scalar.join().expect("symbolic analysis panicked"))
            })
        } else {
            let grouped = if self.params.ordering.is_none() {
                grouped_analysis()
            } else {
                None
            };
            (grouped, scalar_analysis())
        };
        let scalar = scalar?;
        Ok(match grouped {
            Some(g) if g.len_val() < scalar.len_val() => (g, Ordering::Grouped),
            _ => (scalar, Ordering::Scalar),
        })
    }

    /// Numeric factorization of `a` (symbolic analysis first if the pattern changed).
    pub fn factorize(&mut self, a: &CsrMatrix) -> Result<FactorKind, DirectError> {
        self.factorize_and_solve(a, None)
    }

    /// [`factorize`](Self::factorize), and with `rhs = (b, x)` also
    /// `x = A^-1 b` with the factor that passes. Each attempt's residual
    /// probe and the caller's solve are independent triangular solve pairs
    /// on the same factor, so on two or more threads they run side by side
    /// (the probe is 7% of a 40x40 linen Newton iteration when run after
    /// the solve). The solution is the same either way.
    fn factorize_and_solve(
        &mut self,
        a: &CsrMatrix,
        mut rhs: Option<(&[f64], &mut [f64])>,
    ) -> Result<FactorKind, DirectError> {
        self.analyze(a)?;
        self.factor = None;
        let an = self.analysis.as_ref().ok_or(DirectError::NotFactorized)?;
        let max_diag = an
            .lower
            .diagonal(a)
            .fold(0.0f64, |m, d| m.max(d.abs()))
            .max(f64::MIN_POSITIVE);
        let mut attempts: Vec<FactorKind> = vec![FactorKind::Llt];
        let retries = if self.params.definite_only {
            0
        } else {
            self.params.shift_tries
        };
        let mut shift = self.params.initial_shift * max_diag;
        for _ in 0..retries {
            attempts.push(FactorKind::ShiftedLlt { shift });
            shift *= self.params.shift_growth;
        }
        if self.params.ldlt_last_resort && !self.params.definite_only {
            attempts.push(FactorKind::Ldlt);
        }
        let concurrent = crate::parallel::threads() > 1;
        for kind in attempts {
            if !self.try_factor(a, kind) {
                continue;
            }
            let this = &*self;
            let passed = match rhs.as_mut() {
                None => this.passes_residual_probe(a, kind),
                Some((b, x)) => {
                    x.copy_from_slice(b);
                    if concurrent {
                        std::thread::scope(|scope| {
                            let probe = scope.spawn(|| this.passes_residual_probe(a, kind));
                            let solved = this.solve_with(kind, x).is_ok();
                            let probed = probe.join().expect("residual probe panicked");
                            solved && probed
                        })
                    } else {
                        this.passes_residual_probe(a, kind) && this.solve_with(kind, x).is_ok()
                    }
                }
            };
            if passed {
                self.factor = Some(kind);
                return Ok(kind);
            }
        }
        Err(DirectError::NotFactorizable {
            shift_tries: self.params.shift_tries,
        })
    }

    fn try_factor(&mut self, a: &CsrMatrix, kind: FactorKind) -> bool {
        let Some(an) = &self.analysis else { return false };
        let _flush = FlushSubnormals::new();
        for (dst, &src) in self.lower_values.iter_mut().zip(&an.lower.source) {
            *dst = a.values[src];
        }
        if let FactorKind::ShiftedLlt { shift } = kind {
            // A structurally missing diagonal cannot be shifted; LLT will fail there.
            for &d in an.lower.diag.iter().flatten() {
                self.lower_values[d] += shift;
            }
        }
        let n = a.n;
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &an.lower.col_ptr, None, &an.lower.row_idx);
        let mat = SparseColMatRef::new(sym, &self.lower_values);
        let par = self.par();
        let ok = match kind {
            FactorKind::Llt | FactorKind::ShiftedLlt { .. } => {
                let req = an
                    .symbolic
                    .factorize_numeric_llt_scratch::<f64>(par, Default::default());
                let Ok(mut mem) = MemBuffer::try_new(req) else {
                    return false;
                };
                an.symbolic
                    .factorize_numeric_llt(
                        &mut self.factor_values,
                        mat,
                        Side::Lower,
                        LltRegularization::default(),
                        par,
                        MemStack::new(&mut mem),
                        Default::default(),
                    )
                    .is_ok()
            }
            FactorKind::Ldlt => {
                let req = an
                    .symbolic
                    .factorize_numeric_ldlt_scratch::<f64>(par, Default::default());
                let Ok(mut mem) = MemBuffer::try_new(req) else {
                    return false;
                };
                an.symbolic
                    .factorize_numeric_ldlt(
                        &mut self.factor_values,
                        mat,
                        Side::Lower,
                        LdltRegularization::default(),
                        par,
                        MemStack::new(&mut mem),
                        Default::default(),
                    )
                    .is_ok()
            }
        };
        ok
    }

    /// Solves with a fixed probe right-hand side and checks the residual, to
    /// catch factorizations that "succeeded" on a numerically singular matrix.
    ///
    /// The residual is measured on the diagonally scaled system
    /// `S A S y = S b` with `S = diag(|a_ii|^-1/2)`, i.e. `|S (A x - b)| /
    /// |S b|`. Cholesky's rounding error is bounded by the condition number
    /// of that scaled matrix (van der Sluis), not of `A`: an unscaled
    /// residual flagged sound factors of a yarn matrix whose diagonal
    /// spans 1e5 .. 1e22 (a real segment closing within a step) and sent
    /// every such iteration to a shifted retry, where a shift sized to the
    /// largest diagonal swamped every ordinary unknown (docs/RELAX.md,
    /// "Residual probe").
    fn passes_residual_probe(&self, a: &CsrMatrix, kind: FactorKind) -> bool {
        let n = a.n;
        if n == 0 {
            return true;
        }
        let Some(an) = &self.analysis else { return false };
        let b: Vec<f64> = (0..n).map(|i| 1.0 + 0.5 * ((i * 7919) % 13) as f64 / 13.0).collect();
        let mut x = b.clone();
        if self.solve_with(kind, &mut x).is_err() {
            return false;
        }
        let shift = match kind {
            FactorKind::ShiftedLlt { shift } => shift,
            _ => 0.0,
        };
        let mut ax = vec![0.0; n];
        a.mul_vec(&x, &mut ax);
        let (mut rr, mut bb) = (0.0, 0.0);
        for (i, d) in an.lower.diagonal(a).enumerate() {
            let d = (d + shift).abs();
            let s = if d.is_normal() { d.sqrt().recip() } else { 1.0 };
            let r = s * (ax[i] + shift * x[i] - b[i]);
            let sb = s * b[i];
            rr += r * r;
            bb += sb * sb;
        }
        let rel = (rr / bb).sqrt();
        rel.is_finite() && rel <= self.params.max_rel_residual
    }

    /// Which factorization is current, if any.
    pub fn factor_kind(&self) -> Option<FactorKind> {
        self.factor
    }

    /// Overwrites `rhs` with `A^-1 rhs` using the current factorization.
    pub fn solve_in_place(&self, rhs: &mut [f64]) -> Result<(), DirectError> {
        let kind = self.factor.ok_or(DirectError::NotFactorized)?;
        self.solve_with(kind, rhs)
    }

    fn solve_with(&self, kind: FactorKind, rhs: &mut [f64]) -> Result<(), DirectError> {
        let an = self.analysis.as_ref().ok_or(DirectError::NotFactorized)?;
        let n = an.symbolic.nrows();
        if rhs.len() != n {
            return Err(DirectError::Dimension { n, len: rhs.len() });
        }
        let par = self.par();
        let _flush = FlushSubnormals::new();
        let mut mem = MemBuffer::new(an.symbolic.solve_in_place_scratch::<f64>(1, par));
        let stack = MemStack::new(&mut mem);
        let x = MatMut::from_column_major_slice_mut(rhs, n, 1);
        match kind {
            FactorKind::Llt | FactorKind::ShiftedLlt { .. } => {
                LltRef::new(&an.symbolic, &self.factor_values).solve_in_place_with_conj(Conj::No, x, par, stack)
            }
            FactorKind::Ldlt => {
                LdltRef::new(&an.symbolic, &self.factor_values).solve_in_place_with_conj(Conj::No, x, par, stack)
            }
        }
        Ok(())
    }

    /// Factorizes `a` and solves `a x = b`.
    pub fn solve(&mut self, a: &CsrMatrix, b: &[f64], x: &mut [f64]) -> Result<FactorKind, DirectError> {
        if b.len() != a.n || x.len() != a.n {
            return Err(DirectError::Dimension {
                n: a.n,
                len: b.len().min(x.len()),
            });
        }
        self.factorize_and_solve(a, Some((b, x)))
    }
}

/// `v` as `len` zeros, keeping its allocation.
fn refill_zeros(v: &mut Vec<f64>, len: usize) {
    v.clear();
    v.resize(len, 0.0);
}

#[cfg(test)]
mod tests;
