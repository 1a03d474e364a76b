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
