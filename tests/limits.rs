//! Runs at the limits of what they take, each against its closed form: contacts that touch at
//! the start (approaching, at rest, a hair above the floor) and that start late on a moving
//! floor; parameter sensitivities and input matrices of parameters far below 1; Lyapunov spectra
//! of decoupled saddles (sorted, the k largest) and of fast ones (λ = 20 and 100 against the
//! renormalization interval); a reset that leaves the state just off its surface; and hit times
//! that shrink as a power law, which are not a Zeno accumulation.

use lagrange::prelude::*;
use lagrange::sensitivity::Lyapunov;
use lagrange_examples::contact_systems::Ball;

const G: f64 = 9.81;

fn tight() -> Method {
    Method::Dop853 {
        rtol: 1e-12,
        atol: 1e-14,
    }
}

/// A ball that touches the floor at t0 moving into it (y = 0, ẏ = −2) bounces at t0: the jump
/// is the first of the run, ẏ⁺ = −e ẏ⁻ = 1, and the next impact comes 2ẏ⁺/g later; the ball
/// never goes below the floor.
#[test]
fn a_contact_touching_and_approaching_at_the_start_is_an_impact_there() {
    let ball = Ball {
        m: 1.0,
        g: G,
        e: 0.5,
    };
    let tr = Simulation::contacts(&ball, [0.0, 0.0], [0.3, -2.0])
        .method(tight())
        .until(0.3)
        .sample_every(0.001)
        .run()
        .unwrap();
    assert!(tr.jumps.len() >= 2, "{} jumps", tr.jumps.len());
    let first = &tr.jumps[0];
    assert_eq!(first.t, 0.0);
    assert!((first.after.1[1] - 1.0).abs() < 1e-12, "{:?}", first.after);
    assert!((first.energy_change + 0.5 * (4.0 - 1.0)).abs() < 1e-12);
    assert!((tr.jumps[1].t - 2.0 / G).abs() < 1e-9, "{}", tr.jumps[1].t);
    assert_eq!(tr.qdot[0][1], 1.0, "the run starts after the impact");
    let lowest = tr.q.iter().fold(f64::INFINITY, |m, q| m.min(q[1]));
    assert!(lowest > -1e-12, "below the floor: {lowest:e}");
}

/// A ball at rest a hair above the floor (gap 1e-16 … 1e-10) ends on the floor: the run rests
/// there with λ = m g (no "off the constraints" refusal, no advice to project). Above the
/// round-off of the gap it first falls and bounces (1e-10 m: impacts from 4.5 µs, accumulating
/// by 14 µs), which ends in the same resting contact.
#[test]
fn a_contact_within_round_off_of_touching_rests() {
    let ball = Ball {
        m: 2.0,
        g: G,
        e: 0.5,
    };
    for gap in [1e-16, 1e-13, 1e-10] {
        let tr = Simulation::contacts(&ball, [0.0, gap], [0.0, 0.0])
            .until(1.0)
            .run()
            .unwrap_or_else(|e| panic!("gap {gap:e}: {e}"));
        let l = tr.lambda.last().unwrap()[0];
        assert!((l - 2.0 * G).abs() < 1e-9, "gap {gap:e}: λ = {l}");
        assert!(tr.q.last().unwrap()[1].abs() < 1e-9);
    }
}

/// A floor rising at u = 0.5: y_floor = u t, written with the time the contact is read at.
struct RisingFloor;

impl Lagrangian<1> for RisingFloor {
    const COORDINATES: [&'static str; 1] = ["y"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
        v[0] * v[0] * 0.5 - q[0] * G
    }
}

impl Unilateral<1, 1> for RisingFloor {
    fn contacts<S: Scalar>(&self, q: &[S; 1], t: S) -> [Contact<S>; 1] {
        [Contact::gap(q[0] - t * 0.5).named("floor")]
    }
}

/// `.start_time(t0)` sets the contacts up at t0: a ball riding the rising floor from t0 = 2
/// (y = 1, ẏ = 0.5) rides it (y = t/2, λ = m g), and a ball below the floor at t0 = 2 (y = 0.5,
/// above where the floor was at t = 0) is refused as penetrating.
#[test]
fn contacts_are_set_up_at_the_start_time() {
    let tr = Simulation::contacts(&RisingFloor, [1.0], [0.5])
        .method(tight())
        .start_time(2.0)
        .until(4.0)
        .sample_every(0.5)
        .run()
        .unwrap();
    for (t, q) in tr.t.iter().zip(&tr.q) {
        assert!((q[0] - 0.5 * t).abs() < 1e-9, "t = {t}: y = {}", q[0]);
    }
    assert!((tr.lambda.last().unwrap()[0] - G).abs() < 1e-9);
    let err = Simulation::contacts(&RisingFloor, [0.5], [0.5])
        .start_time(2.0)
        .until(3.0)
        .run()
        .unwrap_err();
    assert!(err.to_string().contains("penetrates"), "{err}");
}

/// A spring of stiffness k and a small mass m from x₀ = 1 at rest: x = cos(ωt), ω = √(k/m),
/// ∂x/∂m = x₀ sin(ωt) ω t / (2m).
struct SmallMass {
    m: f64,
    k: f64,
}

impl Lagrangian<1> for SmallMass {
    const COORDINATES: [&'static str; 1] = ["x"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
        (v[0] * v[0] * self.m - q[0] * q[0] * self.k) * 0.5
    }
}

/// ∂x/∂m for masses from 1e-3 to 1e-9 (the difference step stays within the mass's own scale:
/// with a floor of 1 the stencil evaluated a negative mass, 3× off at 1e-3, the wrong sign at
/// 1e-6), against the closed form to 1e-8.
#[test]
fn parameter_sensitivities_of_small_masses() {
    for m in [1e-3, 1e-6, 1e-9] {
        let sys = SmallMass { m, k: m };
        let t = 1.0;
        let run = Simulation::new(&sys, [1.0], [0.0])
            .method(tight())
            .until(t)
            .sensitivity()
            .parameter("m", m, |m| SmallMass { m, k: sys.k })
            .run()
            .unwrap();
        let got = run.dparams.last().unwrap()[(0, 0)];
        let want = t.sin() * t / (2.0 * m);
        assert!(
            (got - want).abs() <= 1e-8 * want.abs(),
            "m = {m:e}: ∂x/∂m = {got} against {want}"
        );
    }
}

/// A force Q = 1/u: B = ∂Q/∂u = −1/u², at u from 1e-4 to 1e4.
struct Inverse {
    u: f64,
}

impl Lagrangian<1> for Inverse {
    const COORDINATES: [&'static str; 1] = ["x"];
    const CYCLIC: [bool; 1] = [true];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S {
        v[0] * v[0] * 0.5
    }
    fn generalized_forces<S: Scalar>(&self, _q: &[S; 1], _v: &[S; 1], _t: S) -> [S; 1] {
        [S::constant(1.0 / self.u)]
    }
}

#[test]
fn input_matrix_of_small_and_large_parameters() {
    use lagrange::linearize::input_matrix;
    for u in [1e-4, 1e-2, 1.0, 1e4] {
        let b = input_matrix(
            |p: &[f64; 1]| Inverse { u: p[0] },
            &[u],
            &[0.0],
            &[0.0],
            0.0,
        )
        .unwrap()[(0, 0)];
        let want = -1.0 / (u * u);
        assert!(
            (b - want).abs() <= 1e-9 * want.abs(),
            "u = {u:e}: B = {b} against {want}"
        );
    }
}

/// Two decoupled saddles, ẍ = a² x and ÿ = b² y: exponents ±a, ±b.
struct Saddles {
    a: f64,
    b: f64,
}

impl Lagrangian<2> for Saddles {
    const COORDINATES: [&'static str; 2] = ["x", "y"];
    const CYCLIC: [bool; 2] = [false, false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
        (v[0] * v[0]
            + v[1] * v[1]
            + q[0] * q[0] * (self.a * self.a)
            + q[1] * q[1] * (self.b * self.b))
            * 0.5
    }
}

/// Exponents 2, 1, −1, −2 come out sorted (over 300 time units: a finite-time exponent is off by
/// about ln(the start's projection)/T), and `directions(1)` and `directions(2)` are the largest
/// ones (the carried directions start in general position: unit vectors stay in the
/// invariant planes of decoupled saddles, and gave [1, 2, −1, −2] with `directions(1)` = 1).
#[test]
fn lyapunov_spectra_are_sorted_and_directions_are_the_largest() {
    let sys = Saddles { a: 1.0, b: 2.0 };
    let spectrum = |k: usize| {
        Lyapunov::new(&sys, [0.0, 0.0], [0.0, 0.0])
            .duration(300.0)
            .directions(k)
            .compute()
            .unwrap()
            .exponents
    };
    let all = spectrum(4);
    for (got, want) in all.iter().zip([2.0, 1.0, -1.0, -2.0]) {
        assert!((got - want).abs() < 2e-2, "{all:?}");
    }
    assert!(all.windows(2).all(|w| w[0] >= w[1]), "{all:?}");
    let one = spectrum(1);
    assert!((one[0] - 2.0).abs() < 2e-2, "{one:?}");
    let two = spectrum(2);
    assert!(
        (two[0] - 2.0).abs() < 2e-2 && (two[1] - 1.0).abs() < 2e-2,
        "{two:?}"
    );
}

/// Saddles growing by e²⁰ and e¹⁰⁰ per renormalization interval of 1: the directions are
/// re-orthonormalized as often as they need, so the spectrum is ±λ and sums to 0 (Liouville;
/// before: 4.07 at λ = 20, [100.4, 63.9] at 100).
#[test]
fn lyapunov_spectra_of_fast_saddles() {
    for a in [20.0, 100.0] {
        let sys = Saddles { a, b: 0.5 };
        let s = Lyapunov::new(&sys, [0.0, 0.0], [0.0, 0.0])
            .duration(200.0)
            .compute()
            .unwrap();
        let e = &s.exponents;
        assert!((e[0] - a).abs() < 2e-3 * a, "{e:?}");
        assert!((e[3] + a).abs() < 2e-3 * a, "{e:?}");
        assert!(
            (e[1] - 0.5).abs() < 0.05 && (e[2] + 0.5).abs() < 0.05,
            "{e:?}"
        );
        assert!(s.sum().abs() < 1e-6 * a, "Σλ = {} for {e:?}", s.sum());
    }
}

/// A free particle on a line.
struct Drift;

impl Lagrangian<1> for Drift {
    const COORDINATES: [&'static str; 1] = ["x"];
    const CYCLIC: [bool; 1] = [true];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S {
        v[0] * v[0] * 0.5
    }
}

/// A particle moving in at ẋ = −1 reset to x = 1e-6 each time it crosses x = 0 (its velocity
/// kept): it crosses again 1e-6 later, so over 10.5e-6 it jumps 10 times (the first crossing at
/// t = 1e-6 from x₀ = 1e-6, then every 1e-6). Before, the fired event's value was set to 0
/// after the jump and the next crossing, from 1e-6, was missed.
#[test]
fn a_reset_just_off_its_surface_crosses_again() {
    let tr = Simulation::new(&Drift, [1e-6], [-1.0])
        .event(
            Event::zero_crossing("wall", |_t, q: &[f64; 1], _v| q[0])
                .falling()
                .reset(|_t, _q, v| ([1e-6], *v)),
        )
        .until(10.5e-6)
        .run()
        .unwrap();
    assert_eq!(
        tr.jumps.len(),
        10,
        "{:?}",
        tr.jumps.iter().map(|j| j.t).collect::<Vec<_>>()
    );
    for (k, j) in tr.jumps.iter().enumerate() {
        assert!(
            (j.t - (k + 1) as f64 * 1e-6).abs() < 1e-12,
            "jump {k} at {}",
            j.t
        );
    }
    assert!(tr.zeno.is_none());
}

/// A ball dropped from y = 1 and lifted by 0.1 each time it falls through y = 0.5: the hits
/// come ever faster as √k, never accumulating, so the run goes to its end (before: "Zeno,
/// accumulating at t = 1.96", stopped at t = 0.99).
#[test]
fn hits_shrinking_as_a_power_law_are_not_zeno() {
    struct Fall;
    impl Lagrangian<1> for Fall {
        const COORDINATES: [&'static str; 1] = ["y"];
        const CYCLIC: [bool; 1] = [false];
        const AUTONOMOUS: bool = true;
        fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
            v[0] * v[0] * 0.5 - q[0] * G
        }
    }
    let tr = Simulation::new(&Fall, [1.0], [0.0])
        .method(tight())
        .event(
            Event::zero_crossing("line", |_t, q: &[f64; 1], _v| q[0] - 0.5)
                .falling()
                .reset(|_t, q, v| ([q[0] + 0.1], *v)),
        )
        .until(1.5)
        .run()
        .unwrap();
    assert!(tr.zeno.is_none(), "{:?}", tr.zeno);
    assert_eq!(*tr.t.last().unwrap(), 1.5);
    // The hit times follow the closed form: from speed v, the next hit after (√(v² + 2g·0.1) − v)/g.
    let mut t = (2.0 * 0.5 / G).sqrt();
    let mut v = G * t;
    for j in &tr.jumps {
        assert!((j.t - t).abs() < 1e-9, "{} against {t}", j.t);
        let d = ((v * v + 2.0 * G * 0.1).sqrt() - v) / G;
        t += d;
        v += G * d;
    }
    assert!(tr.jumps.len() > 60, "{} hits", tr.jumps.len());
}

/// Newton's cradle of three unit point masses on a line, gaps x₂ − x₁ and x₃ − x₂, elastic.
struct Cradle;

impl Lagrangian<3> for Cradle {
    const COORDINATES: [&'static str; 3] = ["x1", "x2", "x3"];
    const CYCLIC: [bool; 3] = [true; 3];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, _q: &[S; 3], v: &[S; 3], _t: S) -> S {
        (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * 0.5
    }
}

impl Unilateral<3, 2> for Cradle {
    const SCLERONOMIC: bool = true;
    fn contacts<S: Scalar>(&self, q: &[S; 3], _t: S) -> [Contact<S>; 2] {
        [
            Contact::gap(q[1] - q[0]).restitution(1.0).named("1-2"),
            Contact::gap(q[2] - q[1]).restitution(1.0).named("2-3"),
        ]
    }
}

/// The README's cradle: touching balls take their impulses together, (−1/3, 2/3, 2/3) (the
/// simultaneous law: ġ⁺ = −ġ⁻ on both rows), energy kept; with gaps of 1e-6 the impacts come one
/// at a time and pass the velocity down the row, (0, 0, 1). (Gaps within 1e-9 of the contacts'
/// scale count as touching.)
#[test]
fn newtons_cradle_simultaneous_and_sequential() {
    let tr = Simulation::contacts(&Cradle, [0.0, 0.0, 0.0], [1.0, 0.0, 0.0])
        .method(tight())
        .until(1.0)
        .run()
        .unwrap();
    let v = tr.qdot.last().unwrap();
    for (got, want) in v.iter().zip([-1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0]) {
        assert!((got - want).abs() < 1e-12, "{v:?}");
    }
    assert!(tr.jumps[0].t == 0.0 && tr.jumps[0].energy_change.abs() < 1e-14);
    let tr = Simulation::contacts(&Cradle, [0.0, 1e-6, 2e-6], [1.0, 0.0, 0.0])
        .method(tight())
        .until(1.0)
        .run()
        .unwrap();
    let v = tr.qdot.last().unwrap();
    for (got, want) in v.iter().zip([0.0, 0.0, 1.0]) {
        assert!((got - want).abs() < 1e-12, "{v:?}");
    }
    assert_eq!(tr.jumps.len(), 2);
}

/// A reset map that returns NaN is named in the error (not "a smaller dt" a step later).
#[test]
fn a_reset_returning_nan_is_named() {
    struct Fall;
    impl Lagrangian<1> for Fall {
        const COORDINATES: [&'static str; 1] = ["y"];
        const CYCLIC: [bool; 1] = [false];
        const AUTONOMOUS: bool = true;
        fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
            v[0] * v[0] * 0.5 - q[0] * G
        }
    }
    let err = Simulation::new(&Fall, [1.0], [0.0])
        .event(
            Event::zero_crossing("floor", |_t, q: &[f64; 1], _v| q[0])
                .falling()
                .reset(|_t, q, _v| (*q, [f64::NAN])),
        )
        .until(2.0)
        .run()
        .unwrap_err();
    let text = err.to_string();
    assert!(text.contains("reset map of event \"floor\""), "{text}");
}

/// Bad input refused with a typed error: restitution outside [0, 1] or NaN, an event function
/// that turns NaN, an impossible shard, a run at t0 = 1e15 (below the time resolution), and
/// `linearize_on_constraints` off the constraints.
#[test]
fn bad_input_is_a_typed_error() {
    for e in [-0.5, 1.5, f64::NAN] {
        let ball = Ball { m: 1.0, g: G, e };
        let err = Simulation::contacts(&ball, [0.0, 1.0], [0.0, 0.0])
            .until(1.0)
            .run()
            .unwrap_err();
        assert!(
            matches!(err, SimulationError::InvalidOptions { .. })
                && err.to_string().contains("restitution"),
            "e = {e}: {err}"
        );
    }
    struct Free;
    impl Lagrangian<1> for Free {
        const COORDINATES: [&'static str; 1] = ["x"];
        const CYCLIC: [bool; 1] = [true];
        const AUTONOMOUS: bool = true;
        fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S {
            v[0] * v[0] * 0.5
        }
    }
    let err = Simulation::new(&Free, [1.0], [-1.0])
        .event(Event::zero_crossing("root", |_t, q: &[f64; 1], _v| {
            q[0].sqrt() - 0.5
        }))
        .until(3.0)
        .run()
        .unwrap_err();
    assert!(err.to_string().contains("event \"root\""), "{err}");
    let err = Simulation::new(&Free, [1.0], [-1.0])
        .start_time(1e15)
        .until(1e15 + 10.0)
        .run()
        .unwrap_err();
    assert!(err.to_string().contains("time resolution"), "{err}");
    use lagrange::ensemble::Ensemble;
    let e = || Ensemble::new(3, |_| Member::new(Free, [0.0], [1.0]));
    assert!(e().try_shard(3, 2).is_err() && e().try_shard(0, 0).is_err());
    assert_eq!(e().try_shard(1, 2).unwrap().members(), 1..3);
    // A pendulum in x, y on the circle of radius 2, linearized 10 % off it.
    struct Rod;
    impl Lagrangian<2> for Rod {
        const COORDINATES: [&'static str; 2] = ["x", "y"];
        const CYCLIC: [bool; 2] = [true, false];
        const AUTONOMOUS: bool = true;
        fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
            (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[1] * G
        }
    }
    impl Holonomic<2, 1> for Rod {
        const SCLERONOMIC: bool = true;
        fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] {
            [q[0] * q[0] + q[1] * q[1] - 4.0]
        }
    }
    let on = Rod
        .linearize_on_constraints(&[0.0, -2.0], &[0.0, 0.0], 0.0)
        .unwrap();
    let l = on.eigenvalues(&["x"], &["x"]).unwrap();
    assert!((l[0].im.abs() - (G / 2.0).sqrt()).abs() < 1e-12, "{l:?}");
    let off = Rod.linearize_on_constraints(&[0.0, -2.2], &[0.0, 0.0], 0.0);
    assert!(
        matches!(&off, Err(DynamicsError::Constrained { message, .. }) if message.contains("off constraint")),
        "{off:?}"
    );
}

/// (A, B) of ẋ = A x + B u for a cart pushed by u: the state order (x, ẋ) and B = [0; 1/m].
#[test]
fn state_space_of_a_pushed_cart() {
    struct Cart {
        push: f64,
    }
    impl Lagrangian<1> for Cart {
        const COORDINATES: [&'static str; 1] = ["x"];
        const CYCLIC: [bool; 1] = [true];
        const AUTONOMOUS: bool = true;
        fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S {
            v[0] * v[0] * 2.0
        }
        fn generalized_forces<S: Scalar>(&self, _q: &[S; 1], _v: &[S; 1], _t: S) -> [S; 1] {
            [S::constant(self.push)]
        }
    }
    let (a, b) = lagrange::linearize::state_space(
        |u: &[f64; 1]| Cart { push: u[0] },
        &[0.3],
        &[1.0],
        &[0.5],
        0.0,
    )
    .unwrap();
    assert_eq!(a.shape(), (2, 2));
    assert_eq!(
        (a[(0, 0)], a[(0, 1)], a[(1, 0)], a[(1, 1)]),
        (0.0, 1.0, 0.0, 0.0)
    );
    // The input's difference quotient: exact but for round-off (a force affine in u).
    assert!(b[(0, 0)] == 0.0 && (b[(1, 0)] - 0.25).abs() < 1e-12, "{b}");
}

/// A helper outside the impl that reads a rate: the macro cannot see the call, and `max` would
/// swallow the NaN rate of numbers without one.
fn hidden_rate<S: Scalar + Velocity>(x: S) -> S {
    x.velocity().max(S::constant(0.0)) * x
}

pub struct HiddenRate;

#[lagrangian(mode = "jets")]
impl HiddenRate {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        0.5 * x_dot * x_dot - 0.5 * x * x + hidden_rate(x)
    }
}

/// Jets mode: a `velocity` read by a helper the macro cannot see is an error that names it, not
/// a q̈ computed with the NaN rate dropped by `max`.
#[test]
fn a_rate_read_outside_the_impl_is_named() {
    let err = HiddenRate.accelerations(&[1.0], &[0.5], 0.0).unwrap_err();
    assert!(err.to_string().contains("velocity"), "{err}");
    let err = Simulation::new(&HiddenRate, [1.0], [0.5])
        .until(1.0)
        .run()
        .unwrap_err();
    assert!(err.to_string().contains("velocity"), "{err}");
}

/// `(_x, x_dot)` (a coordinate L does not read, named as rustc's unused-variable convention
/// asks) names the coordinate `x`, not `_x`.
#[test]
fn a_leading_underscore_is_not_part_of_the_coordinate_name() {
    assert_eq!(<Ball as Lagrangian<2>>::COORDINATES, ["x", "y"]);
}

/// A particle moving in at ẋ = −1 from x = 1, reset to x = 1 each time it crosses x = 0: the
/// jump at t = 1 caps the next step at 0.01 (a hundredth of ‖y‖/‖ẏ‖), and a run that ends
/// right after that capped step (until = 1.01 + k ulp-sized slivers) ends there. Before, the
/// capped step stopped a sliver short of the end and the next one underflowed.
#[test]
fn a_run_ending_one_capped_step_after_a_jump_ends() {
    for k in 0..40 {
        let until = 1.01 + f64::from(k) * 1e-16;
        for method in [
            tight(),
            Method::DormandPrince {
                rtol: 1e-8,
                atol: 1e-8,
            },
        ] {
            let tr = Simulation::new(&Drift, [1.0], [-1.0])
                .method(method)
                .event(
                    Event::zero_crossing("wall", |_t, q: &[f64; 1], _v| q[0])
                        .falling()
                        .reset(|_t, _q, v| ([1.0], *v)),
                )
                .until(until)
                .run()
                .unwrap_or_else(|e| panic!("until 1.01 + {k}e-16 ({method:?}): {e}"));
            assert_eq!(tr.jumps.len(), 1);
            assert_eq!(*tr.t.last().unwrap(), until);
            let x = tr.q.last().unwrap()[0];
            assert!((x - (1.0 - (until - tr.jumps[0].t))).abs() < 1e-12, "{x}");
        }
    }
}

/// A ball with restitution 0.9995 dropped from 1 mm: its bounces shrink by 0.9995 each (a
/// ratio too close to 1 for the 6-interval Zeno test) and accumulate at t∞ = t₁ (1 + e)/(1 − e)
/// with t₁ = √(2 y₀/g); there the run goes on resting on the floor with λ = m g. Before, the
/// bounces shrank until the step underflowed.
#[test]
fn a_nearly_elastic_ball_comes_to_rest() {
    let e = 0.9995;
    let ball = Ball { m: 1.0, g: G, e };
    let y0 = 1e-3;
    let t1 = (2.0 * y0 / G).sqrt();
    let t_inf = t1 * (1.0 + e) / (1.0 - e);
    let tr = Simulation::contacts(&ball, [0.0, y0], [0.0, 0.0])
        .until(t_inf + 1.0)
        .sample_every(0.5)
        .run()
        .unwrap();
    let z = tr.zeno.as_ref().expect("the bounces accumulate");
    assert!(z.resting, "{z:?}");
    assert!(
        (z.t_accumulation - t_inf).abs() < 1e-6 * t_inf,
        "accumulates at {} against {t_inf}",
        z.t_accumulation
    );
    // The ratio from the last 6 intervals, each within 1e3 location tolerances: 1e-3 of an
    // interval each at worst, so the mean ratio to a few 1e-4.
    assert!((z.ratio - e).abs() < 1e-4, "ratio {}", z.ratio);
    let (y, v) = (tr.q.last().unwrap()[1], tr.qdot.last().unwrap()[1]);
    assert!(y.abs() < 1e-12 && v.abs() < 1e-12, "y {y:e}, ẏ {v:e}");
    let l = tr.lambda.last().unwrap()[0];
    assert!((l - G).abs() < 1e-9, "λ = {l}");
}

/// The pendulum θ̈ = −sin θ.
struct Pendulum;

impl Lagrangian<1> for Pendulum {
    const COORDINATES: [&'static str; 1] = ["theta"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
        v[0] * v[0] * 0.5 + q[0].cos()
    }
}

/// The period of the pendulum's libration of amplitude a: 4 K(sin(a/2)), K by the
/// arithmetic–geometric mean, K(k) = π / (2 AGM(1, √(1 − k²))).
fn libration_period(a: f64) -> f64 {
    let k = (a / 2.0).sin();
    let (mut x, mut y) = (1.0_f64, (1.0 - k * k).sqrt());
    for _ in 0..20 {
        (x, y) = (0.5 * (x + y), (x * y).sqrt());
    }
    4.0 * std::f64::consts::PI / (2.0 * x)
}

/// A small libration (amplitude 0.1: T = 2π (1 + 0.000625 + …), nearly isochronous) from a
/// period guess 5 % off: pinned at its amplitude or its energy, shooting finds the orbit of that
/// amplitude, T = 4 K(sin 0.05) to 1e-9. Unpinned, the least-norm Newton step runs down the
/// family towards the equilibrium; where it ends there, the error names the pins.
#[test]
fn shooting_pinned_to_an_amplitude_or_an_energy() {
    use lagrange::sensitivity::Shooting;
    let a = 0.1;
    let want = libration_period(a);
    let guess = 1.05 * want;
    let by_amplitude = Shooting::autonomous(&Pendulum, [a], [0.0], guess)
        .pin_amplitude(0)
        .find()
        .unwrap();
    assert!((by_amplitude.q0[0] - a).abs() < 1e-12);
    assert!(by_amplitude.qdot0[0].abs() < 1e-12);
    assert!(
        (by_amplitude.period - want).abs() < 1e-9,
        "{} against {want}",
        by_amplitude.period
    );
    let by_energy = Shooting::autonomous(&Pendulum, [0.9 * a], [0.0], guess)
        .pin_energy(-a.cos())
        .find()
        .unwrap();
    assert!(
        (by_energy.period - want).abs() < 1e-9,
        "{} against {want}",
        by_energy.period
    );
    let e = Pendulum.energy(&by_energy.q0, &by_energy.qdot0, 0.0);
    assert!((e + a.cos()).abs() < 1e-12, "{e}");
    match Shooting::autonomous(&Pendulum, [a], [0.0], guess).find() {
        Err(e) => assert!(e.to_string().contains("pin_amplitude"), "{e}"),
        Ok(o) => assert!(o.q0[0].hypot(o.qdot0[0]) > 1e-3, "{o:?}"),
    }
    let bad = Shooting::autonomous(&Pendulum, [a], [0.0], guess)
        .pin_amplitude(1)
        .find();
    assert!(bad.unwrap_err().to_string().contains("numbered 0 to 0"));
}

/// A ball on a floor at height h0 (gap y − h0).
struct HighFloor {
    h0: f64,
}

impl Lagrangian<1> for HighFloor {
    const COORDINATES: [&'static str; 1] = ["y"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    const DECLARES_CONTACTS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
        v[0] * v[0] * 0.5 - q[0] * G
    }
    fn declared<'s, V: lagrange::Declared<'s, Self, 1>>(&'s self, v: V) -> V::Output {
        v.contacts::<1>(self)
    }
}

impl Unilateral<1, 1> for HighFloor {
    const SCLERONOMIC: bool = true;
    fn contacts<S: Scalar>(&self, q: &[S; 1], _t: S) -> [Contact<S>; 1] {
        [Contact::gap(q[0] - self.h0).restitution(0.5)]
    }
}

/// A drop from just above the floor is a drop whatever the units and wherever the origin: the
/// first impact comes at t₁ = √(2d/g) for a height d of 5e-10 above a floor at 0 and of 5e-4
/// above a floor at 10⁶ (both were taken for touching, against the gradient's scale, and the
/// ball rested from t0), while a gap within the round-off of computing it (1e-10 at 10⁶, where
/// adjacent numbers are 1.2e-10 apart) is touching.
#[test]
fn a_small_drop_is_a_drop_in_any_units() {
    for (h0, d) in [(0.0, 5e-10), (1e6, 5e-4), (0.0, 1e-7)] {
        let t1 = (2.0 * d / G).sqrt();
        let tr = Simulation::new(&HighFloor { h0 }, [h0 + d], [0.0])
            .method(tight())
            .until(2.0 * t1)
            .run()
            .unwrap();
        assert!(!tr.jumps.is_empty(), "floor {h0}, drop {d:e}: no impact");
        let rel = (tr.jumps[0].t - t1).abs() / t1;
        assert!(
            rel < 1e-6,
            "floor {h0}, drop {d:e}: impact at {} against {t1}",
            tr.jumps[0].t
        );
        assert!((tr.jumps[0].after.1[0] - 0.5 * G * t1).abs() < 1e-6 * G * t1);
    }
    let tr = Simulation::new(&HighFloor { h0: 1e6 }, [1e6 + 1e-10], [0.0])
        .until(1.0)
        .run()
        .unwrap();
    assert!(tr.jumps.is_empty() && (tr.lambda.last().unwrap()[0] - G).abs() < 1e-9);
}

/// A pendulum about an offset angle: L = ẋ²/2 + cos(x − x₀).
struct Offset {
    x0: f64,
}

impl Lagrangian<1> for Offset {
    const COORDINATES: [&'static str; 1] = ["x"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
        v[0] * v[0] * 0.5 + (q[0] - self.x0).cos()
    }
}

/// An oscillator driven at frequency ω: ẍ + x = cos ωt.
struct Driven {
    w: f64,
}

impl Lagrangian<1> for Driven {
    const COORDINATES: [&'static str; 1] = ["x"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = false;
    const ENERGY_CONSERVED: bool = false;
    fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
        (v[0] * v[0] - q[0] * q[0]) * 0.5
    }
    fn generalized_forces<S: Scalar>(&self, _q: &[S; 1], _v: &[S; 1], t: S) -> [S; 1] {
        [(t * self.w).cos()]
    }
}

/// A force sin u of an input u.
struct SineInput {
    u: f64,
}

impl Lagrangian<1> for SineInput {
    const COORDINATES: [&'static str; 1] = ["x"];
    const CYCLIC: [bool; 1] = [true];
    const AUTONOMOUS: bool = true;
    const MOMENTUM_CONSERVED: [bool; 1] = [false];
    const ENERGY_CONSERVED: bool = false;
    fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S {
        v[0] * v[0] * 0.5
    }
    fn generalized_forces<S: Scalar>(&self, _q: &[S; 1], _v: &[S; 1], _t: S) -> [S; 1] {
        [S::constant(self.u.sin())]
    }
}

/// Parameters whose dependence is not on the scale of their value: an offset x₀ = 100 or 1000
/// (the motion moves with x and x₀ together, so ∂x/∂x₀ = 1 − Φ₀₀ from the same run; a step of
/// ε^(1/5)|x₀| = 0.74 was 1 % off), and a drive frequency ω = 50 (from rest,
/// x = (cos ωt − cos t)/(1 − ω²), so ∂x/∂ω = −t sin ωt/(1 − ω²) + 2ω (cos ωt − cos t)/(1 − ω²)²;
/// 6.4e-4 off before); `input_matrix` of sin u at u = 100 and 10⁴ (cos u; the wrong sign at 10⁴
/// before). Tolerances: 1e-9 for the offset (the run's own Φ against its ∂x/∂x₀, both at rtol
/// 1e-12), 1e-6 relative for ω (the fourth-order stencil's truncation along t = 10 with h = 7e-4
/// is 5e-7 relative), 1e-9 for B plus the rounding of u ± h at u's resolution.
#[test]
fn parameters_that_vary_on_another_scale_than_their_value() {
    for x0 in [100.0, 1000.0] {
        let run = Simulation::new(&Offset { x0 }, [x0 + 1.0], [0.0])
            .method(tight())
            .until(5.0)
            .sensitivity()
            .parameter("x0", x0, |x0| Offset { x0 })
            .run()
            .unwrap();
        let (phi, dp) = (run.final_phi(), run.dparams.last().unwrap());
        let want = 1.0 - phi[(0, 0)];
        assert!(
            (dp[(0, 0)] - want).abs() < 1e-9,
            "x0 = {x0}: {} against {want}",
            dp[(0, 0)]
        );
    }
    let (w, t) = (50.0_f64, 10.0_f64);
    let run = Simulation::new(&Driven { w }, [0.0], [0.0])
        .method(tight())
        .until(t)
        .sensitivity()
        .parameter("w", w, |w| Driven { w })
        .run()
        .unwrap();
    let d = 1.0 - w * w;
    let want = -t * (w * t).sin() / d + 2.0 * w * ((w * t).cos() - t.cos()) / (d * d);
    let got = run.dparams.last().unwrap()[(0, 0)];
    assert!(
        (got - want).abs() < 1e-6 * want.abs(),
        "∂x/∂ω = {got} against {want}"
    );
    for u in [100.0_f64, 1e4] {
        let b = lagrange::linearize::input_matrix(
            |p: &[f64; 1]| SineInput { u: p[0] },
            &[u],
            &[0.0],
            &[0.0],
            0.0,
        )
        .unwrap()[(0, 0)];
        // The stencil's arguments u ± h, u ± 2h are rounded to u's own resolution (ε u / 2
        // each); the difference carries 20 of them over 12 h (h = ε^(1/5) = 7.4e-4): 5e-9 at
        // u = 10⁴, below 1e-13 at 100.
        let tol = 1e-9 + 20.0 * f64::EPSILON * u / (12.0 * 7.4e-4);
        assert!(
            (b - u.cos()).abs() < tol,
            "u = {u}: B = {b} against {}",
            u.cos()
        );
    }
}

/// Directions that grow fast without separating: one followed direction at λ = 600 and 1000
/// (e^600 per renormalization interval of 1: past 1e154 the squares overflowed, and the run
/// ended in "separate by a factor e^NaN … tighten the tolerances", advice that did not help),
/// and two followed directions growing alike (a = b = 800). The largest exponent over a run of
/// T = 5 is a + ln(c)/T for the initial direction's share c of the unstable one: within 0.5 % of
/// a. An infinite renormalization interval is refused.
#[test]
fn lyapunov_directions_growing_fast_together() {
    for a in [600.0, 1000.0] {
        let s = Lyapunov::new(&Saddles { a, b: 0.5 }, [0.0, 0.0], [0.0, 0.0])
            .duration(5.0)
            .directions(1)
            .compute()
            .unwrap();
        assert!((s.exponents[0] - a).abs() < 5e-3 * a, "{:?}", s.exponents);
    }
    let s = Lyapunov::new(&Saddles { a: 800.0, b: 800.0 }, [0.0, 0.0], [0.0, 0.0])
        .duration(5.0)
        .directions(2)
        .compute()
        .unwrap();
    for e in &s.exponents {
        assert!((e - 800.0).abs() < 4.0, "{:?}", s.exponents);
    }
    let err = Lyapunov::new(&Saddles { a: 1.0, b: 0.5 }, [0.0, 0.0], [0.0, 0.0])
        .renormalize_every(f64::INFINITY)
        .compute()
        .unwrap_err();
    assert!(
        matches!(err, SimulationError::InvalidOptions { .. }),
        "{err}"
    );
}

/// A harmonic oscillator, ẍ = −x (period 2π).
struct Unit;

impl Lagrangian<1> for Unit {
    const COORDINATES: [&'static str; 1] = ["x"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
        (v[0] * v[0] - q[0] * q[0]) * 0.5
    }
}

/// Shooting at the scales of its tolerance: an orbit of amplitude 1e-8 pinned at its turning
/// point is found (T = 2π to 1e-9) when the tolerance resolves it (1e-20), and refused with
/// advice to lower the tolerance when it does not (the default 1e-10, which "converged" with T
/// off by 5e-5); it was refused as an equilibrium in both cases. An energy below the pendulum's
/// minimum (−1) ends in a typed error within the iteration budget (each backtracking shot was
/// taken over an enormous period: no answer after 120 s).
#[test]
fn shooting_small_orbits_and_unreachable_energies() {
    use lagrange::sensitivity::{OrbitError, Shooting};
    let guess = 1.02 * std::f64::consts::TAU;
    let orbit = Shooting::autonomous(&Unit, [1e-8], [0.0], guess)
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-22,
        })
        .tolerance(1e-20)
        .pin_amplitude(0)
        .find()
        .unwrap();
    assert!(
        (orbit.period - std::f64::consts::TAU).abs() < 1e-9,
        "T = {}",
        orbit.period
    );
    let err = Shooting::autonomous(&Unit, [1e-8], [0.0], guess)
        .pin_amplitude(0)
        .find()
        .unwrap_err();
    assert!(matches!(err, OrbitError::NoConvergence { .. }), "{err}");
    assert!(err.to_string().contains(".tolerance("), "{err}");
    let err = Shooting::autonomous(&Pendulum, [0.1], [0.0], 6.3)
        .pin_energy(-2.0)
        .find()
        .unwrap_err();
    assert!(matches!(err, OrbitError::NoConvergence { .. }), "{err}");
    assert!(err.to_string().contains("no orbit of that energy"), "{err}");
}

/// A reset that puts the state d in front of the wall it crossed, still moving in: each next
/// crossing is a hit. At d = 1e-11 the hits are resolved (11 hits d apart after the first at
/// t = 1, to the location's tolerance 1e-12); at d = 1e-12 and 3e-13, about the located root's
/// own residual, the run either resolves them or reports their accumulation (Zeno: the location
/// cannot tell them apart), and never goes through the wall by more than the location's error
/// (it went through after 6 and 2 hits, with no error: x = −0.01 at t = 1.01).
#[test]
fn a_reset_within_the_location_error_of_its_surface_crosses_again() {
    let run = |d: f64, until: f64| {
        Simulation::new(&Drift, [1.0], [-1.0])
            .method(tight())
            .event(
                Event::zero_crossing("wall", |_t, q: &[f64; 1], _v| q[0])
                    .falling()
                    .reset(move |_t, _q, v| ([d], *v)),
            )
            .until(until)
            .run()
            .unwrap()
    };
    let d = 1e-11;
    let tr = run(d, 1.0 + 10.5 * d);
    let times: Vec<f64> = tr.jumps.iter().map(|j| j.t).collect();
    assert_eq!(times.len(), 11, "{times:?}");
    for (k, t) in times.iter().enumerate() {
        assert!((t - (1.0 + k as f64 * d)).abs() < 1e-12, "hit {k} at {t}");
    }
    for d in [1e-12, 3e-13] {
        let tr = run(d, 1.0 + 1e-9);
        let lowest = tr.q.iter().fold(f64::INFINITY, |m, q| m.min(q[0]));
        // Within 10 location tolerances (1e-12 in time, at unit speed) of the wall.
        assert!(
            lowest > -1e-11,
            "d = {d:e}: through the wall, x = {lowest:e}"
        );
        assert!(
            tr.zeno.is_some() || *tr.t.last().unwrap() == 1.0 + 1e-9,
            "d = {d:e}: {:?}",
            tr.t.last()
        );
    }
}

/// A reset that puts the state d = 3e-13 … 3e-12 in front of the wall, closer than the
/// location's tolerance (1e-12): after each jump the next crossing is located to round-off, so
/// every hit is seen, d apart, and nothing passes the wall or looks like an accumulation. Before,
/// the root right after a jump was taken at the jump's own instant, where the reset changed
/// nothing: at d = 3e-13, 2 hits then through the wall (x = −2.55e-12, no error); at 1e-12 and
/// 3e-12 the located times' noise (1e-13) was read as hits shrinking: Zeno after 6 or 7 hits.
#[test]
fn resets_closer_than_the_location_tolerance_are_each_resolved() {
    for d in [3e-13, 1e-12, 3e-12] {
        let until = 1.0 + 9.5 * d;
        let tr = Simulation::new(&Drift, [1.0], [-1.0])
            .method(tight())
            .event(
                Event::zero_crossing("wall", |_t, q: &[f64; 1], _v| q[0])
                    .falling()
                    .reset(move |_t, _q, v| ([d], *v)),
            )
            .until(until)
            .run()
            .unwrap();
        let times: Vec<f64> = tr.jumps.iter().map(|j| j.t).collect();
        let lowest = tr.q.iter().fold(f64::INFINITY, |m, q| m.min(q[0]));
        assert_eq!(
            times.len(),
            10,
            "d = {d:e}: {times:?} {:?} {:?} {lowest:e} {:?}",
            tr.zeno,
            tr.t.last(),
            tr.q.last()
        );
        for w in times.windows(2) {
            // d apart to a few ulps of t ≈ 1 (2.2e-16).
            assert!((w[1] - w[0] - d).abs() < 1e-15, "d = {d:e}: {times:?}");
        }
        assert!(tr.zeno.is_none(), "d = {d:e}: {:?}", tr.zeno);
        assert_eq!(*tr.t.last().unwrap(), until);
        let lowest = tr.q.iter().fold(f64::INFINITY, |m, q| m.min(q[0]));
        assert!(
            lowest >= -1e-15,
            "d = {d:e}: through the wall, x = {lowest:e}"
        );
        let x_end = tr.q.last().unwrap()[0];
        assert!((x_end - 0.5 * d).abs() < 1e-15, "d = {d:e}: x = {x_end:e}");
    }
}

/// A run that reaches its sample limit while a reset keeps the state 1e-12 in front of a wall
/// reports the last stored sample, as `MaxSamples` documents: it reported the stepper's node, a
/// step past it and beyond a crossing not yet applied (x = −0.01 at t = 1.01, a state the run
/// never reaches).
#[test]
fn the_sample_limit_reports_the_last_stored_sample() {
    let err = Simulation::new(&Drift, [1.0], [-1.0])
        .method(tight())
        .event(
            Event::zero_crossing("wall", |_t, q: &[f64; 1], _v| q[0])
                .falling()
                .reset(|_t, _q, v| ([1e-12], *v)),
        )
        .until(2.0)
        .max_samples(1000)
        .run()
        .unwrap_err();
    let SimulationError::MaxSamples { t, q, .. } = &err else {
        panic!("{err}");
    };
    let kept = err.partial_trajectory::<1>().unwrap();
    assert_eq!(*t, *kept.t.last().unwrap(), "{err}");
    assert_eq!(q[0], kept.q.last().unwrap()[0]);
    assert!(q[0] >= -1e-15 && *t < 1.0 + 1e-8, "{err}");
}

/// A ball dropped from 10⁴ m that is kicked up by 0.1 m/s at each bounce (ẏ⁺ = −0.8 ẏ⁻ + 0.1)
/// settles into a steady bouncing at ẏ⁺ = 0.5 m/s, a hit every 0.102 s: nothing accumulates
/// (it was reported as Zeno at t = 407 after 7 hits, the run stopped at 312). The hit times
/// against the recurrence v ← 0.8 v + 0.1, Δt = 2v/g from the first impact at √(2·10⁴/g),
/// to 1e-9 relative.
#[test]
fn bounces_settling_into_a_steady_cycle_are_not_zeno() {
    struct Fall;
    impl Lagrangian<1> for Fall {
        const COORDINATES: [&'static str; 1] = ["y"];
        const CYCLIC: [bool; 1] = [false];
        const AUTONOMOUS: bool = true;
        fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
            v[0] * v[0] * 0.5 - q[0] * G
        }
    }
    let until = 600.0;
    let tr = Simulation::new(&Fall, [1e4], [0.0])
        .method(tight())
        .event(
            Event::zero_crossing("floor", |_t, q: &[f64; 1], _v| q[0])
                .falling()
                .reset(|_t, q, v| (*q, [-0.8 * v[0] + 0.1])),
        )
        .until(until)
        .run()
        .unwrap();
    assert!(tr.zeno.is_none(), "{:?}", tr.zeno);
    let mut t = (2.0 * 1e4 / G).sqrt();
    let mut v = G * t;
    let mut want = Vec::new();
    while t <= until {
        want.push(t);
        v = 0.8 * v + 0.1;
        t += 2.0 * v / G;
    }
    let got: Vec<f64> = tr.jumps.iter().map(|j| j.t).collect();
    assert_eq!(got.len(), want.len());
    for (a, b) in got.iter().zip(&want) {
        assert!((a - b).abs() < 1e-9 * b, "{a} against {b}");
    }
}

/// Hits accumulating as a power law: a reset that puts the particle 1/k² in front of the wall at
/// its k-th hit (k = 2, 3, …), so the hits accumulate at t∞ = 1 + Σ_{k≥2} 1/k² = π²/6. When the
/// intervals fall below what the event location resolves, the run reports the accumulation
/// (Zeno, within 1e-3 of π²/6) and ends; the particle never goes through the wall (it went on
/// for 1.46 M hits and was at x = −0.355 at t = 2, with no error).
#[test]
fn hits_accumulating_as_a_power_law_are_reported() {
    let k = std::cell::Cell::new(1.0_f64);
    let tr = Simulation::new(&Drift, [1.0], [-1.0])
        .method(tight())
        .event(
            Event::zero_crossing("wall", |_t, q: &[f64; 1], _v| q[0])
                .falling()
                .reset(|_t, _q, v| {
                    k.set(k.get() + 1.0);
                    ([1.0 / (k.get() * k.get())], *v)
                }),
        )
        .until(2.0)
        .max_steps(5_000_000)
        .run()
        .unwrap();
    let zeno = tr.zeno.as_ref().expect("an accumulation");
    let t_inf = std::f64::consts::PI.powi(2) / 6.0;
    assert!((zeno.t_accumulation - t_inf).abs() < 1e-3, "{zeno:?}");
    let lowest = tr.q.iter().fold(f64::INFINITY, |m, q| m.min(q[0]));
    assert!(lowest > -1e-11, "through the wall: {lowest:e}");
}
