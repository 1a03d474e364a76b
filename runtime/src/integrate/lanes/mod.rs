//! The lanes engines: W members of an ensemble step together, one member per lane of
//! [`Lanes`](crate::lanes::Lanes) ([`run_lanes`] dispatches to the instruction set the CPU has).
//! One file per method, named by the list of `method.rs` (`lanes_engines!`), each with a
//! `pub(super) fn run` over its members: `dop853` (each lane its own step size, error norm and
//! decision) and `taylor` (the series of W members in one pass); [`members`] is what they share
//! (a member's entry, its slot, the refill of free lanes, its end). Members of another method,
//! and constrained ones, run the scalar driver. Making a method run in lanes is its engine's
//! file and its line in that list: nothing here changes.

mod members;

pub(crate) use members::Out;
pub use members::accelerations;

use crate::integrate::method::Method;
use crate::integrate::simulation::Simulation;
use crate::lagrangian::Lagrangian;

use members::scalar;

/// Runs `sims` (in order) with W members per vector, calling `out(position, result)` as each
/// member ends (not in order): DOP853 and Taylor members without constraints in lanes, any other
/// member on the scalar driver.
///
/// On an x86-64 CPU with AVX2 the engine runs as AVX2 code, chosen at run time so the same binary
/// runs everywhere; an x86-64 CPU without AVX2 runs the members one at a time (the same results:
/// a lane is its scalar run bit for bit). Lanes in SSE2's 2-wide vectors were 1.6× slower than
/// AVX2's (BENCHMARKS.md "Ensembles with SIMD lanes"), little faster than one member at a time,
/// and cost a second compiled copy of both engines for every system in every build. Other
/// architectures run the engines as their own vector code. Rust does not fuse a multiplication
/// and an addition unless asked (`mul_add`), so every path computes the same numbers.
pub(crate) fn run_lanes<L: Lagrangian<N>, const N: usize, const W: usize>(
    sims: &mut [Simulation<'_, L, N>],
    out: &mut Out<'_, N>,
) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: `run_lanes_avx2` only needs AVX2, which the CPU has (checked just above).
            #[allow(unsafe_code)]
            unsafe {
                run_lanes_avx2::<L, N, W>(sims, out)
            }
        } else {
            one_at_a_time(sims, out)
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    run_lanes_here::<L, N, W>(sims, out)
}

/// Every member on the scalar driver, in order.
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
fn one_at_a_time<L: Lagrangian<N>, const N: usize>(
    sims: &mut [Simulation<'_, L, N>],
    out: &mut Out<'_, N>,
) {
    for (pos, sim) in sims.iter_mut().enumerate() {
        out(pos, sim.prepare().and_then(scalar));
    }
}

/// [`run_lanes_here`] compiled for AVX2 (its vector code inlined here).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn run_lanes_avx2<L: Lagrangian<N>, const N: usize, const W: usize>(
    sims: &mut [Simulation<'_, L, N>],
    out: &mut Out<'_, N>,
) {
    run_lanes_here::<L, N, W>(sims, out)
}

/// Declares the engines' files and [`run_lanes_here`] from the list of `method.rs`.
macro_rules! engines {
    ($($variant:ident => $file:ident),* $(,)?) => {
        $(mod $file;)*

        /// The engines, for the instruction set of their caller: each method's members on its
        /// engine, in the order of the list; every other member (a method without an engine) on
        /// the scalar driver, in order. A constrained member's engine hands it to the scalar
        /// driver too.
        #[inline(always)]
        fn run_lanes_here<L: Lagrangian<N>, const N: usize, const W: usize>(
            sims: &mut [Simulation<'_, L, N>],
            out: &mut Out<'_, N>,
        ) {
            $(
                let ours = |s: &Simulation<'_, L, N>| matches!(s.o.method, Method::$variant { .. });
                if sims.iter().any(ours) {
                    let queue = sims.iter_mut().enumerate().filter(|(_, s)| ours(s));
                    $file::run::<L, N, W>(queue, out);
                }
            )*
            let engine = |s: &Simulation<'_, L, N>| false $(|| matches!(s.o.method, Method::$variant { .. }))*;
            for (pos, sim) in sims.iter_mut().enumerate().filter(|(_, s)| !engine(s)) {
                out(pos, sim.prepare().and_then(scalar));
            }
        }
    };
}

crate::integrate::method::lanes_engines!(engines);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scalar;
    use crate::integrate::error::SimulationError;
    use crate::integrate::trajectory::Trajectory;

    /// x'' = −k x − x³ (a hand-written system: its lanes are the trait's default).
    struct Duffing {
        k: f64,
    }

    impl Lagrangian<1> for Duffing {
        const COORDINATES: [&'static str; 1] = ["x"];
        const CYCLIC: [bool; 1] = [false];
        const AUTONOMOUS: bool = true;
        fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
            let x2 = q[0] * q[0];
            (v[0] * v[0] - x2 * self.k - x2 * x2 * 0.5) * 0.5
        }
    }

    /// Runs `sims` through `engine`, the results in member order.
    fn collect(
        systems: &[Duffing],
        engine: impl FnOnce(&mut [Simulation<'_, Duffing, 1>], &mut Out<'_, 1>),
    ) -> Vec<Result<Trajectory<1>, SimulationError>> {
        let mut sims: Vec<Simulation<'_, Duffing, 1>> = systems
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let sim = Simulation::new(s, [0.5 + 0.1 * i as f64], [0.0]).sample_every(0.5);
                match i % 3 {
                    // A member the lanes do not take, and one that fails before its first step.
                    1 => sim.method(Method::Rk4 { dt: 0.01 }).until(3.0),
                    2 if i == 5 => sim.until(f64::NAN),
                    _ => sim.until(3.0 + i as f64 * 0.25),
                }
            })
            .collect();
        let mut slots: Vec<Option<Result<Trajectory<1>, SimulationError>>> =
            systems.iter().map(|_| None).collect();
        engine(&mut sims, &mut |pos, r| slots[pos] = Some(r));
        slots
            .into_iter()
            .map(|r| r.expect("every member ends"))
            .collect()
    }

    /// The path of an x86-64 CPU without AVX2 (members one at a time) gives what the lanes give,
    /// bit for bit, failures included.
    #[test]
    fn one_at_a_time_equals_the_lanes() {
        let systems: Vec<Duffing> = (0..11).map(|i| Duffing { k: 1.0 + i as f64 }).collect();
        let lanes = collect(&systems, run_lanes::<Duffing, 1, 4>);
        let plain = collect(&systems, one_at_a_time::<Duffing, 1>);
        for (i, (a, b)) in lanes.iter().zip(&plain).enumerate() {
            match (a, b) {
                (Ok(a), Ok(b)) => {
                    let bits = |tr: &Trajectory<1>| -> Vec<u64> {
                        tr.t.iter()
                            .chain(tr.q.iter().map(|q| &q[0]))
                            .chain(tr.qdot.iter().map(|v| &v[0]))
                            .map(|x| x.to_bits())
                            .collect()
                    };
                    assert_eq!(bits(a), bits(b), "member {i}");
                    assert_eq!(a.stats.steps, b.stats.steps, "member {i}");
                }
                (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "member {i}"),
                _ => panic!("member {i}: {a:?} vs {b:?}"),
            }
        }
        assert!(plain[5].is_err() && plain.iter().filter(|r| r.is_ok()).count() == 10);
    }
}
