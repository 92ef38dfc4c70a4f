//! An ordered parallel map: `f(k)` for `k` in `0..n` on several threads,
//! results handed to the caller block by block *in index order*.
//!
//! Why not a plain fork-join per block: the first version spawned scoped
//! threads for every block of 512 stencils, about 200 spawns and joins per
//! Newton assembly of a 40x40 linen stitch, and every join waited for the
//! slowest thread of its block (PSD projections run only for indefinite
//! stencils, so blocks are uneven). Measured on that case's first two
//! relaxation steps, two threads evaluated only 1.44 times as fast as one.
//! Here the threads are spawned once per call and take blocks from a
//! shared counter; the calling thread evaluates blocks too and emits every
//! finished block whose predecessors have all been emitted.
//!
//! Results do not depend on the thread count or on timing: `f` is pure and
//! `emit` sees the results in index order, so every sum the caller forms
//! is done in the same order as on one thread (bit-identical assembly).

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;

/// Calls `emit(start, results)` for consecutive blocks of `block` indices,
/// `results[i] = f(start + i)`, in increasing `start`, evaluating `f` on
/// `workers` threads (the caller's included).
pub fn ordered_map<T: Send, F>(workers: usize, block: usize, n: usize, f: F, mut emit: impl FnMut(usize, &[T]))
where
    F: Fn(usize) -> T + Sync,
{
    let block = block.max(1);
    let blocks = n.div_ceil(block);
    let eval = |b: usize| -> Vec<T> { (b * block..((b + 1) * block).min(n)).map(&f).collect() };
    if workers <= 1 || blocks <= 1 {
        for b in 0..blocks {
            emit(b * block, &eval(b));
        }
        return;
    }
    let next = AtomicUsize::new(0);
    let take = || Some(next.fetch_add(1, Ordering::Relaxed)).filter(|&b| b < blocks);
    std::thread::scope(|scope| {
        // Blocks that finish ahead of the one to emit wait in `done`; at
        // worst that is a whole set's results (1.2 kB per 12x12 stencil:
        // gradient and Hessian). The channel is created inside
        // the scope: if this thread panics, the receiver is dropped before
        // the scope joins, so no helper waits on a full channel.
        let (tx, rx) = mpsc::sync_channel::<(usize, Vec<T>)>(4 * workers);
        let helpers: Vec<_> = (1..workers.min(blocks))
            .map(|_| {
                let tx = tx.clone();
                let (take, eval) = (&take, &eval);
                scope.spawn(move || {
                    while let Some(b) = take() {
                        if tx.send((b, eval(b))).is_err() {
                            return;
                        }
                    }
                })
            })
            .collect();
        drop(tx);
        let mut done: BTreeMap<usize, Vec<T>> = BTreeMap::new();
        let mut emitted = 0;
        while emitted < blocks {
            if let Some(results) = done.remove(&emitted) {
                emit(emitted * block, &results);
                emitted += 1;
            } else if let Ok((b, results)) = rx.try_recv() {
                done.insert(b, results);
            } else if let Some(b) = take() {
                done.insert(b, eval(b));
            } else {
                match rx.recv() {
                    Ok((b, results)) => {
                        done.insert(b, results);
                    }
                    // Every helper has ended without the block: one panicked.
                    Err(_) => break,
                }
            }
        }
        // A helper's panic reaches the caller with its own message.
        for helper in helpers {
            if let Err(payload) = helper.join() {
                std::panic::resume_unwind(payload);
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    fn collect(workers: usize, block: usize, n: usize) -> (Vec<u64>, Vec<usize>) {
        let (mut out, mut starts) = (Vec::new(), Vec::new());
        // Uneven work, so helpers finish out of order.
        let f = |k: usize| {
            let mut x = k as u64;
            for _ in 0..(k % 7) * 2000 {
                x = x.wrapping_mul(6364136223846793005).wrapping_add(1);
            }
            x
        };
        ordered_map(workers, block, n, f, |start, r: &[u64]| {
            starts.push(start);
            out.extend_from_slice(r);
        });
        (out, starts)
    }

    #[test]
    fn results_arrive_in_index_order_for_any_thread_count_and_block() {
        let (serial, _) = collect(1, 1000, 1000);
        assert_eq!(serial.len(), 1000);
        for workers in [2, 3, 8] {
            for block in [1, 7, 64, 5000] {
                let (out, starts) = collect(workers, block, 1000);
                assert_eq!(out, serial, "workers {workers}, block {block}");
                let expect: Vec<usize> = (0..1000).step_by(block).collect();
                assert_eq!(starts, expect);
            }
        }
    }

    #[test]
    fn an_empty_range_emits_nothing() {
        let (out, starts) = collect(4, 16, 0);
        assert!(out.is_empty() && starts.is_empty());
    }

    #[test]
    #[should_panic(expected = "stencil 5")]
    fn a_panicking_evaluation_reaches_the_caller() {
        ordered_map(
            3,
            1,
            64,
            |k| {
                if k == 5 {
                    panic!("stencil 5");
                }
                k
            },
            |_, _: &[usize]| {},
        );
    }
}
