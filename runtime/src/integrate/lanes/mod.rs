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

/// The instruction set and arithmetic an ensemble's lanes run with
/// ([`Ensemble::simd`](crate::ensemble::Ensemble::simd)), chosen when the ensemble runs, from what
/// the CPU has: no `RUSTFLAGS`, and a binary built on one machine runs on any other.
///
/// ```
/// use lagrange_runtime::ensemble::Simd;
/// // What this machine runs for each request: a path it has, or the nearest below it.
/// for s in [Simd::Native, Simd::Exact, Simd::Avx2Fma, Simd::Off] {
///     assert!(s.resolved() != Simd::Native && s.width() >= 1);
/// }
/// assert_eq!((Simd::Exact.width(), Simd::Off.width()), (4, 1));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Simd {
    /// The fastest path measured that the CPU has (the default): [`Avx2Fma`](Simd::Avx2Fma)
    /// where it has FMA, else [`Exact`](Simd::Exact), else one member at a time. The
    /// environment variable `LAGRANGE_SIMD` (`exact`, `avx2-fma`, `off`; any other value: the
    /// default) chooses another.
    #[default]
    Native,
    /// AVX2 lanes whose every operation rounds as the single run's (no fused multiply-add):
    /// a member equals its single run bit for bit, but where the vector sin and cos enter (to
    /// round-off there). One member at a time on a CPU without AVX2.
    Exact,
    /// AVX2 lanes with fused multiply-adds in the integrators' sums, the error norm, the
    /// Taylor convolutions, the generated kernels' multiply-adds and the vector sin, cos and ln:
    /// a member equals its single run to round-off. [`Exact`](Simd::Exact) on a CPU without FMA.
    Avx2Fma,
    /// One member at a time (what `Ensemble::lanes(1)` asks for).
    Off,
}

impl Simd {
    /// The members per vector of this path (4 in AVX2 lanes, 1 for [`Off`](Simd::Off);
    /// [`Native`](Simd::Native) as resolved on this CPU). An engine may run several vectors
    /// side by side: the Taylor method runs two (the list in `integrate/method.rs`).
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::Simd;
    /// assert_eq!((Simd::Avx2Fma.width(), Simd::Off.width()), (4, 1));
    /// ```
    pub fn width(self) -> usize {
        match self {
            Simd::Native => self.resolved().width(),
            Simd::Exact | Simd::Avx2Fma => 4,
            Simd::Off => 1,
        }
    }

    /// The path this CPU runs for the request: [`Native`](Simd::Native) resolved (by
    /// `LAGRANGE_SIMD`, else the fastest the CPU has), a path the CPU lacks lowered to the next
    /// one it has, [`Off`](Simd::Off) where it has none.
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::Simd;
    /// assert_ne!(Simd::Native.resolved(), Simd::Native);
    /// assert_eq!(Simd::Off.resolved(), Simd::Off);
    /// ```
    pub fn resolved(self) -> Simd {
        let want = match self {
            Simd::Native => match std::env::var("LAGRANGE_SIMD").as_deref() {
                Ok("exact") => Simd::Exact,
                Ok("off") => Simd::Off,
                _ => Simd::Avx2Fma,
            },
            other => other,
        };
        let (avx2, fma) = cpu();
        match want {
            Simd::Avx2Fma if avx2 && fma => Simd::Avx2Fma,
            Simd::Avx2Fma | Simd::Exact if avx2 => Simd::Exact,
            _ => Simd::Off,
        }
    }
}

/// Whether the CPU has AVX2 and FMA.
fn cpu() -> (bool, bool) {
    #[cfg(target_arch = "x86_64")]
    {
        (
            std::is_x86_feature_detected!("avx2"),
            std::is_x86_feature_detected!("fma"),
        )
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        (false, false)
    }
}

/// The members a lanes engine takes, one at a time as its lanes free: (position, run). An
/// ensemble's threads share one such queue, so each thread's lanes stay full until the whole
/// ensemble runs dry (one drain per thread, not one per block of members).
pub(crate) type Queue<'q, 'p, 'a, L, const N: usize> =
    dyn Iterator<Item = (usize, &'p mut Simulation<'a, L, N>)> + 'q;

/// Runs the members of `queue` on the path `simd` resolves to on this CPU, calling
/// `out(position, result)` as each member ends (not in order): DOP853 and Taylor members without
/// constraints in lanes, any other member on the scalar driver.
///
/// The lanes code is compiled twice on x86-64, for AVX2 (every operation the scalar one) and for
/// AVX2 with FMA (fused), chosen at run time, each engine at the members per pass its line in
/// `lanes_engines!` names (DOP853 4, Taylor 8); an x86-64 CPU without AVX2
/// runs the members one at a time (the same results as [`Simd::Exact`]: a lane is its scalar run
/// bit for bit there). Lanes in SSE2's 2-wide vectors were 1.6× slower than AVX2's and 8 lanes of
/// AVX-512 with FMA 16–19 % slower than 4 of AVX2 with FMA (BENCHMARKS.md, "Native vector
/// width": this project's AMD EPYC machines run AVX-512 on 256-bit units), so neither is compiled:
/// each path is a copy of both engines for every system in every build. Other architectures run
/// the exact engines as their own vector code.
pub(crate) fn run_lanes<L: Lagrangian<N>, const N: usize>(
    queue: &mut Queue<'_, '_, '_, L, N>,
    out: &mut Out<'_, N>,
    simd: Simd,
) {
    #[cfg(target_arch = "x86_64")]
    {
        // SAFETY (each `unsafe` below): `resolved` returns a path only where the CPU has every
        // feature its function enables.
        #[allow(unsafe_code)]
        match simd.resolved() {
            Simd::Avx2Fma => unsafe { run_lanes_avx2_fma::<L, N>(queue, out) },
            Simd::Exact => unsafe { run_lanes_avx2::<L, N>(queue, out) },
            Simd::Off | Simd::Native => one_at_a_time(queue, out),
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    match simd {
        Simd::Off => one_at_a_time(queue, out),
        _ => run_lanes_here::<L, N, false>(queue, out),
    }
}

/// Every member on the scalar driver, in the queue's order.
fn one_at_a_time<L: Lagrangian<N>, const N: usize>(
    queue: &mut Queue<'_, '_, '_, L, N>,
    out: &mut Out<'_, N>,
) {
    for (pos, sim) in queue {
        out(pos, sim.prepare().and_then(scalar));
    }
}

/// [`run_lanes_here`] compiled for AVX2, unfused ([`Simd::Exact`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn run_lanes_avx2<L: Lagrangian<N>, const N: usize>(
    queue: &mut Queue<'_, '_, '_, L, N>,
    out: &mut Out<'_, N>,
) {
    run_lanes_here::<L, N, false>(queue, out)
}

/// [`run_lanes_here`] compiled for AVX2 and FMA, fused ([`Simd::Avx2Fma`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn run_lanes_avx2_fma<L: Lagrangian<N>, const N: usize>(
    queue: &mut Queue<'_, '_, '_, L, N>,
    out: &mut Out<'_, N>,
) {
    run_lanes_here::<L, N, true>(queue, out)
}

/// The members of one method taken from a queue for its engine; members of any other method met
/// on the way are set aside in `rest` (for a later pass), so an engine never runs a member of
/// another method on the scalar driver while its lanes wait.
struct Taken<'r, 'p, 'a, I: Iterator, L, M, const N: usize> {
    queue: &'r mut core::iter::Peekable<I>,
    rest: &'r mut Vec<(usize, &'p mut Simulation<'a, L, N>)>,
    ours: M,
}

impl<'p, 'a, I, L, M, const N: usize> Iterator for Taken<'_, 'p, 'a, I, L, M, N>
where
    I: Iterator<Item = (usize, &'p mut Simulation<'a, L, N>)>,
    M: Fn(&Method) -> bool,
{
    type Item = (usize, &'p mut Simulation<'a, L, N>);

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            let (pos, sim) = self.queue.next()?;
            if (self.ours)(&sim.o.method) {
                return Some((pos, sim));
            }
            self.rest.push((pos, sim));
        }
    }
}

/// Declares the engines' files and [`run_lanes_here`] from the list of `method.rs`.
macro_rules! engines {
    ($($variant:ident => $file:ident, $w:literal lanes),* $(,)?) => {
        $(mod $file;)*

        /// The engines, for the instruction set of their caller: passes over the queue, each
        /// taking every member of the method of the first member left, on its engine (a method
        /// without an engine: that member on the scalar driver); the members of other methods
        /// met on the way make the next pass's queue. A constrained member's engine hands it to
        /// the scalar driver.
        #[inline(always)]
        fn run_lanes_here<L: Lagrangian<N>, const N: usize, const F: bool>(
            queue: &mut Queue<'_, '_, '_, L, N>,
            out: &mut Out<'_, N>,
        ) {
            // One call of `pass` (inlined with both engines: a second call site would compile
            // every engine twice over).
            let mut rest = Vec::new();
            let mut again: std::vec::IntoIter<(usize, &mut Simulation<'_, L, N>)>;
            let mut source: &mut Queue<'_, '_, '_, L, N> = queue;
            loop {
                pass::<L, N, F>(source, &mut rest, out);
                if rest.is_empty() {
                    return;
                }
                again = core::mem::take(&mut rest).into_iter();
                source = &mut again;
            }
        }

        /// One pass of [`run_lanes_here`] over `queue`, the members set aside to `rest`.
        #[inline(always)]
        fn pass<'p, 'a, L: Lagrangian<N>, const N: usize, const F: bool>(
            queue: &mut Queue<'_, 'p, 'a, L, N>,
            rest: &mut Vec<(usize, &'p mut Simulation<'a, L, N>)>,
            out: &mut Out<'_, N>,
        ) {
            let mut queue = queue.peekable();
            while let Some(method) = queue.peek().map(|(_, s)| s.o.method) {
                $(
                    if matches!(method, Method::$variant { .. }) {
                        let ours = |m: &Method| matches!(m, Method::$variant { .. });
                        $file::run::<L, N, $w, F>(Taken { queue: &mut queue, rest, ours }, out);
                        continue;
                    }
                )*
                if let Some((pos, sim)) = queue.next() {
                    out(pos, sim.prepare().and_then(scalar));
                }
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
        engine: impl FnOnce(&mut Queue<'_, '_, '_, Duffing, 1>, &mut Out<'_, 1>),
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
        engine(&mut sims.iter_mut().enumerate(), &mut |pos, r| {
            slots[pos] = Some(r)
        });
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
        let lanes = collect(&systems, |s, o| run_lanes(s, o, Simd::Exact));
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
