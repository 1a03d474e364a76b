//! What the modules of the integration test crates (tests/equations.rs, tests/physics.rs,
//! tests/ensembles.rs) share: the systems declared once ([`systems`], from the examples' package: benches/symbolic.rs uses
//! them too), the hand-written heavy top ([`hand`]) and a small deterministic random
//! generator ([`Rng`]).
// Each test crate uses a subset.
#![allow(dead_code)]

pub mod hand;
pub use lagrange_examples::systems;
// The systems the examples share, from the examples' package (declared once, in examples/support/;
// each test crate uses some of them).
#[allow(unused_imports)]
pub use lagrange_examples::double_pendulum_system as double_pendulum;
#[allow(unused_imports)]
pub use lagrange_examples::four_bar_system as four_bar;
#[allow(unused_imports)]
pub use lagrange_examples::quaternion_top_system as quaternion_top;

use lagrange::prelude::*;

/// ∫ₐᵇ f by composite Gauss–Legendre quadrature, 5 points on each of 64 panels (degree 9 per
/// panel: a smooth integrand's integral to round-off).
pub fn gauss_legendre(a: f64, b: f64, f: impl Fn(f64) -> f64) -> f64 {
    const X: [f64; 5] = [
        -0.906_179_845_938_664,
        -0.538_469_310_105_683,
        0.0,
        0.538_469_310_105_683,
        0.906_179_845_938_664,
    ];
    const W: [f64; 5] = [
        0.236_926_885_056_189,
        0.478_628_670_499_366,
        0.568_888_888_888_889,
        0.478_628_670_499_366,
        0.236_926_885_056_189,
    ];
    let panels = 64;
    let h = (b - a) / panels as f64;
    let mut sum = 0.0;
    for p in 0..panels {
        let mid = a + (p as f64 + 0.5) * h;
        for (x, w) in X.iter().zip(W) {
            sum += w * 0.5 * h * f(mid + 0.5 * h * x);
        }
    }
    sum
}

/// A small deterministic generator (xorshift) so the tests need no extra dependency.
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }

    /// Three uniform components in [lo, hi), x first.
    pub fn vec3(&mut self, lo: f64, hi: f64) -> Vector3<f64> {
        Vector3::new(
            self.uniform(lo, hi),
            self.uniform(lo, hi),
            self.uniform(lo, hi),
        )
    }

    /// Three uniform values in [lo, hi), the first drawn first.
    pub fn arr3(&mut self, lo: f64, hi: f64) -> [f64; 3] {
        [
            self.uniform(lo, hi),
            self.uniform(lo, hi),
            self.uniform(lo, hi),
        ]
    }
}

/// The generated kernels as the tests call them: a single run's Taylor series and W members'
/// series and q̈ in lanes, through `Lagrangian::series_in` / `accelerations_in` (the trait's
/// generic entries) with the parameters loaded afresh.
pub trait Kernels<const N: usize>: Lagrangian<N> + Sized {
    /// The Taylor series of this system (width 1): `None` where it has none.
    fn taylor_series(
        &self,
        t: f64,
        out: &mut [[[f64; N]; 2]],
        buf: &mut lagrange::taylor::SeriesBuf<f64>,
    ) -> Option<Result<(), DynamicsError>> {
        Self::series_in(&[self], &mut Vec::new(), t, out, buf).map(|r| r.map(|_| ()))
    }

    /// The Taylor series of W members in lanes, with the lanes computed (`None`: no kernel).
    fn taylor_series_lanes<const W: usize>(
        members: &[&Self; W],
        t: lagrange::lanes::Lanes<W>,
        out: &mut [[[lagrange::lanes::Lanes<W>; N]; 2]],
        buf: &mut lagrange::taylor::SeriesBuf<lagrange::lanes::Lanes<W>>,
    ) -> Option<lagrange::lanes::Mask<W>> {
        Self::series_in(members, &mut Vec::new(), t, out, buf).and_then(Result::ok)
    }

    /// q̈ of W members in lanes as the ensemble engine computes it (a lane the kernel leaves
    /// out by its member's own `accelerations`, NaN where that fails).
    fn accelerations_lanes<const W: usize>(
        members: &[&Self; W],
        q: &[lagrange::lanes::Lanes<W>; N],
        qdot: &[lagrange::lanes::Lanes<W>; N],
        t: lagrange::lanes::Lanes<W>,
    ) -> [lagrange::lanes::Lanes<W>; N] {
        lagrange::ensemble::lane_accelerations(members, &mut Vec::new(), q, qdot, t)
    }
}

impl<L: Lagrangian<N>, const N: usize> Kernels<N> for L {}

/// The heavy top the integrator tests run (tests/integrators.rs, tests/stiff.rs).
#[allow(dead_code)]
pub const TOP: hand::HeavyTop = hand::HeavyTop {
    i_perp: 1.0,
    i_par: 0.6,
    mgl: 1.0,
};
#[allow(dead_code)]
pub const TOP_Q0: [f64; 3] = [1.0, 0.0, 0.0];
#[allow(dead_code)]
pub const TOP_V0: [f64; 3] = [0.0, -0.5, 8.0];

/// Least-squares slope of log(err) against log(x).
#[allow(dead_code)]
pub fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0);
    for &(x, e) in points {
        let (x, y) = (x.ln(), e.ln());
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    (n * sxy - sx * sy) / (n * sxx - sx * sx)
}
