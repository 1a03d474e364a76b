//! Symbolic mode (the default, derivatives taken at compile time) against run-time jets: for the
//! heavy top, the non-inertial particle, the gallery systems and pendulum chains, the
//! compile-time derived accelerations, mass matrix, momenta and energy agree with the jets twin
//! (`mode = "jets"`, same body) to 1e-12 relative at random states; the printed equations of the
//! heavy top have the hand-derived structure. Each system is declared once by `twins!`
//! (examples/support/systems.rs), which writes the symbolic and the jets declaration from the same
//! body; the heavy top, Kepler and the chains live in that file, shared with the other tests and
//! benches/symbolic.rs. The compile errors of the symbolic mode ("use jets") are UI cases,
//! tests/ui/symbolic/, run by tests/ui.rs.
#![deny(warnings)]

use lagrange::prelude::*;
use lagrange_examples::twins;

use crate::support::systems::{Chain16, Chain4, HeavyTop, Kepler, RotationTop};

struct Rng(u64);
impl Rng {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let u = (self.0 >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * u
    }
    fn array<const N: usize>(&mut self, lo: f64, hi: f64) -> [f64; N] {
        std::array::from_fn(|_| self.uniform(lo, hi))
    }
}

fn assert_close(what: &str, a: &[f64], b: &[f64], state: &str) {
    let scale = b.iter().fold(1e-300_f64, |s, x| s.max(x.abs()));
    for (k, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= 1e-12 * scale,
            "{what}[{k}]: symbolic {x} vs jets {y} (scale {scale}) at {state}"
        );
    }
}

/// Symbolic and jets agree at one state in everything the trait provides.
fn agree<const N: usize>(
    s: &impl Lagrangian<N>,
    j: &impl Lagrangian<N>,
    q: [f64; N],
    v: [f64; N],
    t: f64,
) {
    let state = format!("q = {q:?}, q̇ = {v:?}, t = {t}");
    let (a, b) = (
        s.accelerations(&q, &v, t).expect("symbolic accelerations"),
        j.accelerations(&q, &v, t).expect("jets accelerations"),
    );
    assert_close("q̈", &a, &b, &state);
    let (ms, mj) = (s.mass_matrix(&q, &v, t), j.mass_matrix(&q, &v, t));
    assert_close("M", ms.as_slice(), mj.as_slice(), &state);
    assert_close("p", &s.momenta(&q, &v, t), &j.momenta(&q, &v, t), &state);
    assert_close("h", &[s.energy(&q, &v, t)], &[j.energy(&q, &v, t)], &state);
    // The fused method (generated straight-line in symbolic mode, one jet pass in jets mode)
    // against the separate ones of the other twin.
    let ((hs, ps), (hj, pj)) = (
        s.energy_and_momenta(&q, &v, t),
        j.energy_and_momenta(&q, &v, t),
    );
    assert_close("p (fused)", &ps, &j.momenta(&q, &v, t), &state);
    assert_close("p (fused, jets)", &pj, &s.momenta(&q, &v, t), &state);
    assert_close("h (fused)", &[hs], &[j.energy(&q, &v, t)], &state);
    assert_close("h (fused, jets)", &[hj], &[s.energy(&q, &v, t)], &state);
    assert_eq!(
        <_ as Lagrangian<N>>::lagrangian(s, &q, &v, t),
        <_ as Lagrangian<N>>::lagrangian(j, &q, &v, t)
    );
}

/// Runs `agree` at `count` random states with q in [lo, hi] and q̇, t in [−2, 2].
fn agree_random<const N: usize>(
    s: &impl Lagrangian<N>,
    j: &impl Lagrangian<N>,
    seed: u64,
    (lo, hi): (f64, f64),
) {
    let mut rng = Rng(seed);
    for _ in 0..40 {
        let q = rng.array(lo, hi);
        let v = rng.array(-2.0, 2.0);
        let t = rng.uniform(-2.0, 2.0);
        agree(s, j, q, v, t);
    }
}

const TOP: HeavyTop = HeavyTop {
    i_perp: 2.0,
    i_par: 0.7,
    m: 1.3,
    g: 9.81,
    l: 0.4,
};

#[test]
fn heavy_top_symbolic_equals_jets() {
    // θ away from the chart singularity sin θ = 0.
    agree_random(&TOP, &TOP.jets(), 1, (0.3, 2.8));
}

/// The top's q̈ in closed form (θ̈ directly, the φ–ψ block by Cramer's rule with
/// det = I∥ I⊥ sin²θ, which has no cancellation as θ → 0).
fn top_closed_form(q: &[f64; 3], v: &[f64; 3]) -> [f64; 3] {
    let HeavyTop {
        i_perp: ip,
        i_par: ia,
        m,
        g,
        l,
    } = TOP;
    let (s, c) = q[0].sin_cos();
    let (td, pd, sd) = (v[0], v[1], v[2]);
    let th = ((ip - ia) * pd * pd * s * c - ia * pd * sd * s + m * g * l * s) / ip;
    let f1 = 2.0 * (ia - ip) * td * pd * s * c + ia * td * sd * s;
    let f2 = ia * td * pd * s;
    let ph = (f1 - c * f2) / (ip * s * s);
    let ps = f2 / ia - c * ph;
    [th, ph, ps]
}

#[test]
fn heavy_top_symbolic_equals_closed_form() {
    let mut rng = Rng(11);
    for _ in 0..20 {
        let q: [f64; 3] = [
            rng.uniform(0.3, 2.8),
            rng.uniform(-3.0, 3.0),
            rng.uniform(-3.0, 3.0),
        ];
        let v: [f64; 3] = rng.array(-2.0, 2.0);
        let a = TOP.accelerations(&q, &v, 0.0).expect("accelerations");
        assert_close("q̈", &a, &top_closed_form(&q, &v), &format!("{q:?} {v:?}"));
    }
}

/// Near the chart singularity (θ → 0, the sleeping top) the φ–ψ block of M is nearly singular:
/// elimination computes its second pivot I∥ − (I∥ cos θ)²/M_φφ as a difference of nearly equal
/// numbers and loses digits like ε/sin²θ (8·10⁻¹⁰ relative at θ = 10⁻⁴ through the run-time
/// jets). The symbolic path solves that decoupled 2×2 block by Cramer's rule with the
/// determinant expanded at compile time, where the terms cancel exactly to I∥ I⊥ sin²θ: full
/// accuracy down to θ = 10⁻⁶ (tolerance 1e-14 relative to the largest component).
#[test]
fn heavy_top_symbolic_keeps_full_accuracy_near_the_singularity() {
    let v = [0.3, -1.1, 2.5];
    for theta in [
        1e-2,
        1e-3,
        1e-4,
        1e-5,
        1e-6,
        -1e-5,
        std::f64::consts::PI - 1e-5,
    ] {
        let q = [theta, 0.2, -0.4];
        let a = TOP.accelerations(&q, &v, 0.0).expect("accelerations");
        let b = top_closed_form(&q, &v);
        let scale = b.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        for i in 0..3 {
            assert!(
                (a[i] - b[i]).abs() <= 1e-14 * scale,
                "θ = {theta:e}, q̈[{i}]: symbolic {} vs closed form {} (scale {scale:e})",
                a[i],
                b[i]
            );
        }
    }
}

#[test]
fn heavy_top_equations_show_the_hand_derived_structure() {
    let lines: Vec<&str> = HeavyTop::EQUATIONS.lines().collect();
    assert_eq!(lines.len(), 3, "{}", HeavyTop::EQUATIONS);
    // θ: I⊥ θ̈ = (I⊥ − I∥) φ̇² sin θ cos θ − I∥ φ̇ ψ̇ sin θ + m g l sin θ
    assert!(
        lines[0].starts_with("theta: i_perp θ\u{308} = "),
        "{}",
        lines[0]
    );
    for term in [
        "(i_perp − i_par) φ\u{307}² sin(θ) cos(θ)",
        "−i_par φ\u{307} ψ\u{307} sin(θ)",
        "+ m g l sin(θ)",
    ] {
        assert!(lines[0].contains(term), "{term} in {}", lines[0]);
    }
    // φ: d/dt [I⊥ φ̇ sin²θ + I∥ (ψ̇ + φ̇ cos θ) cos θ] = 0, expanded.
    assert!(
        lines[1].starts_with(
            "phi: i_perp φ\u{308} sin²(θ) + i_par φ\u{308} cos²(θ) + i_par ψ\u{308} cos(θ) = "
        ),
        "{}",
        lines[1]
    );
    assert!(lines[1].contains("2 (i_par − i_perp) θ\u{307} φ\u{307} sin(θ) cos(θ)"));
    // ψ: d/dt [I∥ (ψ̇ + φ̇ cos θ)] = 0, eq. (93).
    assert_eq!(
        lines[2],
        "psi: i_par φ\u{308} cos(θ) + i_par ψ\u{308} = i_par θ\u{307} φ\u{307} sin(θ)"
    );
    assert!(HeavyTop::EQUATIONS_LATEX.contains("i_{\\mathrm{perp}} \\ddot{\\theta} = "));
}

twins! {
    NonInertial, NonInertialJets {
        m: f64, k: f64, w: f64, w1: f64, nu: f64, a: f64, v0: Vector3<f64>, gravity: Vector3<f64>
    }
    fn lagrangian(&self, (r, r_dot): Coord3, t: Time) -> Scalar {
        // L = m (ṙ + v₀(t) + Ω(t) × r)² / 2 − U(r)
        let v0 = self.v0 * (self.nu * t).cos();
        let omega = Vector3::new(self.w1 * t.sin(), 0.2 * self.w1, self.w * (1.0 + 0.1 * t));
        let v = r_dot + v0 + omega.cross(&r);
        let u = 0.5 * self.k * r.norm_squared() - self.m * self.gravity.dot(&r)
            + self.a / (1.0 + r.norm_squared()).sqrt();
        self.m / 2.0 * v.norm_squared() - u
    }
}

#[test]
fn non_inertial_particle_symbolic_equals_jets() {
    let s = NonInertial {
        m: 1.7,
        k: 3.0,
        w: 0.9,
        w1: 0.4,
        nu: 1.3,
        a: 0.6,
        v0: Vector3::new(0.3, -0.2, 0.5),
        gravity: Vector3::new(0.0, 0.0, -9.81),
    };
    agree_random(&s, &s.jets(), 2, (-2.0, 2.0));
    const { assert!(!<NonInertial as Lagrangian<3>>::AUTONOMOUS) };
}

twins! {
    DoublePendulum, DoublePendulumJets { m1: f64, m2: f64, l1: f64, l2: f64, g: f64 }
    fn lagrangian(&self, (theta1, theta1_dot): Coord, (theta2, theta2_dot): Coord) -> Scalar {
        let v1 = self.l1 * theta1_dot;
        let v2 = self.l2 * theta2_dot;
        (self.m1 + self.m2) / 2.0 * v1.powi(2)
            + self.m2 / 2.0 * v2.powi(2)
            + self.m2 * v1 * v2 * (theta1 - theta2).cos()
            + (self.m1 + self.m2) * self.g * self.l1 * theta1.cos()
            + self.m2 * self.g * self.l2 * theta2.cos()
    }
}

twins! {
    SphericalPendulum, SphericalPendulumJets { m: f64, l: f64, g: f64 }
    fn lagrangian(&self, (theta, theta_dot): Coord, (_phi, phi_dot): Coord) -> Scalar {
        self.m * self.l.powi(2) / 2.0 * (theta_dot.powi(2) + (theta.sin() * phi_dot).powi(2))
            + self.m * self.g * self.l * theta.cos()
    }
}

twins! {
    Charged, ChargedJets { m: f64, q: f64, c: f64, b: Vector3<f64> }
    fn lagrangian(&self, (r, r_dot): Coord3) -> Scalar {
        // A = B × r / 2 + ∇(c x y): the gauge term must drop out of the equations.
        let a = 0.5 * self.b.cross(&r);
        let gauge = Vector3::new(self.c * r.y, self.c * r.x, 0.0);
        self.m / 2.0 * r_dot.norm_squared() + self.q * r_dot.dot(&(a + gauge))
    }
}

twins! {
    DrivenPendulum, DrivenPendulumJets { m: f64, l: f64, g: f64, a: f64, w: f64 }
    fn lagrangian(&self, (theta, theta_dot): Coord, t: Time) -> Scalar {
        // Pivot at height a cos ωt.
        let (s, c) = theta.sin_cos();
        let xd = self.l * c * theta_dot;
        let yd = -self.a * self.w * (self.w * t).sin() + self.l * s * theta_dot;
        let y = self.a * (self.w * t).cos() - self.l * c;
        self.m / 2.0 * (xd * xd + yd * yd) - self.m * self.g * y
    }
}

twins! {
    ElasticPendulum, ElasticPendulumJets { m: f64, k: f64, l0: f64, g: f64 }
    fn lagrangian(&self, (r, r_dot): Coord, (theta, theta_dot): Coord) -> Scalar {
        self.m / 2.0 * (r_dot.powi(2) + (r * theta_dot).powi(2)) + self.m * self.g * r * theta.cos()
            - self.k / 2.0 * (r - self.l0).powi(2)
    }
}

#[test]
fn gallery_symbolic_equals_jets() {
    let dp = DoublePendulum {
        m1: 1.2,
        m2: 0.8,
        l1: 1.1,
        l2: 0.7,
        g: 9.81,
    };
    agree_random(&dp, &dp.jets(), 3, (-3.0, 3.0));
    let sp = SphericalPendulum {
        m: 0.9,
        l: 1.4,
        g: 9.81,
    };
    agree_random(&sp, &sp.jets(), 4, (0.3, 2.8));
    let kp = Kepler { m: 2.0, k: 5.0 };
    agree_random(&kp, &kp.jets(), 5, (0.5, 3.0));
    let ch = Charged {
        m: 1.3,
        q: -0.7,
        c: 2.5,
        b: Vector3::new(0.2, -0.4, 1.5),
    };
    agree_random(&ch, &ch.jets(), 6, (-2.0, 2.0));
    let dr = DrivenPendulum {
        m: 1.0,
        l: 0.8,
        g: 9.81,
        a: 0.1,
        w: 30.0,
    };
    agree_random(&dr, &dr.jets(), 7, (-3.0, 3.0));
    let el = ElasticPendulum {
        m: 0.5,
        k: 20.0,
        l0: 1.0,
        g: 9.81,
    };
    agree_random(&el, &el.jets(), 8, (0.5, 2.0));
}

#[test]
fn charged_particle_gauge_term_drops_out() {
    // m r̈ = q ṙ × B, whatever the gauge constant c.
    let ch = Charged {
        m: 1.3,
        q: -0.7,
        c: 2.5,
        b: Vector3::new(0.2, -0.4, 1.5),
    };
    let v = [0.3, -1.2, 0.8];
    let a = ch
        .accelerations(&[0.4, 0.1, -0.3], &v, 0.0)
        .expect("accelerations");
    let f = Vector3::from(v).cross(&ch.b) * (ch.q / ch.m);
    assert_close("q̈", &a, f.as_slice(), "charged");
    assert!(!Charged::EQUATIONS.contains('c'), "{}", Charged::EQUATIONS);
}

/// Hand-derived chain equations: M_ij = m l² (N − max(i, j)) cos(θᵢ − θⱼ),
/// f_i = −m l² Σⱼ (N − max(i, j)) sin(θᵢ − θⱼ) θ̇ⱼ² − m g l (N − i) sin θᵢ.
fn chain_closed_form<const N: usize>(
    m: f64,
    l: f64,
    g: f64,
    q: &[f64; N],
    v: &[f64; N],
) -> [f64; N] {
    let mut mm = [[0.0; N]; N];
    let mut f = [0.0; N];
    for i in 0..N {
        f[i] = -m * g * l * (N - i) as f64 * q[i].sin();
        for j in 0..N {
            let w = m * l * l * (N - i.max(j)) as f64;
            mm[i][j] = w * (q[i] - q[j]).cos();
            f[i] -= w * (q[i] - q[j]).sin() * v[j] * v[j];
        }
    }
    lagrange::__private::solve_mass_matrix(&mm, &f, ["q"; N], q, v, 0.0).expect("solve")
}

#[test]
fn pendulum_chains_symbolic_equal_jets_and_closed_form() {
    let c4 = Chain4 {
        m: 0.7,
        l: 0.9,
        g: 9.81,
    };
    agree_random(&c4, &c4.jets(), 9, (-3.0, 3.0));
    let c16 = Chain16 {
        m: 0.7,
        l: 0.9,
        g: 9.81,
    };
    let mut rng = Rng(10);
    for _ in 0..5 {
        let q: [f64; 16] = rng.array(-1.0, 1.0);
        let v: [f64; 16] = rng.array(-1.0, 1.0);
        agree(&c16, &c16.jets(), q, v, 0.0);
        let a = c16.accelerations(&q, &v, 0.0).expect("accelerations");
        // The chain's M is worse conditioned at N = 16: compare with a looser, conditioning-aware bound.
        let b = chain_closed_form(0.7, 0.9, 9.81, &q, &v);
        let scale = b.iter().fold(0.0_f64, |s, x| s.max(x.abs()));
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() <= 1e-9 * scale, "{x} vs {y}");
        }
    }
}

#[test]
fn symbolic_mode_is_the_default_and_documents_equations() {
    assert!(
        Kepler::EQUATIONS.starts_with("r: m r\u{308} = "),
        "{}",
        Kepler::EQUATIONS
    );
    assert!(Kepler::EQUATIONS.contains("k/r²"), "{}", Kepler::EQUATIONS);
}

twins! {
    /// `if` on constants: an `if` expression, an `if`/`else if` statement that assigns a
    /// local, and a vector-valued `if`; the conditions use only `self` fields and literals.
    Switched, SwitchedJets { m: f64, k: f64, c: f64 }
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord, t: Time) -> Scalar {
        let f = if self.k > 0.0 {
            self.k * x * x
        } else {
            0.0 * x
        };
        let mut lag = self.m / 2.0 * (x_dot * x_dot + y_dot * y_dot) - f;
        if self.c > 1.0 {
            lag += self.c * x_dot * y.sin() * t.cos();
        } else if self.c > 0.0 {
            lag -= self.c * x * y * y;
        }
        let w = if self.k > 0.0 {
            Vector3::new(x, y, 1.0)
        } else {
            Vector3::new(y, 0.5 * x, 2.0)
        };
        lag - 0.1 * w.norm_squared() * (1.0 + x_dot * x_dot)
    }
}

#[test]
fn constant_if_symbolic_equals_jets_on_every_branch() {
    // k > 0 and k ≤ 0; c > 1, 0 < c ≤ 1 and c ≤ 0: every branch is taken.
    let mut seed = 20;
    for k in [1.5, -1.0] {
        for c in [2.0, 0.5, -1.0] {
            let s = Switched { m: 1.3, k, c };
            let j = SwitchedJets { m: 1.3, k, c };
            agree_random(&s, &j, seed, (-1.5, 1.5));
            seed += 1;
        }
    }
    // The branches really differ: the spring force −2k x is there only for k > 0.
    let (q, v) = ([0.7, 0.0], [0.0, 0.0]);
    let on = Switched {
        m: 1.0,
        k: 3.0,
        c: -1.0,
    };
    let off = Switched {
        m: 1.0,
        k: -3.0,
        c: -1.0,
    };
    let (a_on, a_off) = (
        on.accelerations(&q, &v, 0.0).unwrap(),
        off.accelerations(&q, &v, 0.0).unwrap(),
    );
    assert!((a_on[0] - a_off[0]).abs() > 1.0, "{a_on:?} vs {a_off:?}");
    // The equations show the condition and both branches.
    assert!(
        Switched::EQUATIONS.contains(" if k > 0.0 else "),
        "{}",
        Switched::EQUATIONS
    );
    assert!(
        Switched::EQUATIONS.contains(" if c > 1.0 else "),
        "{}",
        Switched::EQUATIONS
    );
}

twins! {
    /// `Scalar::constant`, `Scalar::from` and `<Scalar as From<f64>>::from` on constants.
    Converted, ConvertedJets { k: f64 }
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        let half = Scalar::constant(0.5);
        let k = <Scalar as From<f64>>::from(self.k);
        half * x_dot * x_dot - Scalar::from(2.0) * k * x.cos()
    }
}

#[test]
fn scalar_conversions_of_constants_symbolic_equals_jets() {
    agree_random(
        &Converted { k: 1.7 },
        &ConvertedJets { k: 1.7 },
        40,
        (-3.0, 3.0),
    );
    // ∂L/∂x = 2k sin x, so ẍ = 2k sin x.
    let a = Converted { k: 1.7 }
        .accelerations(&[0.3], &[0.0], 0.0)
        .unwrap();
    assert!((a[0] - 2.0 * 1.7 * 0.3_f64.sin()).abs() < 1e-14);
}

twins! {
    /// q̈ = (k, k) for a huge k: the sum of q̈ overflows while every component is finite.
    Pushed, PushedJets { k: f64 }
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * (x_dot * x_dot + y_dot * y_dot) + self.k * (x + y)
    }
}

twins! {
    /// An indefinite (but regular) M = diag(1, −1): no LDLᵀ pivot is positive.
    Indefinite, IndefiniteJets { k: f64 }
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * (x_dot * x_dot - y_dot * y_dot) - 0.5 * self.k * (x * x + y * y)
    }
}

/// Every way off the generated fast path ends where the runtime's solve would: a singular M is
/// `SingularMassMatrix`, a NaN state is `NonFinite`, an indefinite M is solved by the pivoting
/// fallback, and finite accelerations whose sum overflows (the fast path's one finiteness test)
/// are returned as they are.
#[test]
fn off_the_fast_path_the_symbolic_code_agrees_with_the_runtime_solve() {
    let (q, v) = ([0.0, 0.2, -0.4], [0.3, -1.1, 2.5]);
    assert!(matches!(
        TOP.accelerations(&q, &v, 0.0),
        Err(DynamicsError::SingularMassMatrix { .. })
    ));
    assert!(matches!(
        TOP.accelerations(&[f64::NAN, 0.2, -0.4], &v, 0.0),
        Err(DynamicsError::NonFinite { .. })
    ));
    let ind = Indefinite { k: 2.0 };
    let a = ind
        .accelerations(&[1.0, 3.0], &[0.0, 0.0], 0.0)
        .expect("regular M");
    assert_eq!(a, [-2.0, 6.0]);
    assert_eq!(
        a,
        ind.jets()
            .accelerations(&[1.0, 3.0], &[0.0, 0.0], 0.0)
            .unwrap()
    );
    let k = 1e308;
    let p = Pushed { k };
    assert_eq!(
        p.accelerations(&[0.0, 0.0], &[0.0, 0.0], 0.0).unwrap(),
        [k, k]
    );
    assert_eq!(
        p.jets()
            .accelerations(&[0.0, 0.0], &[0.0, 0.0], 0.0)
            .unwrap(),
        [k, k]
    );
}

/// An oscillator x written with a second coordinate ψ that enters L only through identities: the
/// velocity is rotated by ψ and the potential carries sin²ψ + cos²ψ. L is ½ m ẋ² + ½ ψ̇² − ½ k x²
/// in disguise, so ψ is cyclic (its momentum ψ̇ conserved) although the body names it.
#[derive(Debug, Clone, Copy)]
pub struct HiddenAngle {
    m: f64,
    k: f64,
}

#[lagrangian]
impl HiddenAngle {
    fn lagrangian(&self, (x, x_dot): Coord, (psi, psi_dot): Coord) -> Scalar {
        let (s, c) = psi.sin_cos();
        0.5 * self.m * ((c * x_dot).powi(2) + (s * x_dot).powi(2)) + 0.5 * psi_dot.powi(2)
            - 0.5 * self.k * x * x * (s * s + c * c)
    }
}

/// The same body with run-time jets: the flags come from the names there (no simplification at
/// run time), so ψ is not flagged; the motion is the same.
#[derive(Debug, Clone, Copy)]
pub struct HiddenAngleJets {
    m: f64,
    k: f64,
}

#[lagrangian(mode = "jets")]
impl HiddenAngleJets {
    fn lagrangian(&self, (x, x_dot): Coord, (psi, psi_dot): Coord) -> Scalar {
        let (s, c) = psi.sin_cos();
        0.5 * self.m * ((c * x_dot).powi(2) + (s * x_dot).powi(2)) + 0.5 * psi_dot.powi(2)
            - 0.5 * self.k * x * x * (s * s + c * c)
    }
}

#[test]
fn a_coordinate_that_cancels_through_an_identity_is_cyclic() {
    assert_eq!(<HiddenAngle as Lagrangian<2>>::CYCLIC, [false, true]);
    assert_eq!(
        <HiddenAngle as Lagrangian<2>>::MOMENTUM_CONSERVED,
        [false, true]
    );
    const { assert!(<HiddenAngle as Lagrangian<2>>::AUTONOMOUS) };
    assert_eq!(<HiddenAngleJets as Lagrangian<2>>::CYCLIC, [false, false]);
    let (m, k) = (2.0, 8.0);
    let sys = HiddenAngle { m, k };
    let jets = HiddenAngleJets { m, k };
    let mut rng = Rng(7);
    for _ in 0..100 {
        let (q, v) = (rng.array::<2>(-3.0, 3.0), rng.array::<2>(-3.0, 3.0));
        let a = sys.accelerations(&q, &v, 0.0).unwrap();
        let want = [-k / m * q[0], 0.0];
        let aj = jets.accelerations(&q, &v, 0.0).unwrap();
        for i in 0..2 {
            assert!(
                (a[i] - want[i]).abs() <= 1e-12 * (1.0 + want[i].abs()),
                "{a:?} vs {want:?}"
            );
            assert!((aj[i] - want[i]).abs() <= 1e-12 * (1.0 + want[i].abs()));
        }
    }
    // A run accepts the declaration (its check shifts ψ and compares q̈) and reports p_ψ as
    // conserved; the oscillator's phase after t = π/2 (ω = 2) is exact to the tolerance.
    let tr = Simulation::new(&sys, [1.0, 0.3], [0.0, 0.7])
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-14,
        })
        .until(std::f64::consts::FRAC_PI_2)
        .run()
        .unwrap();
    let inv = tr.invariants();
    let p_psi = inv.momenta[1].expect("ψ's momentum is reported conserved");
    assert!(p_psi.max_abs <= 1e-13, "{p_psi:?}");
    assert!(inv.momenta[0].is_none());
    let last = tr.q.last().unwrap();
    assert!((last[0] - (-1.0)).abs() <= 1e-9, "x(π/2) = {}", last[0]);
    assert!((last[1] - (0.3 + 0.7 * std::f64::consts::FRAC_PI_2)).abs() <= 1e-9);
}

#[test]
fn heavy_top_from_its_angular_velocity_is_the_heavy_top() {
    assert_eq!(<RotationTop as Lagrangian<3>>::CYCLIC, [false, true, true]);
    // The printed equations are those of eq. 92 written by hand (the same parameters): no ψ, no
    // sin² + cos² pair.
    let eq = RotationTop::EQUATIONS;
    assert_eq!(eq, lagrange_examples::bench_top::MacroTop::EQUATIONS);
    assert!(!eq.contains("(ψ)"), "{eq}");
    let (i_perp, i_par, m, g, l) = (1.3, 0.7, 0.9, 9.81, 0.4);
    let top = RotationTop {
        i_perp,
        i_par,
        mgl: m * g * l,
    };
    let hand = HeavyTop {
        i_perp,
        i_par,
        m,
        g,
        l,
    };
    let mut rng = Rng(11);
    for _ in 0..1000 {
        let mut q = rng.array::<3>(-3.0, 3.0);
        q[0] = rng.uniform(0.2, 2.9); // away from sin θ = 0
        let v = rng.array::<3>(-3.0, 3.0);
        let a = top.accelerations(&q, &v, 0.0).unwrap();
        let want = hand.accelerations(&q, &v, 0.0).unwrap();
        for i in 0..3 {
            assert!(
                (a[i] - want[i]).abs() <= 1e-12 * (1.0 + want[i].abs()),
                "q = {q:?}, q̇ = {v:?}: {a:?} vs {want:?}"
            );
        }
    }
}
