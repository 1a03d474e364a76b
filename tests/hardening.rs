//! Regression tests of the run time under hostile but valid input: each case once failed with a
//! spurious error or lost accuracy silently; each now integrates, or fails up front with an
//! `InvalidOptions` that says why.

use lagrange::prelude::*;

use crate::support::hand::HeavyTop;

/// A pure relative tolerance (atol = 0) is what a user asking for it expects, also where a
/// component of the state is exactly zero (the README's own heavy-top state has φ = ψ = 0, and
/// a planar motion keeps z ≡ 0): it must integrate, not fail at t0 blamed on stiffness.
#[test]
fn a_zero_absolute_tolerance_is_pure_relative_control() {
    let top = HeavyTop {
        i_perp: 1.0,
        i_par: 0.6,
        mgl: 1.0,
    };
    for method in [
        Method::Dop853 {
            rtol: 1e-10,
            atol: 0.0,
        },
        Method::DormandPrince {
            rtol: 1e-8,
            atol: 0.0,
        },
    ] {
        let tr = Simulation::new(&top, [1.0, 0.0, 0.0], [0.0, -0.5, 8.0])
            .method(method)
            .until(10.0)
            .run()
            .unwrap_or_else(|e| panic!("{method:?}: {e}"));
        let reference = Simulation::new(&top, [1.0, 0.0, 0.0], [0.0, -0.5, 8.0])
            .method(Method::Dop853 {
                rtol: 1e-13,
                atol: 1e-13,
            })
            .until(10.0)
            .run()
            .unwrap();
        let (a, b) = (tr.q.last().unwrap(), reference.q.last().unwrap());
        let tol = if matches!(method, Method::Dop853 { .. }) {
            1e-7
        } else {
            1e-5
        };
        for i in 0..3 {
            assert!(
                (a[i] - b[i]).abs() <= tol * (1.0 + b[i].abs()),
                "{method:?}: q[{i}] {} vs {}",
                a[i],
                b[i]
            );
        }
    }
}

/// A well-conditioned but badly scaled mass matrix (a planet and a satellite in SI units) is not
/// singular: the pivot test is relative to each coordinate's own diagonal entry.
struct TwoMasses;
impl Lagrangian<2> for TwoMasses {
    const COORDINATES: [&'static str; 2] = ["planet", "satellite"];
    const CYCLIC: [bool; 2] = [false, false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
        // m1 = 6e24 kg, m2 = 1e3 kg, a spring between them.
        v[0] * v[0] * 3e24 + v[1] * v[1] * 500.0 - (q[0] - q[1]) * (q[0] - q[1]) * 0.5
    }
}

#[test]
fn a_badly_scaled_mass_matrix_is_not_singular() {
    let a = TwoMasses
        .accelerations(&[0.0, 1.0], &[0.0, 0.0], 0.0)
        .expect("diag(6e24, 1e3) is well conditioned");
    assert!((a[0] - 1.0 / 6e24).abs() <= 1e-15 / 6e24, "{a:?}");
    assert!((a[1] + 1.0 / 1e3).abs() <= 1e-15 / 1e3, "{a:?}");
    let m = lagrange::linalg::solve_symmetric(&[[1e14, 0.0], [0.0, 1.0]], &[1.0, 1.0]).unwrap();
    assert_eq!(m, [1e-14, 1.0]);
}

/// Near the Euler-angle singularity the jets' numeric elimination loses digits like ε / sin²θ:
/// at θ = 1e-6 the answer would have lost about 12 of 16 digits. That is a typed error that says
/// so, not a silent loss; where the answer keeps more than half its digits it is returned.
#[test]
fn an_answer_that_lost_half_its_digits_is_an_error() {
    let top = HeavyTop {
        i_perp: 1.0,
        i_par: 0.6,
        mgl: 1.0,
    };
    let err = top
        .accelerations(&[1e-6, 0.0, 0.0], &[0.1, 0.2, 3.0], 0.0)
        .expect_err("12 digits lost");
    let text = err.to_string();
    assert!(
        text.contains("nearly singular") && text.contains("digits"),
        "{text}"
    );
    // At θ = 1e-3 about 6 digits are lost: still an answer.
    assert!(top
        .accelerations(&[1e-3, 0.0, 0.0], &[0.1, 0.2, 3.0], 0.0)
        .is_ok());
}

/// A fixed step below the time resolution at a large start time (t0 = 1e12, where adjacent f64
/// times are 1.2e-4 apart) gave a NaN velocity; it is an `InvalidOptions` that says why.
#[test]
fn a_fixed_step_below_the_time_resolution_is_invalid_options() {
    let top = HeavyTop {
        i_perp: 1.0,
        i_par: 0.6,
        mgl: 1.0,
    };
    for method in [
        Method::Rk4 { dt: 1e-6 },
        Method::VariationalMidpoint { dt: 1e-6 },
    ] {
        let err = Simulation::new(&top, [1.0, 0.0, 0.0], [0.0, -0.5, 8.0])
            .method(method)
            .start_time(1e12)
            .until(1e12 + 1.0)
            .run()
            .expect_err("dt is below the resolution of t");
        assert!(
            matches!(err, SimulationError::InvalidOptions { .. }),
            "{method:?}: {err}"
        );
        assert!(err.to_string().contains("time resolution"), "{err}");
    }
    // The same step from t0 = 0 is fine.
    assert!(Simulation::new(&top, [1.0, 0.0, 0.0], [0.0, -0.5, 8.0])
        .method(Method::Rk4 { dt: 1e-6 })
        .until(1e-3)
        .run()
        .is_ok());
}

/// `write_csv` into a folder that does not exist creates it; a path that cannot be written
/// names itself in the error.
#[test]
fn write_csv_creates_folders_and_names_the_path_it_cannot_write() {
    let top = HeavyTop {
        i_perp: 1.0,
        i_par: 0.6,
        mgl: 1.0,
    };
    let tr = Simulation::new(&top, [1.0, 0.0, 0.0], [0.0, -0.5, 8.0])
        .until(0.1)
        .run()
        .unwrap();
    let dir = std::env::temp_dir().join(format!("lagrange_csv_{}", std::process::id()));
    let path = dir.join("a/b/top.csv");
    tr.write_csv(&path).expect("folders are created");
    assert!(std::fs::read_to_string(&path)
        .unwrap()
        .starts_with("t,theta"));
    // A file where a folder should be.
    let blocked = dir.join("a/b/top.csv/inside.csv");
    let err = tr.write_csv(&blocked).expect_err("a file is in the way");
    assert!(err.to_string().contains("top.csv"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Recording every step (the default) had no bound: 10⁷ steps of a 3-coordinate system took
/// 862 MB. `max_samples` now bounds every mode, with a typed error and the trajectory so far; a
/// long run can stream its samples to an observer and keep none of them.
#[test]
fn every_mode_is_bounded_by_max_samples_and_long_runs_can_stream() {
    let top = HeavyTop {
        i_perp: 1.0,
        i_par: 0.6,
        mgl: 1.0,
    };
    let sim = || {
        Simulation::new(&top, [1.0, 0.0, 0.0], [0.0, -0.5, 8.0])
            .method(Method::Rk4 { dt: 1e-3 })
            .until(20.0)
    };
    let err = sim()
        .max_samples(1000)
        .run()
        .expect_err("20 001 steps > 1000");
    assert!(
        matches!(
            err,
            SimulationError::MaxSamples {
                max_samples: 1000,
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("observe"), "{err}");
    assert_eq!(err.partial_trajectory::<3>().unwrap().t.len(), 1000);

    let full = sim().run().unwrap();
    let mut seen = 0usize;
    let mut last_t = f64::NAN;
    let streamed = sim()
        .max_samples(10)
        .observe(|s| {
            seen += 1;
            last_t = s.t;
        })
        .keep_samples(false)
        .run()
        .expect("nothing is stored, so max_samples is not reached");
    assert_eq!(seen, full.t.len());
    assert_eq!(last_t, 20.0);
    assert_eq!(streamed.t.len(), 2);
    assert_eq!(streamed.invariants(), full.invariants());
}

/// Numbers in messages are printed for people: the grid time 9 · 0.001 is 0.009000000000000001
/// in f64, and the message says `t = 0.009`.
#[test]
fn messages_print_numbers_to_sensible_precision() {
    let top = HeavyTop {
        i_perp: 1.0,
        i_par: 0.6,
        mgl: 1.0,
    };
    let err = Simulation::new(&top, [1.0, 0.0, 0.0], [0.0, -0.5, 8.0])
        .method(Method::Rk4 { dt: 0.001 })
        .until(1.0)
        .max_steps(9)
        .run()
        .expect_err("9 steps are not enough");
    assert_eq!(err.t(), Some(9.0 * 0.001));
    let text = err.to_string();
    assert!(text.contains("t = 0.009,"), "{text}");
    assert!(!text.contains("0.009000000000000001"), "{text}");
}

/// In jets mode `x.abs().powf(1.5)` was NaN at x = 0 (x^(n−2)·x·x = ∞·0); its value and slope
/// there are 0, as in symbolic mode.
pub struct Cusp {
    pub k: f64,
}

#[lagrangian(mode = "jets")]
impl Cusp {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        0.5 * x_dot.powi(2) - self.k * x.abs().powf(1.5)
    }
}

#[test]
fn a_constant_power_of_zero_is_finite_in_the_jets() {
    let a = Cusp { k: 2.0 }
        .accelerations(&[0.0], &[1.0], 0.0)
        .expect("|x|^1.5 is differentiable at 0");
    assert_eq!(a, [0.0]);
    let a = Cusp { k: 2.0 }.accelerations(&[0.25], &[1.0], 0.0).unwrap();
    assert!((a[0] + 2.0 * 1.5 * 0.5).abs() < 1e-15, "{a:?}");
}

/// `powi` at both ends of `i32`, in both modes: V = x^(i32::MIN) + x^(i32::MAX).
macro_rules! extreme_powers {
    ($name:ident, $($mode:tt)*) => {
        struct $name;
        #[lagrangian $($mode)*]
        impl $name {
            fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
                0.5 * x_dot * x_dot - x.powi(-2147483648) - x.powi(2147483647)
            }
        }
    };
}
extreme_powers!(ExtremePowers,);
extreme_powers!(ExtremePowersJets, (mode = "jets"));

#[test]
fn powi_at_the_ends_of_i32_neither_panics_nor_overflows() {
    // V'(x) = MIN x^(MIN−1) + MAX x^(MAX−1): at x = 1, MIN + MAX = −1; at x = −1 (MIN − 1 odd,
    // MAX − 1 even), −MIN + MAX = 2³² − 1. Exact in f64.
    for (x, want) in [(1.0, 1.0), (-1.0, -4294967295.0)] {
        let s = ExtremePowers.accelerations(&[x], &[0.0], 0.0).unwrap();
        let j = ExtremePowersJets.accelerations(&[x], &[0.0], 0.0).unwrap();
        assert_eq!((s[0], j[0]), (want, want), "x = {x}");
    }
}

/// Symbolic mode at θ = 1e-7: the φ–ψ block's determinant cancels symbolically to I⊥ I∥ sin²θ,
/// so its Cramer solve keeps every digit, and the answer is returned (and equals the closed form),
/// where the jets' numeric elimination has lost 14 digits and says so.
#[test]
fn an_exact_answer_near_the_chart_singularity_is_returned() {
    use crate::support::systems::HeavyTop as SymbolicTop;
    let (ip, ia, m, g, l) = (1.0, 0.6, 1.0, 9.81, 0.1);
    let top = SymbolicTop {
        i_perp: ip,
        i_par: ia,
        m,
        g,
        l,
    };
    for theta in [1e-7, 1e-9] {
        let (q, v) = ([theta, 0.3, -0.2], [0.1, 0.2, 3.0]);
        let got = top.accelerations(&q, &v, 0.0).expect("exact: returned");
        // Closed form: θ̈ I⊥ = I⊥ φ̇² s c − I∥ ω₃ φ̇ s + m g l s; ω̇₃ = 0 and ṗ_φ = 0 give
        // φ̈ = (I∥ ω₃ θ̇ − 2 I⊥ φ̇ θ̇ c) / (I⊥ s) and ψ̈ = φ̇ θ̇ s − φ̈ c.
        let (s, c) = theta.sin_cos();
        let w3 = v[2] + v[1] * c;
        let th = (ip * v[1] * v[1] * s * c - ia * w3 * v[1] * s + m * g * l * s) / ip;
        let ph = (ia * w3 * v[0] - 2.0 * ip * v[1] * v[0] * c) / (ip * s);
        let ps = v[1] * v[0] * s - ph * c;
        for (k, want) in [th, ph, ps].into_iter().enumerate() {
            assert!(
                (got[k] - want).abs() <= 1e-12 * want.abs(),
                "θ = {theta}, q̈[{k}] = {} vs {want}",
                got[k]
            );
        }
        let jets = top.jets().accelerations(&q, &v, 0.0);
        assert!(jets.is_err(), "θ = {theta}: {jets:?}");
    }
}

/// A badly scaled symbolic system takes the generated fast path (pivots judged against their
/// own diagonal entries) and gives the exact answer.
#[lagrangian]
impl SymbolicTwoMasses {
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        3e24 * x_dot * x_dot + 500.0 * y_dot * y_dot + 1e-3 * x_dot * y_dot
            - 0.5 * (x - y) * (x - y)
    }
}
struct SymbolicTwoMasses;

#[test]
fn a_badly_scaled_symbolic_system_is_solved_exactly() {
    let a = SymbolicTwoMasses
        .accelerations(&[0.0, 1.0], &[0.0, 0.0], 0.0)
        .expect("well conditioned");
    // M = [[6e24, 1e-3], [1e-3, 1e3]], f = (1, −1).
    let det = 6e24 * 1e3 - 1e-6;
    let want = [(1e3 * 1.0 + 1e-3) / det, (-6e24 - 1e-3) / det];
    for k in 0..2 {
        assert!(
            (a[k] - want[k]).abs() <= 1e-15 * want[k].abs(),
            "{a:?} vs {want:?}"
        );
    }
}
