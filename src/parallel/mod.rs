//! How knitsim uses the machine's cores, in one place.
//!
//! Work is spread over threads only where the result does not depend on how
//! it was spread: stencil evaluation in the Newton assembly (results emitted
//! in index order by [`ordered_map`], so every sum is formed in the same
//! order on any thread count), the direct solver's probe solve beside the
//! caller's own, and the PNG renderer's tiles. A run is reproducible bit for
//! bit on any machine, and `KNITSIM_THREADS=1` gives the same output as the
//! default.

mod ordered_map;

pub use ordered_map::ordered_map;
use std::sync::OnceLock;

/// Worker threads: `KNITSIM_THREADS` if set, else the machine's available
/// parallelism (read once per process). Results do not depend on it.
pub fn threads() -> usize {
    static THREADS: OnceLock<usize> = OnceLock::new();
    *THREADS.get_or_init(|| {
        std::env::var("KNITSIM_THREADS")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
            .max(1)
    })
}
