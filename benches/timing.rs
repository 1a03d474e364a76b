//! What the benches that time a whole run share (each bench a binary of its own, this file a
//! module of those that need it).

use std::time::Instant;

/// The best wall time of `n` calls of `f`, in seconds.
pub fn best_of(n: usize, mut f: impl FnMut()) -> f64 {
    (0..n)
        .map(|_| {
            let t0 = Instant::now();
            f();
            t0.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}
