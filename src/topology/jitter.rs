//! Sub-nanometre jitter of a compiled fabric's nodes: the perturbation that
//! tells a reproducible relaxation from one that is chaotic at rounding
//! level (benchmarks and tests compare runs from jittered starts).

use super::Fabric;

/// Moves every node by up to `1e-9` m per coordinate, from a splitmix64
/// stream of `seed` (0: no jitter), so runs are repeatable.
pub fn jitter(fabric: &mut Fabric, seed: u64) {
    if seed == 0 {
        return;
    }
    let mut state = seed;
    let mut next = || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for node in &mut fabric.nodes {
        for k in 0..3 {
            node.x[k] += 1e-9 * next();
        }
    }
}
