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
}

mod progress;
mod results;
mod run;

use progress::Bar;
#[cfg(test)]
use progress::PROGRESS_TEMPLATE;

#[cfg(test)]
mod limits;
#[cfg(test)]
mod tests;
