//! Linear solver benchmark: sparse Cholesky (symbolic, numeric, solve) against
//! Jacobi-preconditioned CG on Dirichlet Laplacians, the textbook stand-in for
//! the Newton matrix of a fabric sheet (2D) and of a thick stack (3D).
//!
//! Run: `cargo run --example bench_linear --no-default-features [-- --max-n N] [--max-factor M]`
//! `--max-factor` skips the numeric factorization when the Cholesky factor
//! would hold more than `M` entries (8 bytes each); default 1.5e8 (1.2 GB).
//! This is a report, not a timed test: numbers depend on the machine.

use knitsim::solver::linear::{pcg, BlockJacobi, CgParams, DirectSolver};
use knitsim::sparse::CsrMatrix;
use std::time::Instant;

/// Dirichlet Laplacian on an `m^dim` grid: diagonal `2 dim`, `-1` per
/// neighbour inside the grid. SPD; its condition number grows like `m^2`.
fn laplacian(dim: u32, m: usize) -> CsrMatrix {
    let n = m.pow(dim);
    let stride = |axis: u32| m.pow(axis);
    let mut entries = Vec::with_capacity(n * (1 + 2 * dim as usize));
    for i in 0..n {
        entries.push((i as u32, i as u32));
        for axis in 0..dim {
            let coord = (i / stride(axis)) % m;
            if coord + 1 < m {
                let j = i + stride(axis);
                entries.push((i as u32, j as u32));
                entries.push((j as u32, i as u32));
            }
        }
    }
    let mut a = CsrMatrix::from_pattern(n, entries);
    for r in 0..n {
        for k in a.row_ptr[r]..a.row_ptr[r + 1] {
            a.values[k] = if a.col_idx[k] as usize == r {
                2.0 * dim as f64
            } else {
                -1.0
            };
        }
    }
    a
}

fn rel_residual(a: &CsrMatrix, x: &[f64], b: &[f64]) -> f64 {
    let mut ax = vec![0.0; a.n];
    a.mul_vec(x, &mut ax);
    let r: f64 = ax.iter().zip(b).map(|(u, v)| (u - v) * (u - v)).sum();
    let bb: f64 = b.iter().map(|v| v * v).sum();
    (r / bb).sqrt()
}

fn arg(name: &str, default: f64) -> f64 {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn main() {
    let max_n = arg("--max-n", f64::INFINITY);
    let max_factor = arg("--max-factor", 1.5e8);
    println!(
        "machine: {} logical cores",
        std::thread::available_parallelism().map_or(0, |p| p.get())
    );
    println!("direct: faer Cholesky with AMD; 'numeric' includes the residual probe solve. CG: Jacobi, rel_tol 1e-8.");
    println!(
        "{:<4} {:>8} {:>9} {:>11} {:>10} {:>10} {:>9} {:>9} {:>7} {:>9} {:>9}",
        "grid", "n", "nnz", "L entries", "symbolic", "numeric", "solve", "resid", "CG it", "CG time", "CG resid"
    );
    let cases = [(2, 71), (2, 224), (2, 707), (3, 17), (3, 37), (3, 80)];
    for (dim, m) in cases {
        let a = laplacian(dim, m);
        if a.n as f64 > max_n {
            continue;
        }
        let b: Vec<f64> = (0..a.n).map(|i| 1.0 + ((i * 7919) % 101) as f64 / 101.0).collect();
        let label = format!("{dim}D");

        let mut direct = DirectSolver::default();
        let t = Instant::now();
        let analysed = direct.analyze(&a);
        let t_sym = t.elapsed().as_secs_f64();
        let factor_len = direct.factor_len().unwrap_or(0);
        let direct_cols = if analysed.is_err() {
            format!("{:>10} {:>10} {:>9} {:>9}", "failed", "-", "-", "-")
        } else if factor_len as f64 > max_factor {
            format!("{t_sym:>10.3} {:>10} {:>9} {:>9}", "skipped", "-", "-")
        } else {
            let t = Instant::now();
            let factored = direct.factorize(&a);
            let t_num = t.elapsed().as_secs_f64();
            let mut x = b.clone();
            let t = Instant::now();
            let solved = factored.is_ok() && direct.solve_in_place(&mut x).is_ok();
            let t_solve = t.elapsed().as_secs_f64();
            if solved {
                let res = rel_residual(&a, &x, &b);
                format!("{t_sym:>10.3} {t_num:>10.3} {t_solve:>9.4} {res:>9.1e}")
            } else {
                format!("{t_sym:>10.3} {:>10} {:>9} {:>9}", "failed", "-", "-")
            }
        };

        let pre = BlockJacobi::diagonal(&a);
        let mut x = vec![0.0; a.n];
        let t = Instant::now();
        let cg = pcg(
            &a,
            &b,
            &mut x,
            &pre,
            CgParams {
                rel_tol: 1e-8,
                max_iter: 20_000,
            },
        );
        let t_cg = t.elapsed().as_secs_f64();
        println!(
            "{label:<4} {:>8} {:>9} {:>11} {direct_cols} {:>7} {:>9.3} {:>9.1e}",
            a.n,
            a.nnz(),
            factor_len,
            cg.iterations,
            t_cg,
            rel_residual(&a, &x, &b)
        );
    }
}
