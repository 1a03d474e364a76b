//! Ensembles: many runs of one kind of system — a parameter sweep, Monte Carlo over initial
//! states — on the [`Simulation`] builder's terms, in parallel threads, each member's failure kept
//! in its own slot, the results in member order, and shards for job arrays on a cluster.
//!
//! A member is a system with its initial state and, for the CSV, its parameters by name
//! ([`Member`]); the ensemble makes one from each index with a closure ([`Ensemble::new`]) or
//! takes them from an iterator ([`Ensemble::from_members`]), applies the same options
//! to every member's [`Simulation`] ([`Ensemble::configure`]), and returns for each member either
//! its whole [`Trajectory`] ([`Ensemble::run`]) or a row of numbers a closure computes from it
//! ([`Ensemble::reduce`]). DOP853 and Taylor members run several per vector, one per SIMD lane
//! ([`Ensemble::lanes`]; by default for a system with generated lanes code, 4 per AVX2 vector
//! with fused multiply-adds where the CPU has FMA, chosen at run time: [`Ensemble::simd`]).
//! [`Ensemble::shard`] runs the k-th of n contiguous blocks of members, so
//! a batch scheduler's job array runs the blocks on as many machines and their CSVs concatenate
//! (the README's "Ensembles" section has the recipe).
//!
//! ```
//! use lagrange_runtime::ensemble::{Ensemble, Member};
//! use lagrange_runtime::{Lagrangian, Method, Scalar};
//! /// x'' = −w² x.
//! struct Osc { w: f64 }
//! impl Lagrangian<1> for Osc {
//!     const COORDINATES: [&'static str; 1] = ["x"];
//!     const CYCLIC: [bool; 1] = [false];
//!     const AUTONOMOUS: bool = true;
//!     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
//!         (v[0] * v[0] - q[0] * q[0] * (self.w * self.w)) * 0.5
//!     }
//! }
//! // x(π) for w = 1, 2, 3 from x = 1 at rest: cos(wπ) = −1, 1, −1.
//! let rows = Ensemble::new(3, |i| Member::new(Osc { w: (i + 1) as f64 }, [1.0], [0.0]).param("w", (i + 1) as f64))
//!     .configure(|sim| sim.method(Method::Dop853 { rtol: 1e-12, atol: 1e-14 }).until(std::f64::consts::PI))
//!     .reduce(&["x_end"], |tr| vec![tr.q[tr.q.len() - 1][0]]);
//! let x: Vec<f64> = rows.results.iter().map(|r| r.as_ref().unwrap()[0]).collect();
//! assert!((x[0] + 1.0).abs() < 1e-9 && (x[1] - 1.0).abs() < 1e-9 && (x[2] + 1.0).abs() < 1e-9);
//! assert_eq!(rows.params[1], vec![("w", 2.0)]);
//! ```

use std::io::Write;
use std::marker::PhantomData;
use std::ops::Range;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;

use crate::constraints::Holonomic;
pub use crate::integrate::lanes::Simd;
#[doc(hidden)]
pub use crate::integrate::lanes::accelerations as lane_accelerations;
use crate::integrate::lanes::{Out, Queue, run_lanes};
use crate::integrate::{Simulation, SimulationError, Trajectory};
use crate::lagrangian::Lagrangian;

/// One member of an ensemble: a system, its initial state, and its parameters by name (the CSV's
/// columns; they do not change the run).
///
/// ```
/// # use lagrange_runtime::ensemble::Member;
/// let m = Member::new((), [0.5], [0.0]).param("k", 2.0);
/// assert_eq!((m.q0, m.params.clone()), ([0.5], vec![("k", 2.0)]));
/// ```
#[derive(Clone, Debug)]
pub struct Member<L, const N: usize> {
    /// The system.
    pub system: L,
    /// Initial coordinates.
    pub q0: [f64; N],
    /// Initial velocities.
    pub qdot0: [f64; N],
    /// Named parameters, in the CSV's column order.
    pub params: Params,
}

impl<L, const N: usize> Member<L, N> {
    /// A member with no named parameters.
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::Member;
    /// assert!(Member::new((), [0.0; 2], [1.0; 2]).params.is_empty());
    /// ```
    pub fn new(system: L, q0: [f64; N], qdot0: [f64; N]) -> Self {
        Member {
            system,
            q0,
            qdot0,
            params: Vec::new(),
        }
    }

    /// Adds a named parameter (a CSV column).
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::Member;
    /// let m = Member::new((), [0.0], [0.0]).param("a", 1.0).param("b", 2.0);
    /// assert_eq!(m.params, vec![("a", 1.0), ("b", 2.0)]);
    /// ```
    pub fn param(mut self, name: &'static str, value: f64) -> Self {
        self.params.push((name, value));
        self
    }
}

/// The most threads [`Ensemble::threads`] starts per available core.
pub const MAX_THREADS_PER_CORE: usize = 4;

/// A member's named parameters.
pub type Params = Vec<(&'static str, f64)>;

/// The options every member's [`Simulation`] gets.
type Configure<'c, L, const N: usize> =
    Box<dyn for<'s> Fn(Simulation<'s, L, N>) -> Simulation<'s, L, N> + Sync + 'c>;

/// The lanes engine's entry: members as its lanes free (from a queue its thread shares with the
/// others), each result to the sink as the member ends, on the path the [`Simd`] resolves to.
type LanesFn<L, const N: usize> =
    for<'q, 'p, 's, 'o> fn(&mut Queue<'q, 'p, 's, L, N>, &mut Out<'o, N>, Simd);

/// The members per thread in one round of a lanes ensemble: the threads share the round's members
/// from one queue, and each keeps the runs it took until the round ends (a few hundred bytes
/// each) in a room of twice its even share (a faster thread takes more), so that memory is
/// about 2 · 1024 runs per thread whatever the number of threads; each round ends in one drain
/// per thread (its lanes emptying), under 1 % of a round of tops.
const ROUND_PER_THREAD: usize = 1024;

/// How the members of an ensemble run: [`Plain`] (as they are; DOP853 and Taylor members share
/// SIMD lanes) or [`Constrained`] (the constrained run of their system). A type parameter of
/// [`Ensemble`] rather than a field, so that a constrained ensemble does not compile the lanes
/// engines it never uses (large generic code: a minute and a half of build for one system).
///
/// ```
/// use lagrange_runtime::ensemble::{Constrained, Engine, Plain};
/// # use lagrange_runtime::{Holonomic, Lagrangian, Scalar};
/// # struct P;
/// # impl Lagrangian<2> for P {
/// #     const COORDINATES: [&'static str; 2] = ["x", "y"];
/// #     const CYCLIC: [bool; 2] = [true, true];
/// #     const AUTONOMOUS: bool = true;
/// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 2], v: &[S; 2], _t: S) -> S { (v[0] * v[0] + v[1] * v[1]) * 0.5 }
/// # }
/// # impl Holonomic<2, 1> for P {
/// #     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] { [q[0] * q[0] + q[1] * q[1] - 1.0] }
/// # }
/// assert!(<Plain as Engine<P, 2>>::lanes().is_some());
/// assert!(<Constrained<1> as Engine<P, 2>>::lanes().is_none());
/// ```
pub trait Engine<L: Lagrangian<N>, const N: usize> {
    /// Runs one configured member.
    fn run_one(system: &L, sim: Simulation<'_, L, N>) -> Result<Trajectory<N>, SimulationError>;

    /// The lanes engine, where members may share SIMD lanes (none unless said).
    #[doc(hidden)]
    fn lanes() -> Option<LanesFn<L, N>> {
        None
    }
}

/// Members run as they are ([`Ensemble::new`]'s engine).
///
/// ```
/// # use lagrange_runtime::ensemble::{Engine, Plain};
/// # use lagrange_runtime::{Lagrangian, Scalar};
/// # struct Free;
/// # impl Lagrangian<1> for Free {
/// #     const COORDINATES: [&'static str; 1] = ["x"];
/// #     const CYCLIC: [bool; 1] = [true];
/// #     const AUTONOMOUS: bool = true;
/// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
/// # }
/// let sim = lagrange_runtime::Simulation::new(&Free, [0.0], [2.0]).until(1.0);
/// let tr = <Plain as Engine<Free, 1>>::run_one(&Free, sim).unwrap();
/// assert!((tr.q[tr.q.len() - 1][0] - 2.0).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, Default)]
pub struct Plain;

impl<L: Lagrangian<N>, const N: usize> Engine<L, N> for Plain {
    fn run_one(_: &L, sim: Simulation<'_, L, N>) -> Result<Trajectory<N>, SimulationError> {
        sim.run()
    }

    fn lanes() -> Option<LanesFn<L, N>> {
        // Members whose system declares constraints or contacts run one at a time, as
        // `Simulation::run` runs them (the lanes step the unconstrained motion); the branch is
        // decided per system when it compiles, so their lanes engine is not built.
        if L::COMPILED.constrained || L::DECLARES_CONTACTS {
            return None;
        }
        // One width per instruction set is compiled (the engine is large and generic in the
        // system): `Simd`'s paths.
        Some(run_lanes::<L, N>)
    }
}

/// Members run as the constrained run of their system with K constraints
/// ([`Ensemble::constrained`]).
///
/// ```
/// # use lagrange_runtime::ensemble::{Constrained, Engine};
/// # use lagrange_runtime::{Holonomic, Lagrangian, Scalar};
/// # struct P;
/// # impl Lagrangian<2> for P {
/// #     const COORDINATES: [&'static str; 2] = ["x", "y"];
/// #     const CYCLIC: [bool; 2] = [true, true];
/// #     const AUTONOMOUS: bool = true;
/// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 2], v: &[S; 2], _t: S) -> S { (v[0] * v[0] + v[1] * v[1]) * 0.5 }
/// # }
/// # impl Holonomic<2, 1> for P {
/// #     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] { [q[0] * q[0] + q[1] * q[1] - 1.0] }
/// # }
/// // A free particle on the unit circle keeps its speed and stays on the circle.
/// let sim = lagrange_runtime::Simulation::new(&P, [1.0, 0.0], [0.0, 1.0]).until(3.0);
/// let tr = <Constrained<1> as Engine<P, 2>>::run_one(&P, sim).unwrap();
/// let [x, y] = tr.q[tr.q.len() - 1];
/// assert!((x * x + y * y - 1.0).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, Default)]
pub struct Constrained<const K: usize>;

impl<L: Holonomic<N, K>, const N: usize, const K: usize> Engine<L, N> for Constrained<K> {
    fn run_one(system: &L, plain: Simulation<'_, L, N>) -> Result<Trajectory<N>, SimulationError> {
        let (q0, qdot0) = plain.initial();
        Simulation::constrained(system, q0, qdot0)
            .options_from(plain)
            .run()
    }
}

/// An ensemble of `len` members made by a closure from their index ([`Ensemble::new`]) or taken
/// from an iterator ([`Ensemble::from_members`]; see the module docs); `E` says how they run
/// ([`Plain`], or [`Constrained`] after [`Ensemble::constrained`]).
pub struct Ensemble<'c, L, F, const N: usize, E = Plain> {
    len: usize,
    member: F,
    configure: Configure<'c, L, N>,
    threads: Option<usize>,
    shard: Option<(usize, usize)>,
    progress: bool,
    /// Whether members share lanes; `None`: where the system has generated lanes code.
    lanes: Option<bool>,
    /// The lanes' instruction set and width.
    simd: Simd,
    engine: PhantomData<fn() -> E>,
}

/// What an ensemble returns: for each member run, in member order, its index, its parameters and
/// its result (its typed error in its slot if it failed: the others are not affected). A member
/// whose closures or system code panic gets [`SimulationError::MemberPanicked`] with the panic's
/// message (and no parameters if its member closure panicked); with lanes, a panic in the
/// system's code is that of every member then in the engine's lanes (the engine starts again on
/// the members left).
#[derive(Debug)]
pub struct Results<R> {
    /// The members' indices (all of them, or the shard's block).
    pub index: Vec<usize>,
    /// The members' named parameters.
    pub params: Vec<Params>,
    /// Each member's result.
    pub results: Vec<Result<R, SimulationError>>,
    /// The names of a reduction's values (empty for whole trajectories).
    pub columns: Vec<String>,
}

/// The index-to-member closure of [`Ensemble::from_members`] (a type to name the `impl` block by;
/// it is never called).
type FromMembers<L, const N: usize> = fn(usize) -> Member<L, N>;

impl<'c, L, const N: usize> Ensemble<'c, L, FromMembers<L, N>, N, Plain>
where
    L: Lagrangian<N> + Clone + Sync,
{
    /// An ensemble of the members a (finite) iterator gives, in its order: for members that come
    /// from data (measured initial states, rows of a parameter file) rather than from an index.
    /// Member `i` is the iterator's `i`-th item; each runs on a clone of it, so shards, threads
    /// and lanes work as with [`Ensemble::new`].
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::{Ensemble, Member};
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # #[derive(Clone)]
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// // Three measured speeds; x(2) = 2 v.
    /// let speeds = [0.5, -1.0, 3.0];
    /// let r = Ensemble::from_members(speeds.iter().map(|&v| Member::new(Free, [0.0], [v]).param("v", v)))
    ///     .configure(|sim| sim.until(2.0))
    ///     .reduce(&["x_end"], |tr| tr.q[tr.q.len() - 1][0]);
    /// assert_eq!(r.index, vec![0, 1, 2]);
    /// for (i, v) in speeds.iter().enumerate() {
    ///     assert!((r.results[i].as_ref().unwrap() - 2.0 * v).abs() < 1e-12);
    ///     assert_eq!(r.params[i], vec![("v", *v)]);
    /// }
    /// ```
    pub fn from_members(
        members: impl IntoIterator<Item = Member<L, N>>,
    ) -> Ensemble<'c, L, impl Fn(usize) -> Member<L, N> + Sync, N, Plain> {
        let members: Vec<Member<L, N>> = members.into_iter().collect();
        // `i` is one of `0..members.len()` (`Ensemble::members`): the index is in range.
        Ensemble::new(members.len(), move |i| members[i].clone())
    }
}

impl<'c, L, F, const N: usize> Ensemble<'c, L, F, N, Plain>
where
    L: Lagrangian<N>,
    F: Fn(usize) -> Member<L, N> + Sync,
{
    /// `len` members, member `i` made by `member(i)`; each runs with the [`Simulation`]
    /// defaults until [`configure`](Ensemble::configure) says otherwise.
    ///
    /// ```
    /// use lagrange::prelude::*;
    ///
    /// /// A free particle of mass m.
    /// pub struct Free { pub m: f64 }
    ///
    /// #[lagrangian]
    /// impl Free {
    ///     fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
    ///         0.5 * self.m * x_dot * x_dot
    ///     }
    /// }
    ///
    /// // Five particles launched at 0, 1, …, 4: after t = 2 each is at 2 v.
    /// let runs = Ensemble::new(5, |i| Member::new(Free { m: 1.0 }, [0.0], [i as f64]).param("v", i as f64))
    ///     .configure(|sim| sim.until(2.0))
    ///     .reduce(&["x"], |tr| vec![tr.q[tr.len() - 1][0]]);
    /// for (i, r) in runs.results.iter().enumerate() {
    ///     assert!((r.as_ref().unwrap()[0] - 2.0 * i as f64).abs() < 1e-12);
    /// }
    /// ```
    pub fn new(len: usize, member: F) -> Self {
        Ensemble {
            len,
            member,
            configure: Box::new(|s| s),
            threads: None,
            shard: None,
            progress: false,
            lanes: None,
            simd: Simd::Native,
            engine: PhantomData,
        }
    }

    /// Runs every member as the constrained run of its system ([`Simulation::constrained`]:
    /// the index-1 equations with projection after every step, λ at every sample), with the
    /// options [`configure`](Ensemble::configure) gives.
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::{Ensemble, Member};
    /// # use lagrange_runtime::{Holonomic, Lagrangian, Scalar};
    /// /// A unit mass on a rod of length 1 in x, y, under gravity.
    /// struct Pendulum;
    /// # impl Lagrangian<2> for Pendulum {
    /// #     const COORDINATES: [&'static str; 2] = ["x", "y"];
    /// #     const CYCLIC: [bool; 2] = [true, false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
    /// #         (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[1] * 9.81
    /// #     }
    /// # }
    /// # impl Holonomic<2, 1> for Pendulum {
    /// #     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] {
    /// #         [q[0] * q[0] + q[1] * q[1] - 1.0]
    /// #     }
    /// # }
    /// // From the bottom with speeds 0, 1, 2: the rod's residual stays at round-off.
    /// let r = Ensemble::new(3, |i| Member::new(Pendulum, [0.0, -1.0], [i as f64, 0.0]))
    ///     .constrained::<1>()
    ///     .configure(|sim| sim.until(5.0))
    ///     .run();
    /// for tr in &r.results {
    ///     assert!(tr.as_ref().unwrap().invariants().constraints.unwrap().position < 1e-12);
    /// }
    /// ```
    pub fn constrained<const K: usize>(self) -> Ensemble<'c, L, F, N, Constrained<K>>
    where
        L: Holonomic<N, K>,
    {
        Ensemble {
            len: self.len,
            member: self.member,
            configure: self.configure,
            threads: self.threads,
            shard: self.shard,
            progress: self.progress,
            lanes: self.lanes,
            simd: self.simd,
            engine: PhantomData,
        }
    }
}

impl<'c, L, F, E, const N: usize> Ensemble<'c, L, F, N, E>
where
    L: Lagrangian<N>,
    F: Fn(usize) -> Member<L, N> + Sync,
    E: Engine<L, N>,
{
    /// The options of every member's run, on the [`Simulation`] builder's terms (method, end
    /// time, samples, events, limits).
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::{Ensemble, Member};
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// // A free particle moves at its velocity: x(2) = 2 v.
    /// let r = Ensemble::new(3, |i| Member::new(Free, [0.0], [i as f64]))
    ///     .configure(|sim| sim.until(2.0))
    ///     .reduce(&["x"], |tr| tr.q[tr.q.len() - 1][0]);
    /// assert!((r.results[2].as_ref().unwrap() - 4.0).abs() < 1e-12);
    /// ```
    pub fn configure(
        mut self,
        f: impl for<'s> Fn(Simulation<'s, L, N>) -> Simulation<'s, L, N> + Sync + 'c,
    ) -> Self {
        self.configure = Box::new(f);
        self
    }

    /// Runs on `n` threads (default: rayon's global pool, one thread per core). `n = 1` runs in
    /// the calling thread; `n = 0` is taken as 1, and `n` above 4 × the available parallelism
    /// ([`std::thread::available_parallelism`]) as that bound ([`MAX_THREADS_PER_CORE`]): more
    /// threads than that only cost their start (5000 took 15 s) and memory. The pool of `n`
    /// threads is made by the first ensemble that asks for it and kept for the process (idle
    /// between ensembles), as rayon keeps its global pool.
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::{Ensemble, Member};
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let r = Ensemble::new(4, |i| Member::new(Free, [i as f64], [0.0]))
    ///     .configure(|sim| sim.until(1.0))
    ///     .threads(2)
    ///     .run();
    /// assert_eq!(r.index, vec![0, 1, 2, 3]); // member order, whatever thread ran them
    /// assert_eq!(r.results[3].as_ref().unwrap().q[0], [3.0]);
    /// ```
    pub fn threads(mut self, n: usize) -> Self {
        let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
        self.threads = Some(n.clamp(1, MAX_THREADS_PER_CORE.saturating_mul(cores)));
        self
    }

    /// Runs only block `k` of `n` (0 ≤ k < n): members `k·len/n .. (k+1)·len/n`, so that n jobs
    /// of a job array cover the ensemble exactly once and their CSVs concatenate in member order.
    /// An out-of-range `k` or `n = 0` runs no member.
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::{Ensemble, Member};
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let e = Ensemble::new(10, |_| Member::new(Free, [0.0], [1.0])).shard(2, 3);
    /// assert_eq!(e.members(), 6..10);
    /// ```
    pub fn shard(mut self, k: usize, n: usize) -> Self {
        self.shard = Some((k, n));
        self
    }

    /// [`shard`](Ensemble::shard), checked: the k-th of n blocks exists only for n ≥ 1 and
    /// k < n (`shard(3, 2)` and `shard(0, 0)` run no member at all), else
    /// [`SimulationError::InvalidOptions`] saying so.
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::{Ensemble, Member};
    /// # use lagrange_runtime::{Lagrangian, Scalar, SimulationError};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let e = || Ensemble::new(10, |_| Member::new(Free, [0.0], [1.0]));
    /// assert_eq!(e().try_shard(2, 3).unwrap().members(), 6..10);
    /// assert!(matches!(e().try_shard(3, 2), Err(SimulationError::InvalidOptions { .. })));
    /// assert!(e().try_shard(0, 0).is_err());
    /// ```
    pub fn try_shard(self, k: usize, n: usize) -> Result<Self, SimulationError> {
        if n == 0 || k >= n {
            return Err(SimulationError::InvalidOptions {
                message: format!(
                    "shard({k}, {n}): the members split into n ≥ 1 blocks numbered 0 to n − 1, \
                     so block {k} of {n} does not exist (it would run no member); give k < n"
                ),
            });
        }
        Ok(self.shard(k, n))
    }

    /// Shows a progress bar on standard error while the members run (with the `progress`
    /// feature, on by default; hidden where standard error is not a terminal).
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::{Ensemble, Member};
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let r = Ensemble::new(2, |_| Member::new(Free, [0.0], [1.0]))
    ///     .configure(|sim| sim.until(1.0))
    ///     .progress(true)
    ///     .run();
    /// assert_eq!(r.failures(), 0);
    /// ```
    pub fn progress(mut self, show: bool) -> Self {
        self.progress = show;
        self
    }

    /// Runs DOP853 and Taylor members several per vector (`w` ≥ 2; 0 and 1 turn lanes off): they
    /// step together, one per SIMD lane, each with its own step size (and, for DOP853,
    /// accept/reject decision), a member's lane going to the next member as soon as it ends. The
    /// Taylor method's lanes compute the series of W members in one pass of vector code
    /// ([`Lagrangian::series_in`]); each member takes its own step. The width is the instruction
    /// set's and the method's ([`simd`](Ensemble::simd): AVX2, 4 members per pass for DOP853 and 8,
    /// two vectors, for the Taylor method), whatever `w` ≥ 2 is. Without this
    /// call: lanes where the system's accelerations are generated lanes code
    /// ([`Compiled::lanes`](crate::lagrangian::Compiled::lanes): `#[lagrangian]` in symbolic
    /// mode), else none. A lane never depends on the other lanes; it equals the member's single
    /// run bit for bit on [`Simd::Exact`] (but where the vector sin and cos enter: to round-off
    /// there), to round-off on the fused paths. Members with another method (RK4,
    /// Dormand–Prince, variational), or constrained ones, run one at a time whatever `w` is.
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::{Ensemble, Member, Simd};
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # struct Osc { w: f64 }
    /// # impl Lagrangian<1> for Osc {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
    /// #         (v[0] * v[0] - q[0] * q[0] * (self.w * self.w)) * 0.5
    /// #     }
    /// # }
    /// let sweep = |w, simd| {
    ///     Ensemble::new(6, |i| Member::new(Osc { w: 1.0 + i as f64 }, [1.0], [0.0]))
    ///         .configure(|sim| sim.until(3.0))
    ///         .lanes(w)
    ///         .simd(simd)
    ///         .reduce(&["x"], |tr| tr.q[tr.q.len() - 1][0])
    /// };
    /// let one = sweep(1, Simd::Native);
    /// for (simd, bound) in [(Simd::Exact, 0.0), (Simd::Native, 1e-12)] {
    ///     for (a, b) in one.results.iter().zip(&sweep(4, simd).results) {
    ///         assert!((a.as_ref().unwrap() - b.as_ref().unwrap()).abs() <= bound);
    ///     }
    /// }
    /// ```
    pub fn lanes(mut self, w: usize) -> Self {
        self.lanes = Some(w >= 2);
        self
    }

    /// The instruction set, width and arithmetic of the lanes ([`Simd`]; default
    /// [`Simd::Native`]: the fastest measured that the CPU has, chosen when the ensemble runs, or
    /// the one the environment variable `LAGRANGE_SIMD` names). [`Simd::Exact`] makes every member its single
    /// run bit for bit (where no vector sin or cos enters); the fused paths differ from it by
    /// round-off, as a run compiled with fused multiply-adds would.
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::{Ensemble, Member, Simd};
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let r = Ensemble::new(5, |i| Member::new(Free, [0.0], [i as f64]))
    ///     .configure(|sim| sim.until(2.0))
    ///     .lanes(4)
    ///     .simd(Simd::Exact)
    ///     .reduce(&["x"], |tr| tr.q[tr.q.len() - 1][0]);
    /// assert_eq!(r.results[3].as_ref().unwrap(), &6.0);
    /// ```
    pub fn simd(mut self, simd: Simd) -> Self {
        self.simd = simd;
        self
    }

    /// The indices of the members this ensemble (or its shard) runs.
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::{Ensemble, Member};
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// assert_eq!(Ensemble::new(7, |_| Member::new(Free, [0.0], [0.0])).shard(0, 2).members(), 0..3);
    /// ```
    pub fn members(&self) -> Range<usize> {
        match self.shard {
            None => 0..self.len,
            Some((k, n)) if n > 0 && k < n => {
                let block = |k: usize| (k as u128 * self.len as u128 / n as u128) as usize;
                block(k)..block(k + 1)
            }
            Some(_) => 0..0,
        }
    }

    /// Runs every member and keeps its whole trajectory.
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::{Ensemble, Member};
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let r = Ensemble::new(2, |i| Member::new(Free, [0.0], [i as f64]))
    ///     .configure(|sim| sim.until(1.0).sample_every(0.5))
    ///     .run();
    /// assert_eq!(r.results[1].as_ref().unwrap().t, vec![0.0, 0.5, 1.0]);
    /// ```
    pub fn run(self) -> Results<Trajectory<N>> {
        self.execute(Vec::new(), |tr| tr)
    }

    /// Runs every member and keeps the row of numbers `f` computes from its trajectory, named by
    /// `columns` (for [`Results::write_csv`]).
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::{Ensemble, Member};
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let r = Ensemble::new(2, |i| Member::new(Free, [0.0], [i as f64]))
    ///     .configure(|sim| sim.until(3.0))
    ///     .reduce(&["x_end"], |tr| vec![tr.q[tr.q.len() - 1][0]]);
    /// assert_eq!(r.columns, vec!["x_end".to_string()]);
    /// assert!((r.results[1].as_ref().unwrap()[0] - 3.0).abs() < 1e-12);
    /// ```
    pub fn reduce<R: Send>(
        self,
        columns: &[&str],
        f: impl Fn(&Trajectory<N>) -> R + Sync,
    ) -> Results<R> {
        let columns = columns.iter().map(|c| c.to_string()).collect();
        self.execute(columns, move |tr| f(&tr))
    }

    fn execute<R: Send>(
        self,
        columns: Vec<String>,
        keep: impl Fn(Trajectory<N>) -> R + Sync,
    ) -> Results<R> {
        let range = self.members();
        let bar = Bar::new(self.progress, range.len());
        let simd = match self.lanes.unwrap_or(L::COMPILED.lanes) {
            true => self.simd.resolved(),
            false => Simd::Off,
        };
        let width = simd.width();
        let lanes = E::lanes().filter(|_| width >= 2);
        let out: Vec<(Params, Result<R, SimulationError>)> = if let Some(engine) = lanes {
            // Rounds of members, each shared by the threads' lanes engines from one queue.
            let threads = self
                .threads
                .unwrap_or_else(rayon::current_num_threads)
                .max(1);
            let round = ROUND_PER_THREAD.saturating_mul(threads);
            let mut out = Vec::with_capacity(range.len());
            let mut a = range.start;
            while a < range.end {
                let b = a + round.min(range.end - a);
                out.extend(self.lanes_round(a..b, threads, engine, simd, &keep, &bar));
                a = b;
            }
            out
        } else {
            let one = |i: usize| {
                let out = match isolated(i, || (self.member)(i)) {
                    Ok(m) => {
                        let r = isolated(i, || {
                            let sim = (self.configure)(Simulation::new(&m.system, m.q0, m.qdot0));
                            E::run_one(&m.system, sim).map(&keep)
                        })
                        .and_then(|r| r);
                        (m.params, r)
                    }
                    Err(e) => (Vec::new(), Err(e)),
                };
                bar.inc();
                out
            };
            self.in_threads(range.clone().collect(), one)
        };
        bar.finish();
        let (params, results) = out.into_iter().unzip();
        Results {
            index: range.collect(),
            params,
            results,
            columns,
        }
    }

    /// `f` of every item, in order, on the ensemble's threads.
    fn in_threads<I: Send, T: Send>(
        &self,
        items: Vec<I>,
        f: impl Fn(I) -> T + Sync + Send,
    ) -> Vec<T> {
        in_threads(self.threads, items, &f)
    }

    /// The members of `range` on `threads` lanes engines, one per thread, that take them from one
    /// shared queue as their lanes free; in member order.
    fn lanes_round<R: Send>(
        &self,
        range: Range<usize>,
        threads: usize,
        engine: LanesFn<L, N>,
        simd: Simd,
        keep: &(impl Fn(Trajectory<N>) -> R + Sync),
        bar: &Bar,
    ) -> Vec<(Params, Result<R, SimulationError>)> {
        let next = AtomicUsize::new(range.start);
        let one =
            |_: usize| self.lanes_share(range.clone(), threads, &next, engine, simd, keep, bar);
        let parts = self.in_threads((0..threads).collect(), one);
        let mut slots: Vec<(Params, Option<Result<R, SimulationError>>)> =
            range.clone().map(|_| (Vec::new(), None)).collect();
        for part in parts {
            for (pos, params) in part.params {
                slots[pos - range.start].0 = params;
            }
            for (pos, r) in part.results {
                slots[pos - range.start].1 = Some(r);
            }
        }
        slots
            .into_iter()
            .map(|(params, r)| {
                // Every member is taken and ended; a slot left empty would be a bug, reported in
                // the member's slot rather than as a panic.
                let r = r.unwrap_or_else(|| {
                    Err(SimulationError::InvalidOptions {
                        message: "the lanes engine did not run this member (a bug in lagrange)"
                            .to_string(),
                    })
                });
                (params, r)
            })
            .collect()
    }

    /// One thread's share of a round: its lanes engine runs members taken from `next` until the
    /// round runs dry. A panic in a member's closures is that member's
    /// [`SimulationError::MemberPanicked`]; a panic in the engine (the system's code) is that of
    /// every member then in this engine's lanes, and the engine starts again on the members left.
    #[allow(clippy::too_many_arguments)]
    fn lanes_share<R>(
        &self,
        range: Range<usize>,
        threads: usize,
        next: &AtomicUsize,
        engine: LanesFn<L, N>,
        simd: Simd,
        keep: &(impl Fn(Trajectory<N>) -> R + Sync),
        bar: &Bar,
    ) -> Share<R> {
        // Room for twice this thread's even share of the round (filled in the order taken): the
        // threads' rooms hold the round twice over, so every member finds one.
        let room = range.len().min(2 * range.len().div_ceil(threads) + 64);
        let mut members: Vec<Option<Member<L, N>>> = (0..room).map(|_| None).collect();
        let mut sims: Vec<Option<Simulation<'_, L, N>>> = (0..room).map(|_| None).collect();
        let mut queue = Taking {
            ensemble: self,
            next,
            end: range.end,
            dry: false,
            members: members.iter_mut(),
            sims: sims.iter_mut(),
            bar,
            params: Vec::new(),
            failed: Vec::new(),
        };
        let mut results: Vec<(usize, Result<R, SimulationError>)> = Vec::new();
        loop {
            let before = queue.params.len();
            let run = {
                let mut out = |pos: usize, r: Result<Trajectory<N>, SimulationError>| {
                    let r = isolated(pos, || r.map(keep)).and_then(|r| r);
                    results.push((pos, r));
                    bar.inc();
                };
                isolated(range.start, || engine(&mut queue, &mut out, simd))
            };
            let Err(e) = run else { break };
            let message = match e {
                SimulationError::MemberPanicked { message, .. } => message,
                other => other.to_string(),
            };
            let ended: std::collections::HashSet<usize> =
                results.iter().map(|&(pos, _)| pos).collect();
            for &(pos, _) in &queue.params[before..] {
                if !ended.contains(&pos) {
                    results.push((
                        pos,
                        Err(SimulationError::MemberPanicked {
                            member: pos,
                            message: format!(
                                "{message} (in the lanes engine, running this member together \
                                 with others: the system's code panicked for one of them)"
                            ),
                        }),
                    ));
                    bar.inc();
                }
            }
            if queue.params.len() == before || queue.dry {
                break;
            }
        }
        let Taking {
            mut params, failed, ..
        } = queue;
        for (pos, made, e) in failed {
            params.push((pos, made));
            results.push((pos, Err(e)));
        }
        Share { params, results }
    }
}

/// What one thread's lanes engine did in a round: the parameters of the members it made and the
/// results of those it ended (member indices).
struct Share<R> {
    params: Vec<(usize, Params)>,
    results: Vec<(usize, Result<R, SimulationError>)>,
}

/// The queue a thread's lanes engine takes members from: the next index of the round from the
/// counter all threads share, made (the member closure) and configured here, kept in this
/// thread's room for the round. A member whose closures panic is its failure, not taken. A
/// thread whose room is full takes no more (the others take the rest).
struct Taking<'e, 'm, 'p, 'c, L, F, E, const N: usize> {
    ensemble: &'e Ensemble<'c, L, F, N, E>,
    next: &'e AtomicUsize,
    end: usize,
    /// The counter passed the round's end, or the room is full (no more calls to it).
    dry: bool,
    members: core::slice::IterMut<'m, Option<Member<L, N>>>,
    sims: core::slice::IterMut<'p, Option<Simulation<'m, L, N>>>,
    bar: &'e Bar,
    /// The members given to the engine, in order, with their parameters.
    params: Vec<(usize, Params)>,
    /// Members whose closures panicked (made or configured), with what was made of them.
    failed: Vec<(usize, Params, SimulationError)>,
}

impl<'e, 'm, 'p, L, F, E, const N: usize> Iterator for Taking<'e, 'm, 'p, '_, L, F, E, N>
where
    L: Lagrangian<N>,
    F: Fn(usize) -> Member<L, N>,
{
    type Item = (usize, &'p mut Simulation<'m, L, N>);

    fn next(&mut self) -> Option<Self::Item> {
        while !self.dry {
            // The room first: an index taken is a member this thread runs.
            if self.members.len() == 0 || self.sims.len() == 0 {
                self.dry = true;
                break;
            }
            let i = self.next.fetch_add(1, Ordering::Relaxed);
            if i >= self.end {
                self.dry = true;
                break;
            }
            let (Some(room), Some(run)) = (self.members.next(), self.sims.next()) else {
                self.dry = true;
                break;
            };
            let ensemble = self.ensemble;
            let made = match isolated(i, || (ensemble.member)(i)) {
                Ok(mut m) => {
                    let params = core::mem::take(&mut m.params);
                    let m: &'m Member<L, N> = room.insert(m);
                    match isolated(i, || {
                        (ensemble.configure)(Simulation::new(&m.system, m.q0, m.qdot0))
                    }) {
                        Ok(sim) => {
                            self.params.push((i, params));
                            return Some((i, run.insert(sim)));
                        }
                        Err(e) => (params, e),
                    }
                }
                Err(e) => (Vec::new(), e),
            };
            self.failed.push((i, made.0, made.1));
            self.bar.inc();
        }
        None
    }
}

/// `f` of every item, in order, on `threads` threads (rayon's pool where `None`): `f` as a trait
/// object, so rayon's machinery is compiled once per item and result type, not once per ensemble
/// closure (one indirect call per member).
fn in_threads<I: Send, T: Send>(
    threads: Option<usize>,
    items: Vec<I>,
    f: &(dyn Fn(I) -> T + Sync),
) -> Vec<T> {
    match threads {
        Some(1) => items.into_iter().map(f).collect(),
        Some(n) => match pool(n) {
            Some(pool) => pool.install(|| items.into_par_iter().map(f).collect()),
            // No threads to be had: the calling thread runs them all.
            None => items.into_iter().map(f).collect(),
        },
        None => items.into_par_iter().map(f).collect(),
    }
}

/// The pool of `n` threads, made at the first ensemble that asks for `n` and kept for the
/// process (as rayon keeps its global pool): a pool made per run starts its threads again each
/// time, and new threads take the allocator's arenas anew — two of them now and then sharing one,
/// their members' buffers then side by side in memory, a run of two threads 10–20 % slower by
/// the luck of the draw (measured: BENCHMARKS.md, "Two threads at 1.97×"). `None` where the
/// threads cannot be started.
fn pool(n: usize) -> Option<std::sync::Arc<rayon::ThreadPool>> {
    use std::sync::{Arc, Mutex, OnceLock};
    /// The pools made so far, by their number of threads.
    type Pools = Mutex<Vec<(usize, Arc<rayon::ThreadPool>)>>;
    static POOLS: OnceLock<Pools> = OnceLock::new();
    let pools = POOLS.get_or_init(|| Mutex::new(Vec::new()));
    // A panic elsewhere while the lock was held leaves the list as it was: still usable.
    let mut pools = pools.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, p)) = pools.iter().find(|(m, _)| *m == n) {
        return Some(Arc::clone(p));
    }
    let p = Arc::new(
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .ok()?,
    );
    pools.push((n, Arc::clone(&p)));
    Some(p)
}

/// `f()`, or the member's [`SimulationError::MemberPanicked`] with the panic's message if it
/// panicked: one member's panic does not take the others' results with it.
fn isolated<T>(member: usize, f: impl FnOnce() -> T) -> Result<T, SimulationError> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).map_err(|payload| {
        let message = if let Some(s) = payload.downcast_ref::<&str>() {
            (*s).to_string()
        } else if let Some(s) = payload.downcast_ref::<String>() {
            s.clone()
        } else {
            "a panic whose payload is not a string".to_string()
        };
        SimulationError::MemberPanicked { member, message }
    })
}

impl<R> Results<R> {
    /// How many members failed.
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::{Ensemble, Member};
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// // A NaN end time is rejected before any step: every member fails, in its own slot.
    /// let r = Ensemble::new(3, |_| Member::new(Free, [0.0], [1.0])).configure(|sim| sim.until(f64::NAN)).run();
    /// assert_eq!(r.failures(), 3);
    /// ```
    pub fn failures(&self) -> usize {
        self.results.iter().filter(|r| r.is_err()).count()
    }
}

impl Results<Vec<f64>> {
    /// Writes one row per member: `member`, the parameters by name, the reduction's columns, and
    /// `error` (empty, or the member's error as a sentence, its values then empty). With `header
    /// = false` the header line is left out (for the second and later shards of a job array).
    ///
    /// There is one parameter column per distinct name, in the order the names are first met
    /// (member order, then each member's order); a member without a name has an empty cell there.
    /// A shard's columns are those of its own members, so shards concatenate when every member
    /// has the same names. Fields holding a comma, a quote or a line break are quoted as RFC 4180
    /// says (inner quotes doubled). Missing parent folders are created.
    ///
    /// # Errors
    ///
    /// [`std::io::ErrorKind::InvalidInput`], before anything is written, when a member's row has
    /// not one value per column (the reduction returned more or fewer values than `columns`
    /// names) or a member names a parameter twice; otherwise the I/O error, naming the path.
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::{Ensemble, Member};
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let r = Ensemble::new(2, |i| Member::new(Free, [0.0], [i as f64]).param("v", i as f64))
    ///     .configure(|sim| sim.until(1.0))
    ///     .reduce(&["x"], |tr| vec![tr.q[tr.q.len() - 1][0]]);
    /// let path = std::env::temp_dir().join(format!("lagrange-doc-{}.csv", std::process::id()));
    /// r.write_csv(&path, true).unwrap();
    /// let text = std::fs::read_to_string(&path).unwrap();
    /// assert_eq!(text.lines().next(), Some("member,v,x,error"));
    /// std::fs::remove_file(&path).unwrap();
    /// ```
    pub fn write_csv(&self, path: impl AsRef<Path>, header: bool) -> std::io::Result<()> {
        let path = path.as_ref();
        let text = self.csv_text(header)?;
        let named = |e: std::io::Error| {
            std::io::Error::new(e.kind(), format!("writing {}: {e}", path.display()))
        };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(named)?;
        }
        let mut w = std::io::BufWriter::new(std::fs::File::create(path).map_err(named)?);
        w.write_all(text.as_bytes()).map_err(named)?;
        w.flush().map_err(named)
    }

    /// The CSV of [`Results::write_csv`] as text, checked before any of it is written.
    fn csv_text(&self, header: bool) -> std::io::Result<String> {
        let mut out = String::new();
        for (r, row) in self.cells(header)?.iter().enumerate() {
            let last = row.len() - 1;
            let cells: Vec<String> = row
                .iter()
                .enumerate()
                .map(|(k, c)| {
                    // A data row's error is always quoted (a sentence); every other field as RFC
                    // 4180 needs.
                    if k == last && !c.is_empty() && (r > 0 || !header) {
                        format!("\"{}\"", c.replace('"', "\"\""))
                    } else {
                        csv_field(c)
                    }
                })
                .collect();
            out.push_str(&cells.join(","));
            out.push('\n');
        }
        Ok(out)
    }

    /// The table of [`Results::write_csv`], unquoted: the header (with `header`), then a row per
    /// member; checked (a parameter named twice, a reduction of the wrong length) first.
    fn cells(&self, header: bool) -> std::io::Result<Vec<Vec<String>>> {
        let invalid = |msg: String| std::io::Error::new(std::io::ErrorKind::InvalidInput, msg);
        // One column per distinct parameter name, in first-seen order.
        let mut names: Vec<&str> = Vec::new();
        for (p, i) in self.params.iter().zip(&self.index) {
            for (k, (n, _)) in p.iter().enumerate() {
                if p[..k].iter().any(|(m, _)| m == n) {
                    return Err(invalid(format!(
                        "member {i} names the parameter {n:?} twice: give each parameter of a \
                         member its own name (one CSV column per name)"
                    )));
                }
                if !names.contains(n) {
                    names.push(n);
                }
            }
        }
        for (i, r) in self.index.iter().zip(&self.results) {
            if let Ok(vals) = r
                && vals.len() != self.columns.len()
            {
                return Err(invalid(format!(
                    "member {i}: the reduction returned {} values for {} columns ({}); \
                         return one value per column named in `reduce` (no CSV written)",
                    vals.len(),
                    self.columns.len(),
                    self.columns.join(", ")
                )));
            }
        }
        let mut rows = Vec::new();
        if header {
            let mut cols = vec!["member".to_string()];
            cols.extend(names.iter().map(|n| n.to_string()));
            cols.extend(self.columns.iter().cloned());
            cols.push("error".to_string());
            rows.push(cols);
        }
        for ((i, p), r) in self.index.iter().zip(&self.params).zip(&self.results) {
            let mut row = vec![i.to_string()];
            row.extend(names.iter().map(|n| {
                p.iter()
                    .find(|(m, _)| m == n)
                    .map_or(String::new(), |(_, v)| csv_number(*v))
            }));
            match r {
                Ok(vals) => {
                    row.extend(vals.iter().map(|&v| csv_number(v)));
                    row.push(String::new());
                }
                Err(e) => {
                    row.extend(self.columns.iter().map(|_| String::new()));
                    // One line per member: a line break in the message becomes a space.
                    row.push(e.to_string().replace(['\r', '\n'], " "));
                }
            }
            rows.push(row);
        }
        Ok(rows)
    }
}

/// A number as a CSV cell that spreadsheets read and that reads back to the same f64: an
/// integer as an integer (19, not 1.9e1), other values in plain decimals where that is short
/// (2.006066806131417, 0.0005), in exponent form only outside 1e-5 … 1e16 (1e-20).
fn csv_number(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-5..1e16).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

impl core::fmt::Display for Results<Vec<f64>> {
    /// The table of [`Results::write_csv`] in aligned columns, for a terminal (a row per member;
    /// the reason in place of the values of a member that failed).
    ///
    /// ```
    /// # use lagrange_runtime::ensemble::{Ensemble, Member};
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// # struct Free;
    /// # impl Lagrangian<1> for Free {
    /// #     const COORDINATES: [&'static str; 1] = ["x"];
    /// #     const CYCLIC: [bool; 1] = [true];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// # }
    /// let r = Ensemble::new(2, |i| Member::new(Free, [0.0], [i as f64]).param("v", i as f64))
    ///     .configure(|s| s.until(1.0))
    ///     .reduce(&["v0"], |tr| vec![tr.qdot[0][0]]);
    /// assert_eq!(r.to_string(), "member  v  v0  error\n0       0  0   \n1       1  1   \n");
    /// ```
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let rows = self.cells(true).map_err(|_| core::fmt::Error)?;
        let mut width = vec![0usize; rows.first().map_or(0, Vec::len)];
        for row in &rows {
            for (w, c) in width.iter_mut().zip(row) {
                *w = (*w).max(c.chars().count());
            }
        }
        for row in &rows {
            for (k, c) in row.iter().enumerate() {
                if k + 1 == row.len() {
                    f.write_str(c)?;
                } else {
                    write!(f, "{c:<w$}  ", w = width[k])?;
                }
            }
            f.write_str("\n")?;
        }
        Ok(())
    }
}

/// A CSV field as RFC 4180 says: quoted, its quotes doubled, when it holds a comma, a quote or a
/// line break; as it is otherwise.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// The progress bar's line: members done of all, the bar, the time elapsed and the estimated time
/// left (`[00:00:12] ████████░░░░  512/1024 members, 00:00:12 left`).
#[cfg(feature = "progress")]
const PROGRESS_TEMPLATE: &str =
    "[{elapsed_precise}] {wide_bar} {pos}/{len} members, {eta_precise} left";

/// The progress bar (a no-op without the `progress` feature or when not asked for).
struct Bar {
    #[cfg(feature = "progress")]
    bar: Option<indicatif::ProgressBar>,
}

impl Bar {
    fn new(show: bool, len: usize) -> Self {
        #[cfg(feature = "progress")]
        {
            Bar {
                bar: show.then(|| {
                    indicatif::ProgressBar::new(len as u64).with_style(
                        indicatif::ProgressStyle::with_template(PROGRESS_TEMPLATE)
                            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
                    )
                }),
            }
        }
        #[cfg(not(feature = "progress"))]
        {
            let _ = (show, len);
            Bar {}
        }
    }
    fn inc(&self) {
        #[cfg(feature = "progress")]
        if let Some(b) = &self.bar {
            b.inc(1);
        }
    }
    fn finish(&self) {
        #[cfg(feature = "progress")]
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The progress line shows the time elapsed and the time left, and indicatif takes it.
    #[cfg(feature = "progress")]
    #[test]
    fn progress_shows_elapsed_and_eta() {
        assert!(PROGRESS_TEMPLATE.contains("{elapsed_precise}"));
        assert!(PROGRESS_TEMPLATE.contains("{eta_precise}"));
        assert!(indicatif::ProgressStyle::with_template(PROGRESS_TEMPLATE).is_ok());
    }

    fn results(
        params: Vec<Params>,
        results: Vec<Result<Vec<f64>, SimulationError>>,
    ) -> Results<Vec<f64>> {
        Results {
            index: (0..params.len()).collect(),
            params,
            results,
            columns: vec!["x".to_string(), "y, z".to_string()],
        }
    }

    fn temp(name: &str) -> std::path::PathBuf {
        std::env::temp_dir()
            .join(format!("lagrange-results-{}", std::process::id()))
            .join(name)
    }

    /// Members with different parameter names get a column per name in first-seen order, empty
    /// where a member lacks it; names with commas or quotes are quoted as RFC 4180 says; missing
    /// folders are created.
    #[test]
    fn csv_has_a_column_per_parameter_name_quoted() {
        let r = results(
            vec![
                vec![("a", 1.0), ("b,c", 2.0)],
                vec![("d\"q", 3.0), ("a", 4.0)],
            ],
            vec![
                Ok(vec![5.0, 6.0]),
                Err(SimulationError::InvalidOptions {
                    message: "said \"no\"\nthen".to_string(),
                }),
            ],
        );
        let path = temp("nested/deeper/sweep.csv");
        let _ = std::fs::remove_dir_all(temp(""));
        r.write_csv(&path, true).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "member,a,\"b,c\",\"d\"\"q\",x,\"y, z\",error");
        // Counts as integers, not 1e0 (spreadsheets read both, people only the first).
        assert_eq!(lines[1], "0,1,2,,5,6,");
        assert!(lines[2].starts_with("1,4,,3,,,\""), "{}", lines[2]);
        assert!(lines[2].contains("said \"\"no\"\" then"), "{}", lines[2]);
        assert_eq!(lines.len(), 3);
        // A shard without its header has the same columns.
        r.write_csv(&path, false).unwrap();
        let shard = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            shard,
            lines[1..]
                .iter()
                .map(|l| format!("{l}\n"))
                .collect::<String>()
        );
        let _ = std::fs::remove_dir_all(temp(""));
    }

    /// CSV numbers: integers as integers, others as the shortest decimal that reads back to the
    /// same f64, in exponent form only far from 1.
    #[test]
    fn csv_numbers_read_back_exactly() {
        for (v, text) in [
            (19.0, "19"),
            (-3.0, "-3"),
            (2.006066806131417, "2.006066806131417"),
            (0.000125, "0.000125"),
            (1e-20, "1e-20"),
            (6.02e23, "6.02e23"),
            (0.0, "0"),
        ] {
            assert_eq!(super::csv_number(v), text);
            assert_eq!(text.parse::<f64>().unwrap(), v);
        }
        assert_eq!(super::csv_number(f64::NAN), "NaN");
    }

    /// A reduction that returned fewer or more values than its columns is refused with
    /// InvalidInput naming the member and the counts, and nothing is written.
    #[test]
    fn csv_refuses_a_row_of_the_wrong_length() {
        for vals in [vec![1.0], vec![1.0, 2.0, 3.0]] {
            let n = vals.len();
            let r = results(vec![vec![], vec![]], vec![Ok(vec![1.0, 2.0]), Ok(vals)]);
            let path = temp(&format!("ragged{n}.csv"));
            let e = r.write_csv(&path, true).unwrap_err();
            assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput);
            let msg = e.to_string();
            assert!(
                msg.contains("member 1") && msg.contains(&format!("{n} values for 2 columns")),
                "{msg}"
            );
            assert!(!path.exists());
        }
    }

    /// A full disk (ENOSPC) names the path.
    #[cfg(target_os = "linux")]
    #[test]
    fn csv_names_the_path_on_a_full_disk() {
        let r = results(vec![vec![("a", 1.0)]], vec![Ok(vec![1.0, 2.0])]);
        let e = r.write_csv("/dev/full", true).unwrap_err();
        assert!(e.to_string().contains("/dev/full"), "{e}");
    }

    /// A member naming a parameter twice is refused (one column per name would lose a value).
    #[test]
    fn csv_refuses_a_parameter_named_twice() {
        let r = results(vec![vec![("a", 1.0), ("a", 2.0)]], vec![Ok(vec![1.0, 2.0])]);
        let e = r.write_csv(temp("twice.csv"), true).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput);
        assert!(e.to_string().contains("member 0"), "{e}");
    }
}

#[cfg(test)]
mod limits {
    use super::*;
    use crate::scalar::Scalar;

    /// x'' = −x.
    #[derive(Clone)]
    struct Osc;
    impl Lagrangian<1> for Osc {
        const COORDINATES: [&'static str; 1] = ["x"];
        const CYCLIC: [bool; 1] = [false];
        const AUTONOMOUS: bool = true;
        fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
            (v[0] * v[0] - q[0] * q[0]) * 0.5
        }
    }

    /// Lanes over several rounds (one thread: 1024 members a round) and over more threads than
    /// cores (8 threads sharing one round, each room holding 2 · 625 + 64 members: the threads
    /// that start first fill theirs and the others take the rest) lose no member and change
    /// none: every result equals its single run bit for bit on the exact lanes.
    #[test]
    fn rounds_and_full_rooms_lose_no_member() {
        let sweep = |lanes: usize, threads: usize| {
            Ensemble::new(5000, |i| Member::new(Osc, [1.0], [i as f64 * 1e-3]))
                .configure(|sim| sim.until(0.5))
                .lanes(lanes)
                .simd(Simd::Exact)
                .threads(threads)
                .reduce(&["x"], |tr| tr.q[tr.q.len() - 1][0])
        };
        let one = sweep(1, 1);
        for threads in [1, 8] {
            let r = sweep(4, threads);
            assert_eq!(r.index, (0..5000).collect::<Vec<_>>());
            assert_eq!(r.failures(), 0, "threads {threads}");
            for (i, (a, b)) in one.results.iter().zip(&r.results).enumerate() {
                let (a, b) = (a.as_ref().unwrap(), b.as_ref().unwrap());
                assert_eq!(a.to_bits(), b.to_bits(), "member {i}, threads {threads}");
            }
        }
    }

    /// `lanes(usize::MAX)` and `threads(usize::MAX)` run (they overflowed `16 · width` and
    /// `4 · threads` in a debug build); the threads are bounded by 4 × the available parallelism.
    #[test]
    fn huge_lanes_and_threads_are_clamped() {
        let e = Ensemble::new(3, |i| Member::new(Osc, [i as f64], [0.0]))
            .configure(|sim| sim.until(1.0))
            .lanes(usize::MAX)
            .threads(usize::MAX);
        let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
        assert_eq!(e.threads, Some(MAX_THREADS_PER_CORE * cores));
        assert_eq!(e.lanes, Some(true));
        let r = e.run();
        assert_eq!(r.failures(), 0);
        let e = Ensemble::new(1, |_| Member::new(Osc, [1.0], [0.0]))
            .threads(0)
            .lanes(0);
        assert_eq!((e.threads, e.lanes), (Some(1), Some(false)));
    }

    /// x'' = −x, whose Lagrangian panics once |x| passes `limit` (system code that panics).
    #[derive(Clone)]
    struct Fragile {
        limit: f64,
    }
    impl Lagrangian<1> for Fragile {
        const COORDINATES: [&'static str; 1] = ["x"];
        const CYCLIC: [bool; 1] = [false];
        const AUTONOMOUS: bool = true;
        fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
            assert!(q[0].value().abs() <= self.limit, "x left the table");
            (v[0] * v[0] - q[0] * q[0]) * 0.5
        }
    }

    /// A member whose closure, reduction or system code panics gets a MemberPanicked in its slot
    /// with the panic's message; every other member's result is kept (one panic lost them all),
    /// with lanes and without, on one thread and on two.
    #[test]
    fn a_panicking_member_loses_only_its_own_result() {
        for (lanes, threads) in [(1, 1), (1, 2), (4, 1), (4, 2)] {
            let r = Ensemble::new(40, |i| {
                assert!(i != 3, "no member 3");
                Member::new(Osc, [1.0], [i as f64]).param("v", i as f64)
            })
            .configure(|sim| sim.until(1.0))
            .lanes(lanes)
            .threads(threads)
            .reduce(&["x"], |tr| {
                let x = tr.q[tr.q.len() - 1][0];
                assert!(tr.qdot[0][0] != 7.0, "reduce saw member 7");
                vec![x]
            });
            assert_eq!(r.results.len(), 40);
            assert_eq!(r.failures(), 2, "lanes {lanes}, threads {threads}");
            for (i, res) in r.results.iter().enumerate() {
                match (i, res) {
                    (3 | 7, Err(SimulationError::MemberPanicked { member, message })) => {
                        assert_eq!(*member, i);
                        assert!(message.contains(&format!("member {i}")), "{message}");
                    }
                    (3 | 7, other) => panic!("member {i}: {other:?}"),
                    (_, Ok(x)) => {
                        assert!((x[0] - (1.0_f64.cos() + i as f64 * 1.0_f64.sin())).abs() < 1e-8)
                    }
                    (_, Err(e)) => panic!("member {i}: {e}"),
                }
            }
            assert!(r.params[3].is_empty() && r.params[7] == vec![("v", 7.0)]);
            let text = r.results[3].as_ref().unwrap_err().to_string();
            assert!(
                text.contains("ensemble member 3 panicked: no member 3"),
                "{text}"
            );
        }
        // System code that panics: without lanes only that member fails.
        let r = Ensemble::new(6, |i| {
            Member::new(Fragile { limit: 2.0 }, [1.0], [i as f64])
        })
        .configure(|sim| sim.until(1.0))
        .lanes(1)
        .threads(1)
        .run();
        assert_eq!(r.failures(), 4); // v ≥ 2 reaches |x| > 2 within t = 1
        assert!(r.results[0].is_ok() && r.results[1].is_ok());
        assert!(matches!(
            &r.results[5],
            Err(SimulationError::MemberPanicked { member: 5, message }) if message.contains("x left the table")
        ));
        // With lanes a panic in the system's code fails the members then in the engine's lanes;
        // the run returns, with every slot filled.
        let r = Ensemble::new(6, |i| {
            Member::new(Fragile { limit: 2.0 }, [1.0], [i as f64])
        })
        .configure(|sim| sim.until(1.0))
        .lanes(4)
        .threads(1)
        .run();
        assert_eq!(r.results.len(), 6);
        assert!(r.failures() >= 4);
        assert!(r.results.iter().all(|x| match x {
            Ok(_) => true,
            Err(SimulationError::MemberPanicked { message, .. }) =>
                message.contains("x left the table"),
            Err(_) => false,
        }));
        // The engine starts again after a panic: one member that panics (member 2, v = 3) fails
        // at most the members sharing its lanes (4 for DOP853), and the members taken after it
        // run to their end, on one thread and on two.
        for threads in [1, 2] {
            let r = Ensemble::new(40, |i| {
                let v = if i == 2 { 3.0 } else { 0.5 };
                Member::new(Fragile { limit: 2.0 }, [1.0], [v])
            })
            .configure(|sim| sim.until(1.0))
            .lanes(4)
            .simd(Simd::Exact)
            .threads(threads)
            .run();
            assert!(matches!(
                &r.results[2],
                Err(SimulationError::MemberPanicked { member: 2, message }) if message.contains("x left the table")
            ));
            assert!(
                (1..=4 * threads).contains(&r.failures()),
                "threads {threads}"
            );
            assert!(
                r.results[8..].iter().all(Result::is_ok),
                "threads {threads}"
            );
        }
    }
}
