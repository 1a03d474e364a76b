//! How an ensemble runs its members: one at a time on the threads, or shared by the threads'
//! lanes engines in rounds; each member isolated so that its panic is its own error.

use super::*;

impl<'c, L, F, E, const N: usize> Ensemble<'c, L, F, N, E>
where
    L: Lagrangian<N>,
    F: Fn(usize) -> Member<L, N> + Sync,
    E: Engine<L, N>,
{
    pub(super) fn execute<R: Send>(
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
