//! Ensembles: member order with threads, failures isolated per member, shards covering the
//! ensemble exactly once, CSV columns named, reductions equal to the runs they reduce.

use lagrange::prelude::*;

use crate::support::systems::HeavyTop;

fn top(i: usize) -> HeavyTop {
    HeavyTop {
        i_perp: 1.0,
        i_par: 0.5 + 0.01 * i as f64,
        m: 1.0,
        g: 9.81,
        l: 0.5,
    }
}

fn ensemble(
    len: usize,
    bad: Option<usize>,
) -> Ensemble<'static, HeavyTop, impl Fn(usize) -> Member<HeavyTop, 3> + Sync, 3> {
    Ensemble::new(len, move |i| {
        // θ = 0 is the Euler-angle chart's singularity: that member fails at its first step.
        let theta = if Some(i) == bad {
            0.0
        } else {
            0.3 + 0.02 * i as f64
        };
        Member::new(top(i), [theta, 0.0, 0.0], [0.0, 1.0, 20.0])
            .param("i_par", top(i).i_par)
            .param("theta0", theta)
    })
    .configure(|sim| {
        sim.method(Method::Dop853 {
            rtol: 1e-10,
            atol: 1e-12,
        })
        .until(3.0)
    })
}

fn last_state(tr: &Trajectory<3>) -> Vec<f64> {
    let (q, v) = (tr.q[tr.q.len() - 1], tr.qdot[tr.qdot.len() - 1]);
    q.iter().chain(&v).copied().collect()
}

/// Two threads give the results of one thread, bit for bit, in member order; each equals the
/// member's own `Simulation`.
#[test]
fn threads_keep_member_order_and_results() {
    // With the default lanes (4 members per vector for this symbolic-mode system): a member's
    // result does not depend on its neighbours, so the threads' blocks do not change it.
    let one = ensemble(24, None)
        .threads(1)
        .reduce(&["th", "ph", "ps", "thd", "phd", "psd"], last_state);
    let two = ensemble(24, None)
        .threads(2)
        .reduce(&["th", "ph", "ps", "thd", "phd", "psd"], last_state);
    assert_eq!(one.index, (0..24).collect::<Vec<_>>());
    assert_eq!(two.index, one.index);
    for (a, b) in one.results.iter().zip(&two.results) {
        assert_eq!(a.as_ref().unwrap(), b.as_ref().unwrap());
    }
    // One member at a time (`lanes(1)`), each equals its `Simulation` bit for bit (lanes are
    // compared with single runs in tests/ensemble_lanes.rs).
    let one = ensemble(24, None)
        .threads(2)
        .lanes(1)
        .reduce(&["th", "ph", "ps", "thd", "phd", "psd"], last_state);
    for i in [0, 7, 23] {
        let t = top(i);
        let tr = Simulation::new(&t, [0.3 + 0.02 * i as f64, 0.0, 0.0], [0.0, 1.0, 20.0])
            .method(Method::Dop853 {
                rtol: 1e-10,
                atol: 1e-12,
            })
            .until(3.0)
            .run()
            .unwrap();
        assert_eq!(one.results[i].as_ref().unwrap(), &last_state(&tr));
        assert_eq!(
            one.params[i],
            vec![("i_par", t.i_par), ("theta0", 0.3 + 0.02 * i as f64)]
        );
    }
}

/// Radau5 members (not a lanes method: each runs on the scalar driver, whatever `lanes` says)
/// equal their own `Simulation` bit for bit, on two threads.
#[test]
fn radau5_members_equal_their_runs() {
    let radau = Method::Radau5 {
        rtol: 1e-8,
        atol: 1e-10,
    };
    let r = ensemble(6, None)
        .configure(move |sim| sim.method(radau).until(3.0))
        .threads(2)
        .reduce(&["th", "ph", "ps", "thd", "phd", "psd"], last_state);
    for i in 0..6 {
        let tr = Simulation::new(&top(i), [0.3 + 0.02 * i as f64, 0.0, 0.0], [0.0, 1.0, 20.0])
            .method(radau)
            .until(3.0)
            .run()
            .unwrap();
        assert_eq!(
            r.results[i].as_ref().unwrap(),
            &last_state(&tr),
            "member {i}"
        );
    }
}

/// A member that fails has its typed error in its slot; every other member runs to the end.
#[test]
fn a_failing_member_does_not_stop_the_others() {
    let r = ensemble(9, Some(4)).threads(2).run();
    assert_eq!(r.failures(), 1);
    for (i, res) in r.results.iter().enumerate() {
        match res {
            Ok(tr) => {
                assert_ne!(i, 4);
                assert_eq!(*tr.t.last().unwrap(), 3.0);
            }
            Err(e) => {
                assert_eq!(i, 4);
                assert!(matches!(e, SimulationError::Dynamics { .. }), "{e:?}");
            }
        }
    }
}

/// The shards k = 0..n of any ensemble are contiguous, disjoint, in order and cover it; an
/// out-of-range shard is empty; a shard's results are the full run's.
#[test]
fn shards_cover_the_ensemble_exactly_once() {
    for len in [0, 1, 2, 7, 10, 1000, 1023] {
        for n in 1..=6 {
            let mut next = 0;
            for k in 0..n {
                let m = ensemble(len, None).shard(k, n).members();
                assert_eq!(m.start, next, "len {len}, shard {k}/{n}");
                next = m.end;
            }
            assert_eq!(next, len, "len {len}, {n} shards");
        }
        assert!(ensemble(len, None).shard(3, 3).members().is_empty());
        assert!(ensemble(len, None).shard(0, 0).members().is_empty());
    }
    let full = ensemble(10, None)
        .threads(1)
        .reduce(&["th"], |tr| vec![last_state(tr)[0]]);
    let part = ensemble(10, None)
        .shard(1, 3)
        .reduce(&["th"], |tr| vec![last_state(tr)[0]]);
    assert_eq!(part.index, vec![3, 4, 5]);
    for (j, &i) in part.index.iter().enumerate() {
        assert_eq!(
            part.results[j].as_ref().unwrap(),
            full.results[i].as_ref().unwrap()
        );
    }
}

/// The CSV names its columns: member, the parameters, the reduction's values, error; a failed
/// member's row has its error and empty values; shards write without the header and concatenate.
#[test]
fn csv_columns_are_named() {
    let dir = std::env::temp_dir().join(format!("lagrange-ensemble-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("sweep.csv");
    let r = ensemble(5, Some(2)).reduce(&["theta_end"], |tr| vec![last_state(tr)[0]]);
    r.write_csv(&path, true).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "member,i_par,theta0,theta_end,error");
    assert_eq!(lines.len(), 6);
    assert!(lines[3].starts_with("2,"), "{}", lines[3]);
    let cells: Vec<&str> = lines[3].splitn(5, ',').collect();
    assert_eq!(cells[3], "");
    assert!(cells[4].contains("singular"), "{}", cells[4]);
    let ok: Vec<&str> = lines[1].split(',').collect();
    assert_eq!(ok.len(), 5);
    assert_eq!(ok[4], "");
    assert_eq!(
        ok[3].parse::<f64>().unwrap(),
        r.results[0].as_ref().unwrap()[0]
    );
    // Shards without their header concatenate to the whole file's rows.
    let mut joined = String::new();
    for k in 0..2 {
        let p = dir.join(format!("shard{k}.csv"));
        ensemble(5, Some(2))
            .shard(k, 2)
            .reduce(&["theta_end"], |tr| vec![last_state(tr)[0]])
            .write_csv(&p, k == 0)
            .unwrap();
        joined.push_str(&std::fs::read_to_string(&p).unwrap());
    }
    assert_eq!(joined, text);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `.constrained::<K>()`: every member is the constrained run of its system with the options
/// `configure` gives: its samples (q, q̇, λ) equal a `Simulation::constrained` run's bit for bit,
/// in member order, with two threads.
#[test]
fn constrained_members_equal_their_constrained_runs() {
    use crate::support::quaternion_top::QuaternionTop;
    let top = || QuaternionTop {
        i_perp: 1.0,
        i_par: 0.4,
        mgl: 1.5,
    };
    // Upright, nudged, spinning about the axis at rates 2 … 7.
    let state = |i: usize| {
        let spin = 2.0 + i as f64;
        ([1.0, 0.0, 0.0, 0.0], [0.0, 0.05, 0.0, spin / 2.0])
    };
    let method = Method::Dop853 {
        rtol: 1e-11,
        atol: 1e-13,
    };
    let r = Ensemble::new(6, |i| {
        let (q0, v0) = state(i);
        Member::new(top(), q0, v0).param("spin", 2.0 + i as f64)
    })
    .constrained::<1>()
    .configure(move |sim| sim.method(method).until(4.0).sample_every(0.5))
    .threads(2)
    .run();
    assert_eq!(r.index, (0..6).collect::<Vec<_>>());
    for (i, got) in r.results.iter().enumerate() {
        let got = got.as_ref().expect("member runs");
        let (q0, v0) = state(i);
        let system = top();
        let want = Simulation::constrained(&system, q0, v0)
            .method(method)
            .until(4.0)
            .sample_every(0.5)
            .run()
            .expect("the constrained run");
        assert_eq!(got.t, want.t, "member {i}");
        assert_eq!(got.q, want.q, "member {i}");
        assert_eq!(got.qdot, want.qdot, "member {i}");
        assert_eq!(got.lambda, want.lambda, "member {i}");
        assert_eq!(got.t.len(), 9);
        assert!(got.invariants().constraints.expect("constrained").position < 1e-12);
    }
}

/// Members from an iterator run as the same members made from their index: in the iterator's
/// order, bit for bit, with threads, lanes and shards.
#[test]
fn members_from_an_iterator_equal_members_from_an_index() {
    let by_index = ensemble(13, Some(5))
        .threads(2)
        .reduce(&["th", "ph", "ps", "thd", "phd", "psd"], last_state);
    let members: Vec<Member<HeavyTop, 3>> = (0..13)
        .map(|i| {
            let theta = if i == 5 { 0.0 } else { 0.3 + 0.02 * i as f64 };
            Member::new(top(i), [theta, 0.0, 0.0], [0.0, 1.0, 20.0])
                .param("i_par", top(i).i_par)
                .param("theta0", theta)
        })
        .collect();
    fn configure(sim: Simulation<'_, HeavyTop, 3>) -> Simulation<'_, HeavyTop, 3> {
        sim.method(Method::Dop853 {
            rtol: 1e-10,
            atol: 1e-12,
        })
        .until(3.0)
    }
    let from_iter = Ensemble::from_members(members.clone())
        .configure(configure)
        .threads(2)
        .reduce(&["th", "ph", "ps", "thd", "phd", "psd"], last_state);
    assert_eq!(from_iter.index, by_index.index);
    assert_eq!(from_iter.params, by_index.params);
    for (i, (a, b)) in from_iter.results.iter().zip(&by_index.results).enumerate() {
        match (a, b) {
            (Ok(a), Ok(b)) => assert_eq!(a, b, "member {i}"),
            (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "member {i}"),
            _ => panic!("member {i}: {a:?} vs {b:?}"),
        }
    }
    assert_eq!(from_iter.failures(), 1);
    let shard = Ensemble::from_members(members)
        .configure(configure)
        .shard(2, 3)
        .reduce(&["th"], |tr| vec![last_state(tr)[0]]);
    assert_eq!(shard.index, (8..13).collect::<Vec<_>>());
    for (j, &i) in shard.index.iter().enumerate() {
        assert_eq!(
            shard.results[j].as_ref().unwrap()[0],
            by_index.results[i].as_ref().unwrap()[0]
        );
    }
}
