//! SIMD lanes: an ensemble run W members per vector gives every member's scalar run — bit for bit
//! (steps, samples, events, statistics, errors) where the lanes compute what the scalar code
//! computes (arithmetic, `sqrt`, the `f64` methods per lane: a polynomial system in symbolic mode,
//! any system in jets mode), and to round-off where the lanes' vector sin and cos (within 1 ulp of
//! the `f64` methods) enter (the heavy top); the generated `accelerations_lanes` equals
//! `accelerations` lane by lane for every kind of input.

use lagrange::ensemble::Simd;
use lagrange::lanes::Lanes;
use lagrange::prelude::*;
use lagrange::Stats;

use crate::support::systems::{HeavyTop, HeavyTopJets};
use crate::support::Kernels;

fn top(i: usize) -> HeavyTop {
    HeavyTop {
        i_perp: 1.0 + 0.013 * i as f64,
        i_par: 0.5 - 0.007 * i as f64,
        m: 1.0,
        g: 9.81,
        l: 0.4 + 0.01 * i as f64,
    }
}

/// θ0 of member i; `bad` starts at θ = 0, the chart's singularity (the member fails at once).
fn theta0(i: usize, bad: Option<usize>) -> f64 {
    if Some(i) == bad {
        0.0
    } else {
        0.3 + 0.04 * i as f64
    }
}

/// Every recorded number of a trajectory, as bits.
fn bits(tr: &Trajectory<3>) -> Vec<u64> {
    let mut out: Vec<u64> = Vec::new();
    for k in 0..tr.t.len() {
        out.push(tr.t[k].to_bits());
        out.extend(tr.q[k].iter().chain(&tr.qdot[k]).map(|x| x.to_bits()));
        out.push(tr.energy[k].to_bits());
    }
    for e in &tr.events {
        out.push(e.t.to_bits());
        out.extend(e.q.iter().map(|x| x.to_bits()));
    }
    out
}

/// A particle in an anharmonic well with a velocity-dependent coupling (a mass matrix that depends
/// on the state): polynomial, so the lanes compute exactly the scalar operations.
#[derive(Clone, Copy, Debug)]
pub struct Anharmonic {
    m: f64,
    k: f64,
    a: f64,
}

#[lagrangian]
impl Anharmonic {
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord, (z, z_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot + z_dot * z_dot)
            + 0.5 * self.a * (x * y_dot - y * x_dot).powi(2)
            - 0.5 * self.k * (x * x + y * y + z * z)
            - 0.25 * (x * x * y * y + z.powi(4))
    }
}

fn well(i: usize) -> Anharmonic {
    Anharmonic {
        m: 1.0 + 0.05 * i as f64,
        k: 2.0 - 0.03 * i as f64,
        a: 0.3 + 0.02 * i as f64,
    }
}

/// A member's recorded bits, statistics and terminating event, or its error as text.
type Outcome = Result<(Vec<u64>, Stats, Option<String>), String>;

/// The members' trajectories (or errors, as text) with `w` lanes on the exact path (every
/// operation rounded as the single run's: [`Simd::Exact`]).
fn sweep<L: Lagrangian<3> + Sync>(
    len: usize,
    w: usize,
    bad: Option<usize>,
    system: impl Fn(usize) -> L + Sync,
    configure: for<'s> fn(Sim<'s, L>) -> Sim<'s, L>,
) -> Vec<Outcome> {
    sweep_on(Simd::Exact, len, w, bad, system, configure)
}

/// [`sweep`] on the lanes path `simd`.
fn sweep_on<L: Lagrangian<3> + Sync>(
    simd: Simd,
    len: usize,
    w: usize,
    bad: Option<usize>,
    system: impl Fn(usize) -> L + Sync,
    configure: for<'s> fn(Sim<'s, L>) -> Sim<'s, L>,
) -> Vec<Outcome> {
    Ensemble::new(len, |i| {
        Member::new(
            system(i),
            [theta0(i, bad), 0.1, 0.0],
            [0.2, 1.0 + 0.1 * i as f64, 15.0],
        )
    })
    .configure(configure)
    .lanes(w)
    .simd(simd)
    .threads(1)
    .run()
    .results
    .into_iter()
    .map(|r| {
        r.map(|tr| (bits(&tr), tr.stats, tr.terminated_by.clone()))
            .map_err(|e| e.to_string())
    })
    .collect()
}

/// The options of the tests' runs (fns: closures do not infer the higher-ranked signature).
type Sim<'s, L> = Simulation<'s, L, 3>;

fn every_step(sim: Sim<'_, HeavyTop>) -> Sim<'_, HeavyTop> {
    every_step_any(sim)
}

fn every_step_any<L: Lagrangian<3>>(sim: Sim<'_, L>) -> Sim<'_, L> {
    sim.method(Method::Dop853 {
        rtol: 1e-10,
        atol: 1e-12,
    })
    .until(4.0)
}

fn samples_and_events(sim: Sim<'_, Anharmonic>) -> Sim<'_, Anharmonic> {
    sim.method(Method::Dop853 {
        rtol: 1e-9,
        atol: 1e-12,
    })
    .until(6.0)
    .sample_every(0.05)
    .event(Event::zero_crossing("y = 0.9", |_t, q: &[f64; 3], _v| q[1] - 0.9).terminal())
    .event(Event::zero_crossing("x turns", |_t, _q, v: &[f64; 3]| v[0]))
}

fn taylor_every_step<L: Lagrangian<3>>(sim: Sim<'_, L>) -> Sim<'_, L> {
    sim.method(Method::Taylor { tol: 1e-12 }).until(4.0)
}

fn taylor_samples_and_events(sim: Sim<'_, Anharmonic>) -> Sim<'_, Anharmonic> {
    samples_and_events(sim).method(Method::Taylor { tol: 1e-10 })
}

fn taylor_short<L: Lagrangian<3>>(sim: Sim<'_, L>) -> Sim<'_, L> {
    sim.method(Method::Taylor { tol: 1e-10 }).until(2.0)
}

fn short<L: Lagrangian<3>>(sim: Sim<'_, L>) -> Sim<'_, L> {
    sim.until(2.0)
}

fn budget(sim: Sim<'_, Anharmonic>) -> Sim<'_, Anharmonic> {
    sim.until(50.0).max_steps(40)
}

fn rk4(sim: Sim<'_, Anharmonic>) -> Sim<'_, Anharmonic> {
    sim.method(Method::Rk4 { dt: 0.01 }).until(1.0)
}

fn nan_end(sim: Sim<'_, Anharmonic>) -> Sim<'_, Anharmonic> {
    sim.until(f64::NAN)
}

/// Every step recorded: the generated lanes code gives the scalar run of every member, step for
/// step, with the same statistics; 13 members, so the lanes refill unevenly and the last vector
/// runs part empty.
#[test]
fn generated_lanes_equal_scalar_runs_bit_for_bit() {
    const { assert!(Anharmonic::COMPILED.lanes && !HeavyTopJets::COMPILED.lanes) };
    let scalar = sweep(13, 1, None, well, every_step_any);
    assert_eq!(sweep(13, 4, None, well, every_step_any), scalar);
    let steps = scalar[0].as_ref().map(|r| r.1.steps).unwrap_or(0);
    assert!(steps > 50, "a run of many steps: {steps}");
}

/// The heavy top's lanes take sin and cos from the vector code (within 1 ulp of the `f64`
/// methods): every member's run equals its scalar run to round-off — the same number of steps
/// (±1) and every final coordinate within 1e-12 relative after 4 s.
#[test]
fn heavy_top_lanes_equal_scalar_runs_to_round_off() {
    const { assert!(HeavyTop::COMPILED.lanes) };
    let run = |w: usize| {
        Ensemble::new(13, |i| {
            Member::new(
                top(i),
                [theta0(i, None), 0.1, 0.0],
                [0.2, 1.0 + 0.1 * i as f64, 15.0],
            )
        })
        .configure(every_step)
        .lanes(w)
        .threads(1)
        .run()
        .results
    };
    let scalar = run(1);
    let four = run(4);
    {
        let w = 4;
        let mut differ = 0;
        for (i, (a, b)) in four.iter().zip(&scalar).enumerate() {
            let (a, b) = (
                a.as_ref().expect("lanes run"),
                b.as_ref().expect("scalar run"),
            );
            assert!(
                a.stats.steps.abs_diff(b.stats.steps) <= 1,
                "member {i}: {:?} vs {:?}",
                a.stats,
                b.stats
            );
            let (ya, yb) = (a.q.last().expect("a state"), b.q.last().expect("a state"));
            for c in 0..3 {
                let tol = 1e-12 * yb[c].abs().max(1.0);
                assert!(
                    (ya[c] - yb[c]).abs() <= tol,
                    "member {i}, q{c}: {} vs {}",
                    ya[c],
                    yb[c]
                );
                differ += usize::from(ya[c] != yb[c]);
            }
        }
        assert!(differ > 0, "{w} lanes: the vector sin and cos do enter");
    }
    // A lane's value never depends on the other lanes: two threads (other blocks of members,
    // other neighbours) give the same bits.
    let bits = |r: &[Result<Trajectory<3>, SimulationError>]| -> Vec<Vec<u64>> {
        r.iter()
            .map(|x| x.as_ref().map(bits).unwrap_or_default())
            .collect()
    };
    let two_threads = Ensemble::new(13, |i| {
        Member::new(
            top(i),
            [theta0(i, None), 0.1, 0.0],
            [0.2, 1.0 + 0.1 * i as f64, 15.0],
        )
    })
    .configure(every_step)
    .lanes(4)
    .threads(2)
    .run()
    .results;
    assert_eq!(bits(&two_threads), bits(&four));
}

/// Samples between the nodes, a terminal event and a non-terminal one read each member's dense
/// output: all equal the scalar runs.
#[test]
fn samples_and_events_in_lanes_equal_scalar_runs() {
    let cfg = samples_and_events;
    let scalar = sweep(11, 1, None, well, cfg);
    let ended = scalar
        .iter()
        .filter(|r| r.as_ref().is_ok_and(|r| r.2.is_some()))
        .count();
    assert!(
        ended > 0 && ended < 11,
        "some members end at the terminal event: {ended}"
    );
    assert_eq!(sweep(11, 4, None, well, cfg), scalar);
}

fn end_only<L: Lagrangian<3>>(sim: Sim<'_, L>) -> Sim<'_, L> {
    every_step_any(sim).sample_every(4.0)
}

fn taylor_end_only<L: Lagrangian<3>>(sim: Sim<'_, L>) -> Sim<'_, L> {
    taylor_every_step(sim).sample_every(4.0)
}

/// Samples at the start and the end only (the last node): the lanes keep no interpolant
/// (nothing falls inside a step) and still give every member's scalar run.
#[test]
fn end_only_sampling_in_lanes_equals_scalar_runs() {
    let scalar = sweep(13, 1, None, well, end_only);
    assert!(scalar
        .iter()
        .all(|r| r.as_ref().is_ok_and(|r| r.0.len() == 2 * 8)));
    assert_eq!(sweep(13, 4, None, well, end_only), scalar);
    let scalar = sweep(13, 1, None, well, taylor_end_only);
    assert_eq!(sweep(13, 4, None, well, taylor_end_only), scalar);
}

/// The jets mode has no generated lanes code: the default calls `accelerations` lane by lane, and
/// the runs are again the scalar ones.
#[test]
fn default_lanes_of_the_jets_mode_equal_scalar_runs() {
    let jets = |i: usize| top(i).jets();
    let cfg = short::<HeavyTopJets>;
    assert_eq!(sweep(6, 4, None, jets, cfg), sweep(6, 1, None, jets, cfg));
}

/// A member that fails (θ0 = 0, a singular mass matrix) reports the scalar run's error in its
/// slot; the members sharing its vector are unaffected (the jets twin: bit for bit).
#[test]
fn a_failing_lane_reports_the_scalar_error_and_spares_the_others() {
    let jets = |i: usize| top(i).jets();
    let cfg = short::<HeavyTopJets>;
    let scalar = sweep(9, 1, Some(5), jets, cfg);
    assert!(scalar[5].is_err(), "{:?}", scalar[5]);
    assert_eq!(sweep(9, 4, Some(5), jets, cfg), scalar);
    // The generated lanes: the same error where the pivot test fails in one lane.
    let scalar = sweep(9, 1, Some(5), top, short::<HeavyTop>);
    let lanes = sweep(9, 4, Some(5), top, short::<HeavyTop>);
    assert_eq!(lanes[5], scalar[5]);
    assert!(lanes.iter().filter(|r| r.is_ok()).count() == 8);
}

/// The Taylor method in lanes: the series of four members per vector, each member's step its
/// own — the scalar runs bit for bit (13 members, every step recorded), with samples between the
/// nodes and events from each member's series; a member whose M₀ is indefinite (m < 0: the
/// scalar series pivots) takes the scalar series in its lane and still equals its single run, up
/// to the same error where it blows up.
#[test]
fn taylor_lanes_equal_scalar_runs_bit_for_bit() {
    let negative = |i: usize| Anharmonic {
        m: if i == 6 { -1.0 } else { well(i).m },
        ..well(i)
    };
    let scalar = sweep(13, 1, None, negative, taylor_every_step);
    // The negative mass makes z blow up (z̈ = k z + z³) after many pivoted steps.
    assert!(
        scalar[6].as_ref().is_err_and(|e| e.contains("underflow")),
        "{:?}",
        scalar[6]
    );
    assert_eq!(scalar.iter().filter(|r| r.is_ok()).count(), 12);
    assert_eq!(sweep(13, 4, None, negative, taylor_every_step), scalar);
    let steps = scalar[0].as_ref().map(|r| r.1.steps).unwrap_or(0);
    assert!(steps > 20, "a run of many steps: {steps}");
    let cfg = taylor_samples_and_events;
    let scalar = sweep(11, 1, None, well, cfg);
    let ended = scalar
        .iter()
        .filter(|r| r.as_ref().is_ok_and(|r| r.2.is_some()))
        .count();
    assert!(
        ended > 0 && ended < 11,
        "some end at the terminal event: {ended}"
    );
    assert_eq!(sweep(11, 4, None, well, cfg), scalar);
}

/// The heavy top's Taylor series in lanes use the vector sin and cos: every member's run equals
/// its single run to round-off (steps ±1, final coordinates within 1e-11 relative after 4 s); a
/// member starting at θ = 0 (M₀ singular) gets the scalar run's error and its neighbours finish.
#[test]
fn taylor_lanes_of_the_heavy_top_equal_scalar_runs_to_round_off() {
    let scalar = sweep(13, 1, None, top, taylor_every_step);
    let lanes = sweep(13, 4, None, top, taylor_every_step);
    let mut differ = 0;
    for (i, (a, b)) in lanes.iter().zip(&scalar).enumerate() {
        let (a, b) = (
            a.as_ref().expect("lanes run"),
            b.as_ref().expect("scalar run"),
        );
        assert!(
            a.1.steps.abs_diff(b.1.steps) <= 1,
            "member {i}: {:?} vs {:?}",
            a.1,
            b.1
        );
        // The last state: its bits are the last record's t, q and q̇.
        let last = |r: &[u64]| -> Vec<f64> {
            r[r.len() - 8..r.len() - 1]
                .iter()
                .map(|&x| f64::from_bits(x))
                .collect()
        };
        let (ya, yb) = (last(&a.0), last(&b.0));
        for c in 0..7 {
            let tol = 1e-11 * yb[c].abs().max(1.0);
            assert!(
                (ya[c] - yb[c]).abs() <= tol,
                "member {i}, {c}: {} vs {}",
                ya[c],
                yb[c]
            );
            differ += usize::from(ya[c] != yb[c]);
        }
    }
    assert!(differ > 0, "the vector sin and cos do enter");
    let scalar = sweep(9, 1, Some(5), top, taylor_short::<HeavyTop>);
    let lanes = sweep(9, 4, Some(5), top, taylor_short::<HeavyTop>);
    assert!(scalar[5].is_err(), "{:?}", scalar[5]);
    assert_eq!(lanes[5], scalar[5]);
    assert_eq!(lanes.iter().filter(|r| r.is_ok()).count(), 8);
    // The jets twin has no series: its Taylor runs fail alike, in lanes or not.
    let jets = |i: usize| top(i).jets();
    let cfg = taylor_short::<HeavyTopJets>;
    let r = sweep(5, 4, None, jets, cfg);
    assert!(r.iter().all(Result::is_err), "{r:?}");
    assert_eq!(r, sweep(5, 1, None, jets, cfg));
}

/// A step budget, a non-DOP853 method and bad options behave in lanes as in scalar runs.
#[test]
fn limits_other_methods_and_bad_options_in_lanes() {
    let r = sweep(5, 4, None, well, budget);
    assert!(
        r.iter()
            .all(|x| x.as_ref().is_err_and(|e| e.contains("40"))),
        "{r:?}"
    );
    assert_eq!(r, sweep(5, 1, None, well, budget));
    assert_eq!(sweep(5, 4, None, well, rk4), sweep(5, 1, None, well, rk4));
    let r = sweep(5, 4, None, well, nan_end);
    assert!(r.iter().all(Result::is_err));
    assert_eq!(r, sweep(5, 1, None, well, nan_end));
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Spring {
    Soft,
    Hard,
}

/// A charged particle in a magnetic field (a `Vector3` parameter), in a spring whose stiffness a
/// constant `match` picks, driven in time, with drag: every kind of input the lanes code reads.
#[derive(Clone, Copy, Debug)]
pub struct Mixed {
    m: f64,
    k: [f64; 2],
    spring: Spring,
    b: Vector3<f64>,
    drive: f64,
    c: f64,
    /// An exponent of the potential (per member: a lane's own power).
    p: f64,
}

#[lagrangian]
impl Mixed {
    fn lagrangian(&self, (r, r_dot): Coord3, t: Time) -> Scalar {
        let k = match self.spring {
            Spring::Soft => self.k[0],
            Spring::Hard => self.k[1],
        };
        let a = self.b.cross(&r) / 2.0;
        0.5 * self.m * (1.0 + 0.1 * r.z.cos()) * r_dot.norm_squared() + r_dot.dot(&a)
            - 0.5 * k * r.norm_squared()
            - (r.x * r.x + 1.0).sqrt() * (self.drive * t).sin()
            + 0.01 * r.y.atan2(2.0 + r.x) * r.z.exp()
            - 0.1 * (r.y * r.y + 1.0).powf(self.p)
    }
    fn dissipation(&self, (_, r_dot): Coord3) -> Scalar {
        0.5 * self.c * r_dot.norm_squared()
    }
}

/// Member i of the `Mixed` tests: both `match` arms alternate, every parameter varies.
fn member(i: usize) -> Mixed {
    Mixed {
        m: 1.0 + 0.3 * i as f64,
        k: [0.5 + 0.1 * i as f64, 3.0],
        spring: if i.is_multiple_of(2) {
            Spring::Soft
        } else {
            Spring::Hard
        },
        b: Vector3::new(0.1 * i as f64, -0.2, 1.5),
        drive: 1.3,
        c: 0.05 * i as f64,
        p: 0.5 + 0.25 * i as f64,
    }
}

/// (q, q̇) of the four lanes of the `Mixed` tests, and their times.
const MIXED_STATE: [[Lanes<4>; 3]; 2] = [
    [
        Lanes([0.3, -0.2, 0.5, 1.1]),
        Lanes([0.1, 0.7, -0.4, 0.2]),
        Lanes([0.2, 0.0, 1.0, -0.6]),
    ],
    [
        Lanes([1.0, -0.5, 0.25, 0.0]),
        Lanes([0.3, 0.2, -1.0, 0.4]),
        Lanes([-0.7, 0.1, 0.6, 2.0]),
    ],
];
const MIXED_T: Lanes<4> = Lanes([0.0, 0.5, 1.7, 3.2]);

/// The generated lanes code's q̈ (as the ensemble engine takes it) equals `accelerations` of each lane's member to
/// round-off (1e-14 relative: its cos and sin are the vector ones), with members of both `match`
/// arms in one vector; a lane whose mass matrix is singular (m = 0) is NaN and the other lanes
/// keep their values.
#[test]
fn generated_lanes_equal_scalar_accelerations_for_every_input_kind() {
    const { assert!(Mixed::COMPILED.lanes) };
    let check = |ms: [Mixed; 4]| {
        let refs = [&ms[0], &ms[1], &ms[2], &ms[3]];
        let ([q, v], t) = (MIXED_STATE, MIXED_T);
        let a = Mixed::accelerations_lanes(&refs, &q, &v, t);
        for (l, m) in ms.iter().enumerate() {
            let ql = [q[0].0[l], q[1].0[l], q[2].0[l]];
            let vl = [v[0].0[l], v[1].0[l], v[2].0[l]];
            match m.accelerations(&ql, &vl, t.0[l]) {
                Ok(s) => {
                    for i in 0..3 {
                        let tol = 1e-14 * s[i].abs().max(1.0);
                        assert!(
                            (a[i].0[l] - s[i]).abs() <= tol,
                            "lane {l}, q̈{i}: {} vs {}",
                            a[i].0[l],
                            s[i]
                        );
                    }
                }
                Err(_) => assert!(a.iter().all(|x| x.0[l].is_nan()), "lane {l} fails: NaN"),
            }
        }
    };
    check(std::array::from_fn(member));
    let mut singular: [Mixed; 4] = std::array::from_fn(|i| member(i + 4));
    singular[2].m = 0.0;
    check(singular);
}

/// The generated series in lanes equals the width-1 series of each lane's member, every
/// coefficient to order 12 within 1e-12 of its size (its sin and cos are the vector ones), for
/// every kind of input (the `Vector3` field, both `match` arms in one vector, time, dissipation,
/// sqrt, atan2, exp, a power whose exponent differs from lane to lane); a lane whose M₀ is singular (m = 0) is left out of the mask and the others
/// keep their values.
#[test]
fn generated_taylor_lanes_equal_scalar_series_for_every_input_kind() {
    use lagrange::taylor::{SeriesBuf, TaylorBuf};
    let check = |ms: [Mixed; 4], left_out: Option<usize>| {
        let refs = [&ms[0], &ms[1], &ms[2], &ms[3]];
        let (y0, t) = (MIXED_STATE, MIXED_T);
        let mut series = vec![y0; 13];
        let ok = Mixed::taylor_series_lanes(&refs, t, &mut series, &mut SeriesBuf::new())
            .expect("generated lanes series");
        for (l, m) in ms.iter().enumerate() {
            if Some(l) == left_out {
                assert!(!ok.0[l], "lane {l} is left out");
                continue;
            }
            assert!(ok.0[l], "lane {l}");
            let mut one = vec![[[0.0; 3]; 2]; 13];
            one[0] = [0, 1].map(|c| [0, 1, 2].map(|i| y0[c][i].0[l]));
            m.taylor_series(t.0[l], &mut one, &mut TaylorBuf::new())
                .expect("generated series")
                .expect("regular M₀");
            for k in 0..13 {
                for c in 0..2 {
                    for i in 0..3 {
                        let (a, b) = (series[k][c][i].0[l], one[k][c][i]);
                        assert!(
                            (a - b).abs() <= 1e-12 * b.abs().max(1.0),
                            "lane {l}, order {k}, ({c}, {i}): {a} vs {b}"
                        );
                    }
                }
            }
        }
    };
    check(std::array::from_fn(member), None);
    let mut singular: [Mixed; 4] = std::array::from_fn(|i| member(i + 4));
    singular[2].m = 0.0;
    check(singular, Some(2));
}

/// The fused paths this machine has (AVX2 with FMA, 4 lanes).
fn fused_paths() -> Vec<Simd> {
    let paths: Vec<Simd> = [Simd::Avx2Fma]
        .into_iter()
        .filter(|s| s.resolved() == *s)
        .collect();
    eprintln!("fused lanes paths on this machine: {paths:?}");
    paths
}

/// The last record's t, q and q̇ of an outcome.
fn last_state(r: &(Vec<u64>, Stats, Option<String>)) -> Vec<f64> {
    let b = &r.0;
    b[b.len() - 8..b.len() - 1]
        .iter()
        .map(|&x| f64::from_bits(x))
        .collect()
}

/// `fused` against `exact`, member by member: the same failures with the same messages; for the
/// others the same number of steps (±1) and the last state within `rel` relative (absolute below
/// 1). The number of members whose last state differs at all.
fn to_round_off(fused: &[Outcome], exact: &[Outcome], rel: f64, what: &str) -> usize {
    assert_eq!(fused.len(), exact.len());
    let mut differ = 0;
    for (i, (a, b)) in fused.iter().zip(exact).enumerate() {
        let (a, b) = match (a, b) {
            (Ok(a), Ok(b)) => (a, b),
            (Err(a), Err(b)) => {
                assert_eq!(a, b, "{what}, member {i}");
                continue;
            }
            _ => panic!("{what}, member {i}: {a:?} vs {b:?}"),
        };
        assert!(
            a.1.steps.abs_diff(b.1.steps) <= 1,
            "{what}, member {i}: {:?} vs {:?}",
            a.1,
            b.1
        );
        let (ya, yb) = (last_state(a), last_state(b));
        let worst = (0..7)
            .map(|c| (ya[c] - yb[c]).abs() / yb[c].abs().max(1.0))
            .fold(0.0_f64, f64::max);
        eprintln!(
            "{what}, member {i}: steps {} vs {}, last state {worst:.1e} relative",
            a.1.steps, b.1.steps
        );
        for c in 0..7 {
            let tol = rel * yb[c].abs().max(1.0);
            assert!(
                (ya[c] - yb[c]).abs() <= tol,
                "{what}, member {i}, {c}: {} vs {}",
                ya[c],
                yb[c]
            );
        }
        differ += usize::from(ya != yb);
    }
    differ
}

/// Every fused path this machine has gives every member the run of the exact lanes to round-off
/// (DOP853 and Taylor, the polynomial well and the heavy top, 4 s): steps ±1, the last state
/// within 1e-12 relative (DOP853) and 1e-11 (Taylor, as for the vector sin and cos); a failing
/// member reports the same error and spares its neighbours; a lane does not depend on the
/// others (two threads, other neighbours, the same bits).
#[test]
fn fused_paths_equal_the_exact_lanes_to_round_off() {
    for simd in fused_paths() {
        let w = simd.width();
        let what = format!("{simd:?} ({w} lanes)");
        // 13 members on `simd` against the exact lanes, to `rel` (see `to_round_off`).
        fn against_exact<L: Lagrangian<3> + Sync>(
            simd: Simd,
            system: impl Fn(usize) -> L + Sync + Copy,
            cfg: for<'s> fn(Sim<'s, L>) -> Sim<'s, L>,
            rel: f64,
            what: &str,
        ) -> usize {
            let fused = sweep_on(simd, 13, simd.width(), None, system, cfg);
            to_round_off(&fused, &sweep(13, 4, None, system, cfg), rel, what)
        }
        let differ = against_exact(simd, well, every_step_any, 1e-12, &what)
            + against_exact(simd, well, taylor_every_step, 1e-11, &what)
            + against_exact(simd, top, every_step, 1e-12, &what)
            + against_exact(simd, top, taylor_every_step, 1e-11, &what);
        assert!(
            differ > 0,
            "{what}: the fused multiply-adds do change the rounding"
        );
        // A failing member (θ0 = 0: M singular) in the middle of a vector.
        let fused = sweep_on(simd, 9, w, Some(5), top, short::<HeavyTop>);
        assert_eq!(fused[5], sweep(9, 1, Some(5), top, short::<HeavyTop>)[5]);
        assert_eq!(fused.iter().filter(|r| r.is_ok()).count(), 8, "{what}");
        // Lane independence: the same members with other neighbours (two threads).
        let two = Ensemble::new(13, |i| {
            Member::new(
                well(i),
                [theta0(i, None), 0.1, 0.0],
                [0.2, 1.0 + 0.1 * i as f64, 15.0],
            )
        })
        .configure(every_step_any)
        .simd(simd)
        .threads(2)
        .run()
        .results;
        let two: Vec<Vec<u64>> = two
            .iter()
            .map(|r| r.as_ref().map(bits).unwrap_or_default())
            .collect();
        let one: Vec<Vec<u64>> = sweep_on(simd, 13, w, None, well, every_step_any)
            .into_iter()
            .map(|r| r.map(|r| r.0).unwrap_or_default())
            .collect();
        assert_eq!(two, one, "{what}");
    }
}
