//! Regressions of an adversarial review of the Taylor method: every function of the
//! table and `powi(n)` for n = −3 … 8, in L and in M, against DOP853 (scalar and lanes); bodies
//! that are not analytic are refused; coefficients that vanish at the start bound the step; the
//! work integral carries the step's accuracy.

use lagrange::ensemble::{Ensemble, Member};
use lagrange::lanes::Lanes;
use lagrange::prelude::*;
use lagrange::taylor::{SeriesBuf, TaylorBuf};
use lagrange::SimulationError;

use crate::support::Kernels;

/// A system of one coordinate per expression `f[i]` of x[i]: M_ii = 2 + f and V_i = ½x² + f/10
/// (so f enters M and its derivative the right-hand side).
macro_rules! functions {
    ($name:ident, $n:literal, ($x:ident, $x_dot:ident); $($f:expr),* $(,)?) => {
        #[derive(Clone, Copy, Debug)]
        pub struct $name;

        #[lagrangian]
        impl $name {
            fn lagrangian(&self, ($x, $x_dot): Coords<$n>) -> Scalar {
                let f = [$($f),*];
                let mut l = 0.0;
                for i in 0..$n {
                    l += 0.5 * (2.0 + f[i]) * $x_dot[i] * $x_dot[i] - 0.5 * $x[i] * $x[i] - 0.1 * f[i];
                }
                l
            }
        }
    };
}

// Every function of the table at a = c + 0.3 x inside its domain (|x| ≤ 0.5 along the motion),
// five per system: small enough for the lanes code (`COMPILED.lanes`).
functions!(FunctionsA, 5, (x, x_dot);
    (1.0 + 0.3 * x[0]).sqrt() * 0.5,
    (0.3 + 0.3 * x[1]).sin(),
    (0.3 + 0.3 * x[2]).cos() * 0.5,
    (0.3 + 0.3 * x[3]).tan(),
    (0.3 * x[4]).exp() * 0.5,
);
functions!(FunctionsB, 5, (x, x_dot);
    (1.5 + 0.3 * x[0]).ln(),
    (0.3 + 0.3 * x[1]).asinh(),
    (1.5 + 0.3 * x[2]).acosh(),
    (0.3 + 0.3 * x[3]).atanh(),
    (0.3 * x[4]).exp2() * 0.5,
);
functions!(FunctionsC, 5, (x, x_dot);
    (1.0 + 0.3 * x[0]).cbrt() * 0.5,
    (0.3 + 0.3 * x[1]).ln_1p(),
    (0.3 * x[2]).exp_m1(),
    (1.5 + 0.3 * x[3]).log10(),
    (1.5 + 0.3 * x[4]).log2() * 0.5,
);
functions!(FunctionsD, 5, (x, x_dot);
    (0.3 + 0.3 * x[0]).asin(),
    (0.3 + 0.3 * x[1]).acos() * 0.5,
    (0.3 + 0.3 * x[2]).atan(),
    (0.3 + 0.3 * x[3]).sinh(),
    (0.3 + 0.3 * x[4]).cosh() * 0.5,
);
functions!(FunctionsE, 5, (x, x_dot);
    (0.3 + 0.3 * x[0]).tanh(),
    (1.0 + 0.3 * x[1]).powf(2.5) * 0.3,
    (0.3 + 0.3 * x[2]).atan2(1.0 + 0.2 * x[2]),
    (0.3 + 0.3 * x[3]).hypot(1.0) * 0.5,
    (1.5 + 0.3 * x[4]).recip(),
);

// `powi(n)`, n = −3 … 8: in M and V through (1 + x/5)ⁿ (0.3 (1 + x/5)ⁿ here), and for n ≥ 2
// also xⁿ in V (through x = 0, where the power rule's 1/x₀ would fail).
functions!(PowersA, 4, (x, x_dot);
    0.3 * (1.0 + 0.2 * x[0]).powi(-3),
    0.3 * (1.0 + 0.2 * x[1]).powi(-2),
    0.3 * (1.0 + 0.2 * x[2]).powi(-1),
    0.3 * (1.0 + 0.2 * x[3]).powi(0) + x[3].powi(2),
);
functions!(PowersB, 4, (x, x_dot);
    0.3 * (1.0 + 0.2 * x[0]).powi(1) + x[0].powi(3),
    0.3 * (1.0 + 0.2 * x[1]).powi(2) + x[1].powi(4),
    0.3 * (1.0 + 0.2 * x[2]).powi(3) + x[2].powi(5),
    0.3 * (1.0 + 0.2 * x[3]).powi(4) + x[3].powi(6),
);
functions!(PowersC, 4, (x, x_dot);
    0.3 * (1.0 + 0.2 * x[0]).powi(5) + x[0].powi(7),
    0.3 * (1.0 + 0.2 * x[1]).powi(6) + x[1].powi(8),
    0.3 * (1.0 + 0.2 * x[2]).powi(7) + 0.5 * x[2].powi(4),
    0.3 * (1.0 + 0.2 * x[3]).powi(8) + 0.5 * x[3].powi(5),
);

/// The reproducer: ẍ = −x − x³ from x = 1 at rest.
pub struct Quartic;

#[lagrangian]
impl Quartic {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        x_dot * x_dot / 2.0 - x * x / 2.0 - x.powi(4) / 4.0
    }
}

/// The end state of a run of `method` to t = 10.
fn end<L: Lagrangian<N>, const N: usize>(sys: &L, q0: [f64; N], method: Method) -> [f64; N] {
    let tr = Simulation::new(sys, q0, [0.0; N])
        .method(method)
        .until(10.0)
        .sample_at([0.0; 0])
        .run()
        .expect("a regular run");
    tr.q[tr.q.len() - 1]
}

const DOP: Method = Method::Dop853 {
    rtol: 1e-13,
    atol: 1e-13,
};

/// Taylor at tol 1e-15 against DOP853 at 1e-13 to t = 10, every coordinate (the defect: 1e-2
/// to 1e2 errors with `Ok`). 1e-9 is ten thousand times DOP853's error on these orbits.
fn agree<const N: usize>(a: [f64; N], b: [f64; N], what: &str) {
    for i in 0..N {
        assert!(
            (a[i] - b[i]).abs() < 1e-9,
            "{what}, coordinate {i}: Taylor {} against DOP853 {}",
            a[i],
            b[i]
        );
    }
}

#[test]
fn taylor_equals_dop853_on_a_quartic_oscillator() {
    // x(10) = 0.798875 (DOP853 and SciPy); the Taylor method gave 0.710012.
    let x = end(&Quartic, [1.0], Method::Taylor { tol: 1e-15 })[0];
    assert!((x - 0.798875).abs() < 1e-6, "x(10) = {x}");
    agree(
        end(&Quartic, [1.0], Method::Taylor { tol: 1e-15 }),
        end(&Quartic, [1.0], DOP),
        "x⁴/4",
    );
}

/// Taylor against DOP853 for one system of the tables, from a state of every coordinate ≈ 0.5.
fn against_dop853<L: Lagrangian<N>, const N: usize>(sys: &L, what: &str) {
    let q0 = core::array::from_fn(|i| 0.5 - 0.03 * i as f64);
    agree(
        end(sys, q0, Method::Taylor { tol: 1e-15 }),
        end(sys, q0, DOP),
        what,
    );
}

#[test]
fn taylor_equals_dop853_for_every_function_of_the_table() {
    against_dop853(&FunctionsA, "sqrt sin cos tan exp");
    against_dop853(&FunctionsB, "ln asinh acosh atanh exp2");
    against_dop853(&FunctionsC, "cbrt ln_1p exp_m1 log10 log2");
    against_dop853(&FunctionsD, "asin acos atan sinh cosh");
    against_dop853(&FunctionsE, "tanh powf atan2 hypot recip");
}

#[test]
fn taylor_equals_dop853_for_every_power() {
    against_dop853(&PowersA, "powi −3 … 0");
    against_dop853(&PowersB, "powi 1 … 4");
    against_dop853(&PowersC, "powi 5 … 8");
}

/// The lanes code: `taylor_series_lanes` of four members at four states equals, lane by lane,
/// `taylor_series` of that member (which the tests above hold against DOP853), to round-off
/// (the vector sin, cos, exp and ln are not the scalar ones bit for bit).
fn lanes_equal_scalar<L: Lagrangian<N>, const N: usize>(sys: &L, what: &str) {
    const P: usize = 20;
    assert!(L::COMPILED.lanes, "{what}: no lanes code");
    let state = |l: usize, c: usize, i: usize| {
        0.1 + 0.07 * l as f64 + 0.03 * i as f64 - if c == 1 { 0.2 } else { 0.0 }
    };
    let mut out = vec![[[Lanes::<4>::ZERO; N]; 2]; P + 1];
    out[0] = core::array::from_fn(|c| {
        core::array::from_fn(|i| Lanes(core::array::from_fn(|l| state(l, c, i))))
    });
    let done = L::taylor_series_lanes(
        &[sys, sys, sys, sys],
        Lanes::ZERO,
        &mut out,
        &mut SeriesBuf::new(),
    )
    .expect("lanes code");
    assert!(done.all(), "{what}: a lane was left out");
    for l in 0..4 {
        let mut scalar = vec![[[0.0; N]; 2]; P + 1];
        scalar[0] = core::array::from_fn(|c| core::array::from_fn(|i| state(l, c, i)));
        sys.taylor_series(0.0, &mut scalar, &mut TaylorBuf::new())
            .expect("a series")
            .expect("a regular state");
        for k in 0..=P {
            for c in 0..2 {
                for i in 0..N {
                    let (a, b) = (out[k][c][i].0[l], scalar[k][c][i]);
                    assert!(
                        (a - b).abs() <= 1e-13 * b.abs().max(1.0),
                        "{what}: lane {l}, order {k}, {c}/{i}: {a} against {b}"
                    );
                }
            }
        }
    }
}

#[test]
fn taylor_lanes_equal_the_scalar_series_for_every_function_and_power() {
    lanes_equal_scalar(&FunctionsA, "sqrt sin cos tan exp");
    lanes_equal_scalar(&FunctionsB, "ln asinh acosh atanh exp2");
    lanes_equal_scalar(&FunctionsC, "cbrt ln_1p exp_m1 log10 log2");
    lanes_equal_scalar(&FunctionsD, "asin acos atan sinh cosh");
    lanes_equal_scalar(&FunctionsE, "tanh powf atan2 hypot recip");
    lanes_equal_scalar(&PowersA, "powi −3 … 0");
    lanes_equal_scalar(&PowersB, "powi 1 … 4");
    lanes_equal_scalar(&PowersC, "powi 5 … 8");
}

/// An ensemble in lanes with the Taylor method (five members: one lane runs two) equals DOP853
/// member by member.
#[test]
fn taylor_ensemble_in_lanes_equals_dop853() {
    let q0 = |k: usize| core::array::from_fn(|i| 0.45 - 0.03 * i as f64 + 0.01 * k as f64);
    let r = Ensemble::new(5, |k| Member::new(PowersC, q0(k), [0.0; 4]))
        .configure(|sim| {
            sim.method(Method::Taylor { tol: 1e-15 })
                .until(10.0)
                .sample_at([0.0; 0])
        })
        .lanes(4)
        .threads(1)
        .run();
    for (k, tr) in r.results.iter().enumerate() {
        let tr = tr.as_ref().expect("a regular run");
        agree(
            tr.q[tr.q.len() - 1],
            end(&PowersC, q0(k), DOP),
            "powers in lanes",
        );
    }
}

/// ẍ = −sgn x: a kink at x = 0 (exact x(10) = 0.137085; one Taylor step gave x(10) = −49).
pub struct Vee;

#[lagrangian]
impl Vee {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        x_dot * x_dot / 2.0 - x.abs()
    }
}

/// The same written as √(x²).
pub struct VeeSqrt;

#[lagrangian]
impl VeeSqrt {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        x_dot * x_dot / 2.0 - (x * x).sqrt()
    }
}

/// A spring with a one-sided stop: max.
pub struct Stop;

#[lagrangian]
impl Stop {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        x_dot * x_dot / 2.0 - 0.5 * x.max(0.0) * x.max(0.0) - 0.1 * x.min(1.0) - x.clamp(-1.0, 1.0)
    }
}

/// Coulomb friction on an oscillator: `signum` in the forces.
pub struct Coulomb;

#[lagrangian]
impl Coulomb {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        x_dot * x_dot / 2.0 - x * x / 2.0
    }
    fn forces(&self, (_x, x_dot): Coord) -> [Scalar; 1] {
        [-0.5 * x_dot.signum()]
    }
}

/// The refusal of a body that is not analytic, naming the construct.
fn refused<L: Lagrangian<1>>(sys: &L, construct: &str) {
    let r = Simulation::new(sys, [1.0], [0.0])
        .method(Method::Taylor { tol: 1e-12 })
        .until(10.0)
        .run();
    match r {
        Err(SimulationError::InvalidOptions { message }) => {
            assert!(
                message.contains(construct) && message.contains("Dop853"),
                "{message}"
            );
        }
        other => panic!("expected InvalidOptions naming {construct}, got {other:?}"),
    }
    // DOP853 runs it (to t = 2, before Coulomb friction sticks the oscillator).
    if let Err(e) = Simulation::new(sys, [1.0], [0.0]).until(2.0).run() {
        panic!("DOP853 on a body with {construct}: {e}");
    }
}

#[test]
fn taylor_refuses_bodies_that_are_not_analytic() {
    refused(&Vee, "`abs`");
    refused(&VeeSqrt, "square root of a square");
    refused(&Stop, "`max`, `min` or `clamp`");
    // |x| in a potential enters the equations through its slope, the step H(x).
    refused(&Coulomb, "`signum`");
    assert_eq!(
        Vee::COMPILED.not_analytic.map(|s| s.starts_with("`abs`")),
        Some(true)
    );
    assert_eq!(
        Coulomb::COMPILED
            .not_analytic
            .map(|s| s.starts_with("`signum`")),
        Some(true)
    );
    assert_eq!(Quartic::COMPILED.not_analytic, None);
    // The kink itself, by DOP853: x(10) = 0.137085 (the value, from the parabolas
    // x = 1 − t²/2 and their mirror images: period 4√2).
    let tr = Simulation::new(&Vee, [1.0], [0.0])
        .method(DOP)
        .until(10.0)
        .run()
        .expect("DOP853 steps through the kink");
    let x = tr.q[tr.q.len() - 1][0];
    assert!((x - 0.137085).abs() < 1e-5, "x(10) = {x}");
}

/// A force t²⁵ on a free particle from rest at t = 0: x = t²⁷/702.
pub struct Ramp;

#[lagrangian]
impl Ramp {
    fn lagrangian(&self, (_x, x_dot): Coord) -> Scalar {
        x_dot * x_dot / 2.0
    }
    fn forces(&self, (_x, _x_dot): Coord, t: Time) -> [Scalar; 1] {
        [t.powi(25)]
    }
}

/// The first 25 coefficients of the motion vanish at t = 0: with order 19 the Jorba–Zou step
/// was infinite and x(2) came out 0 (exact 2²⁷/702 = 1.9e5).
#[test]
fn taylor_bounds_the_step_where_the_top_coefficients_vanish() {
    // (Below order 13 a polynomial of degree 27 defeats the step estimate itself: its terms past
    // the order grow instead of falling off, see the README's Reliability section.)
    for tol in [1e-15, 1e-12, 1e-10] {
        let tr = Simulation::new(&Ramp, [0.0], [0.0])
            .method(Method::Taylor { tol })
            .until(2.0)
            .sample_at([0.0; 0])
            .run()
            .expect("a regular run");
        let x = tr.q[tr.q.len() - 1][0];
        let exact = 2f64.powi(27) / 702.0;
        assert!(
            ((x - exact) / exact).abs() < 100.0 * tol.max(1e-14),
            "tol {tol:e}: x(2) = {x}, exact {exact}"
        );
        assert!(tr.stats.steps > 1, "tol {tol:e}: {} steps", tr.stats.steps);
    }
    // A motion that is a polynomial (a constant force) still takes one step.
    let tr = Simulation::new(&Quartic, [0.0], [0.0])
        .method(Method::Taylor { tol: 1e-15 })
        .until(1e-3)
        .run()
        .expect("a regular run");
    assert!(tr.stats.steps >= 1);
}

/// F = sin t on a free particle from rest: v = 1 − cos t, W(t) = v²/2.
pub struct Pushed;

#[lagrangian]
impl Pushed {
    fn lagrangian(&self, (_x, x_dot): Coord) -> Scalar {
        x_dot * x_dot / 2.0
    }
    fn forces(&self, (_x, _x_dot): Coord, t: Time) -> [Scalar; 1] {
        [t.sin()]
    }
}

/// The work integral of a Taylor run carries the step's accuracy (a 4-point Gauss rule over an
/// order-20 step left W(10) off by 4e-8 relative while x(10) was right to 1.8e-15).
#[test]
fn taylor_work_integral_has_the_steps_accuracy() {
    let tr = Simulation::new(&Pushed, [0.0], [0.0])
        .method(Method::Taylor { tol: 1e-15 })
        .until(10.0)
        .sample_every(0.5)
        .run()
        .expect("a regular run");
    for (k, &t) in tr.t.iter().enumerate() {
        let v = 1.0 - t.cos();
        let w = v * v / 2.0;
        assert!(
            (tr.work[k] - w).abs() <= 1e-13 * w.max(1.0),
            "t = {t}: W = {}, exact {w}",
            tr.work[k]
        );
        assert!((tr.q[k][0] - (t - t.sin())).abs() < 1e-13);
    }
}
