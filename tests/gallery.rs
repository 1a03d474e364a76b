//! Gallery of `#[lagrangian]` systems, each against equations of motion derived by hand
//! and written out in closed form below, at ≥ 1000 random states to 1e-12 relative, plus the
//! COORDINATES / CYCLIC / AUTONOMOUS constants the macro fills in.
//!
//! The bodies deliberately exercise what the macro contract promises: `let` with tuple patterns,
//! blocks, `if` on an `f64` field, `match` on a non-numeric field, a helper generic over
//! `S: Scalar`, `2.0 * x` and `x / 2.0`, `Vector3<f64>` fields as receiver, argument and factor,
//! doc comments and `#[allow(...)]` on the function.
//!
//! So these declarations are variants on purpose: plain bodies of the same systems are declared
//! once as symbolic/jets twins in tests/symbolic.rs, and Kepler, whose body here exercises
//! nothing special, is the shared declaration of examples/support/systems.rs.

use lagrange::prelude::*;

use crate::support::systems::Kepler;
use crate::support::Rng;

// ---------------------------------------------------------------------------------------------
// Test support
// ---------------------------------------------------------------------------------------------

const STATES: usize = 2000;
const REL: f64 = 1e-12;

/// |got − want| ≤ rel · max(1, max |want|), component-wise.
fn assert_close(got: &[f64], want: &[f64], rel: f64, ctx: &str) {
    assert_eq!(got.len(), want.len());
    let scale = want.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    for (g, w) in got.iter().zip(want) {
        assert!(
            (g - w).abs() <= rel * scale,
            "{ctx}: got {got:?}, want {want:?}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 1. Double pendulum
// ---------------------------------------------------------------------------------------------

/// Two point masses on massless rods; angles from the downward vertical.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DoublePendulum {
    pub m1: f64,
    pub m2: f64,
    pub l1: f64,
    pub l2: f64,
    pub g: f64,
}

#[lagrangian]
impl DoublePendulum {
    /// L = (m₁+m₂) l₁² θ̇₁²/2 + m₂ l₂² θ̇₂²/2 + m₂ l₁ l₂ θ̇₁ θ̇₂ cos(θ₁−θ₂)
    ///     + (m₁+m₂) g l₁ cos θ₁ + m₂ g l₂ cos θ₂.
    #[allow(clippy::many_single_char_names)]
    fn lagrangian(&self, (th1, th1_dot): Coord, (th2, th2_dot): Coord) -> Scalar {
        let (m1, m2, l1, l2, g) = (self.m1, self.m2, self.l1, self.l2, self.g);
        let (_, c12) = (th1 - th2).sin_cos();
        let kinetic = (m1 + m2) * l1 * l1 * th1_dot.powi(2) / 2.0
            + m2 * l2 * l2 / 2.0 * th2_dot.powi(2)
            + m2 * l1 * l2 * th1_dot * th2_dot * c12;
        let potential = -(m1 + m2) * g * l1 * th1.cos() - m2 * g * l2 * th2.cos();
        kinetic - potential
    }
}

/// Hand-derived (M q̈ = f, 2×2, solved in closed form):
/// θ̈₁ = [−g(2m₁+m₂) sin θ₁ − m₂ g sin(θ₁−2θ₂) − 2 sin Δ m₂ (θ̇₂² l₂ + θ̇₁² l₁ cos Δ)] / (l₁ D),
/// θ̈₂ = [2 sin Δ (θ̇₁² l₁ (m₁+m₂) + g (m₁+m₂) cos θ₁ + θ̇₂² l₂ m₂ cos Δ)] / (l₂ D),
/// Δ = θ₁ − θ₂, D = 2m₁ + m₂ − m₂ cos 2Δ.
pub fn double_pendulum_closed_form(p: &DoublePendulum, q: &[f64; 2], qd: &[f64; 2]) -> [f64; 2] {
    let DoublePendulum { m1, m2, l1, l2, g } = *p;
    let (t1, t2, w1, w2) = (q[0], q[1], qd[0], qd[1]);
    let d = t1 - t2;
    let den = 2.0 * m1 + m2 - m2 * (2.0 * d).cos();
    let a1 = (-g * (2.0 * m1 + m2) * t1.sin()
        - m2 * g * (t1 - 2.0 * t2).sin()
        - 2.0 * d.sin() * m2 * (w2 * w2 * l2 + w1 * w1 * l1 * d.cos()))
        / (l1 * den);
    let a2 = 2.0
        * d.sin()
        * (w1 * w1 * l1 * (m1 + m2) + g * (m1 + m2) * t1.cos() + w2 * w2 * l2 * m2 * d.cos())
        / (l2 * den);
    [a1, a2]
}

#[test]
fn double_pendulum_constants() {
    assert_eq!(
        <DoublePendulum as Lagrangian<2>>::COORDINATES,
        ["th1", "th2"]
    );
    assert_eq!(<DoublePendulum as Lagrangian<2>>::CYCLIC, [false, false]);
    const { assert!(<DoublePendulum as Lagrangian<2>>::AUTONOMOUS) };
}

#[test]
fn double_pendulum_matches_closed_form() {
    let mut rng = Rng(0x0bad_cafe_1234_5678);
    for _ in 0..STATES {
        let p = DoublePendulum {
            m1: rng.uniform(0.1, 3.0),
            m2: rng.uniform(0.1, 3.0),
            l1: rng.uniform(0.2, 2.0),
            l2: rng.uniform(0.2, 2.0),
            g: rng.uniform(1.0, 20.0),
        };
        let q = [rng.uniform(-7.0, 7.0), rng.uniform(-7.0, 7.0)];
        let qd = [rng.uniform(-8.0, 8.0), rng.uniform(-8.0, 8.0)];
        let got = p.accelerations(&q, &qd, 0.0).unwrap();
        let want = double_pendulum_closed_form(&p, &q, &qd);
        assert_close(&got, &want, REL, "double pendulum");
    }
}

#[test]
fn double_pendulum_energy_is_t_plus_v() {
    let p = DoublePendulum {
        m1: 1.2,
        m2: 0.7,
        l1: 1.1,
        l2: 0.6,
        g: 9.81,
    };
    let (q, qd): ([f64; 2], [f64; 2]) = ([0.4, -1.3], [2.0, -0.5]);
    let t = 0.5 * (p.m1 + p.m2) * p.l1.powi(2) * qd[0].powi(2)
        + 0.5 * p.m2 * p.l2.powi(2) * qd[1].powi(2)
        + p.m2 * p.l1 * p.l2 * qd[0] * qd[1] * (q[0] - q[1]).cos();
    let v = -(p.m1 + p.m2) * p.g * p.l1 * q[0].cos() - p.m2 * p.g * p.l2 * q[1].cos();
    let e = p.energy(&q, &qd, 0.0);
    assert!(
        (e - (t + v)).abs() < 1e-13 * (t.abs() + v.abs()),
        "{e} vs {}",
        t + v
    );
}

// ---------------------------------------------------------------------------------------------
// 2. Spherical pendulum (φ cyclic) — kinetic energy through a generic helper
// ---------------------------------------------------------------------------------------------

/// A point mass on a rod of length `l` free to swing in 3-D; θ from the downward vertical.
#[derive(Debug, Clone)]
pub struct SphericalPendulum {
    pub m: f64,
    pub l: f64,
    pub g: f64,
}

/// |v|² on a sphere of unit radius: θ̇² + sin²θ φ̇². Generic, so the macro body may call it.
fn sphere_speed_sq<S: Scalar>(theta: S, theta_dot: S, phi_dot: S) -> S {
    let s = theta.sin();
    theta_dot * theta_dot + s * s * phi_dot * phi_dot
}

// This body calls a helper generic over `S: Scalar`: the symbolic mode (the default) rejects that with a
// pointed error, so it uses the run-time jets.
#[lagrangian(mode = "jets")]
impl SphericalPendulum {
    fn lagrangian(&self, (theta, theta_dot): Coord, (phi, phi_dot): Coord) -> Scalar {
        let ml2 = self.m * self.l.powi(2);
        ml2 / 2.0 * sphere_speed_sq(theta, theta_dot, phi_dot)
            + self.m * self.g * self.l * theta.cos()
    }
}

#[test]
fn spherical_pendulum_constants() {
    assert_eq!(
        <SphericalPendulum as Lagrangian<2>>::COORDINATES,
        ["theta", "phi"]
    );
    assert_eq!(<SphericalPendulum as Lagrangian<2>>::CYCLIC, [false, true]);
    const { assert!(<SphericalPendulum as Lagrangian<2>>::AUTONOMOUS) };
}

#[test]
fn spherical_pendulum_matches_closed_form() {
    // θ̈ = sinθ cosθ φ̇² − (g/l) sinθ;   φ̈ = −2 θ̇ φ̇ cosθ / sinθ.
    let mut rng = Rng(77);
    for _ in 0..STATES {
        let p = SphericalPendulum {
            m: rng.uniform(0.1, 5.0),
            l: rng.uniform(0.1, 3.0),
            g: rng.uniform(0.0, 20.0),
        };
        let q = [rng.uniform(0.05, 3.09), rng.uniform(-7.0, 7.0)];
        let qd = [rng.uniform(-6.0, 6.0), rng.uniform(-6.0, 6.0)];
        let (s, c) = q[0].sin_cos();
        let want = [
            s * c * qd[1] * qd[1] - p.g / p.l * s,
            -2.0 * qd[0] * qd[1] * c / s,
        ];
        let got = p.accelerations(&q, &qd, 0.0).unwrap();
        assert_close(&got, &want, REL, "spherical pendulum");
        // p_φ = m l² sin²θ φ̇ is the conserved momentum of the cyclic coordinate.
        let p_phi = p.m * p.l * p.l * s * s * qd[1];
        let mom = p.momenta(&q, &qd, 0.0);
        assert!((mom[1] - p_phi).abs() <= 1e-13 * p_phi.abs().max(1.0));
    }
}

// ---------------------------------------------------------------------------------------------
// 3. Kepler problem in polar coordinates (φ cyclic)
// ---------------------------------------------------------------------------------------------

// `Kepler`, a body of mass `m` in the potential −k/r, is the shared declaration of
// examples/support/systems.rs (the same system tests/symbolic.rs checks against its jets twin).

#[test]
fn kepler_constants() {
    assert_eq!(<Kepler as Lagrangian<2>>::COORDINATES, ["r", "phi"]);
    assert_eq!(<Kepler as Lagrangian<2>>::CYCLIC, [false, true]);
    const { assert!(<Kepler as Lagrangian<2>>::AUTONOMOUS) };
}

#[test]
fn kepler_matches_closed_form_and_conserves_areal_velocity() {
    // r̈ = r φ̇² − k/(m r²);  φ̈ = −2 ṙ φ̇ / r;  so d(r²φ̇)/dt = 2 r ṙ φ̇ + r² φ̈ = 0.
    let mut rng = Rng(31337);
    for _ in 0..STATES {
        let sys = Kepler {
            m: rng.uniform(0.1, 5.0),
            k: rng.uniform(0.1, 10.0),
        };
        let q = [rng.uniform(0.2, 5.0), rng.uniform(-7.0, 7.0)];
        let qd = [rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0)];
        let (r, rd, phd) = (q[0], qd[0], qd[1]);
        let want = [r * phd * phd - sys.k / (sys.m * r * r), -2.0 * rd * phd / r];
        let got = sys.accelerations(&q, &qd, 0.0).unwrap();
        assert_close(&got, &want, REL, "kepler");
        let areal_rate = 2.0 * r * rd * phd + r * r * got[1];
        assert!(
            areal_rate.abs() <= 1e-12 * (2.0 * r * rd * phd).abs().max(1.0),
            "d(r²φ̇)/dt = {areal_rate}"
        );
        let mom = sys.momenta(&q, &qd, 0.0);
        assert!(
            (mom[1] - sys.m * r * r * phd).abs() <= 1e-13 * (sys.m * r * r * phd).abs().max(1.0)
        );
        let e = sys.m / 2.0 * (rd * rd + r * r * phd * phd) - sys.k / r;
        assert!((sys.energy(&q, &qd, 0.0) - e).abs() <= 1e-13 * e.abs().max(1.0));
    }
}

#[test]
fn kepler_orbit_closes_after_one_period_with_constant_angular_momentum() {
    // Start at periapsis (ṙ = 0) with φ̇ above the circular rate: an ellipse of energy E < 0,
    // semi-major axis a = −k/(2E), period T = 2π √(m a³ / k) (Kepler's third law).
    let sys = Kepler { m: 1.5, k: 4.0 };
    let (r0, phid0): (f64, f64) = (1.0, 2.0);
    let e = sys.m / 2.0 * (r0 * phid0).powi(2) - sys.k / r0;
    assert!(e < 0.0);
    let a = -sys.k / (2.0 * e);
    let period = 2.0 * std::f64::consts::PI * (sys.m * a.powi(3) / sys.k).sqrt();
    let traj = Simulation::new(&sys, [r0, 0.0], [0.0, phid0])
        .method(Method::Dop853 {
            rtol: 1e-11,
            atol: 1e-12,
        })
        .until(2.5 * period)
        .sample_every(period / 50.0)
        .event(Event::zero_crossing("periapsis", |_t, _q, qd: &[f64; 2]| qd[0]).rising())
        .run()
        .unwrap();
    let hits: Vec<f64> = traj.events.iter().map(|h| h.t).collect();
    assert_eq!(hits.len(), 2, "periapsis passages: {hits:?}");
    for (n, t) in hits.iter().enumerate() {
        let want = period * (n + 1) as f64;
        assert!(
            (t - want).abs() < 1e-8 * want,
            "passage {n}: t = {t}, T = {period}"
        );
    }
    // φ advanced by exactly 2π per period, r returned to r0.
    let h = &traj.events[0];
    assert!(
        (h.q[1] - 2.0 * std::f64::consts::PI).abs() < 1e-8,
        "{:?}",
        h.q
    );
    assert!((h.q[0] - r0).abs() < 1e-8, "{:?}", h.q);
    // Areal velocity r²φ̇/2 (∝ the cyclic momentum) is constant along the samples.
    let areal0 = r0 * r0 * phid0 / 2.0;
    for (q, qd) in traj.q.iter().zip(&traj.qdot) {
        let areal = q[0] * q[0] * qd[1] / 2.0;
        assert!((areal - areal0).abs() < 1e-9 * areal0, "r²φ̇/2 = {areal}");
    }
}

// ---------------------------------------------------------------------------------------------
// 4. Charged particle in uniform B (through a vector potential) and uniform E; gauge terms
// ---------------------------------------------------------------------------------------------

/// Which gauge function χ(r) is added to L as λ ∇χ·ṙ (a total time derivative λ dχ/dt).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Gauge {
    /// χ = 0.
    None,
    /// χ = x y z.
    Xyz,
    /// χ = sin(x) y.
    SinXTimesY,
    /// χ = (c·r)²/2 with c = `ChargedParticle::c`.
    Quadratic,
}

/// L = m|ṙ|²/2 + q ṙ·A(r) + q E·r + λ ∇χ(r)·ṙ, with A = B×r/2 (symmetric gauge).
#[derive(Debug, Clone)]
pub struct ChargedParticle {
    pub m: f64,
    pub q: f64,
    pub b: Vector3<f64>,
    pub e: Vector3<f64>,
    pub gauge: Gauge,
    pub lambda: f64,
    pub c: Vector3<f64>,
}

// This body uses `match` and `if` on its parameters: the symbolic mode (the default) rejects that with a
// pointed error, so it uses the run-time jets.
#[lagrangian(mode = "jets")]
impl ChargedParticle {
    fn lagrangian(&self, (r, r_dot): Coord3) -> Scalar {
        let a = self.b.cross(&r) / 2.0;
        let grad_chi = match self.gauge {
            Gauge::None => Vector3::new(0.0, 0.0, 0.0),
            Gauge::Xyz => Vector3::new(r.y * r.z, r.x * r.z, r.x * r.y),
            Gauge::SinXTimesY => Vector3::new(r.x.cos() * r.y, r.x.sin(), 0.0),
            Gauge::Quadratic => self.c * self.c.dot(&r),
        };
        let gauge_term = if self.lambda != 0.0 {
            self.lambda * grad_chi.dot(&r_dot)
        } else {
            0.0
        };
        self.m / 2.0 * r_dot.norm_squared()
            + self.q * r_dot.dot(&a)
            + (self.e * self.q).dot(&r)
            + gauge_term
    }
}

fn random_particle(rng: &mut Rng, gauge: Gauge) -> ChargedParticle {
    ChargedParticle {
        m: rng.uniform(0.1, 5.0),
        q: rng.uniform(-3.0, 3.0),
        b: rng.vec3(-2.0, 2.0),
        e: rng.vec3(-2.0, 2.0),
        gauge,
        lambda: if gauge == Gauge::None {
            0.0
        } else {
            rng.uniform(-5.0, 5.0)
        },
        c: rng.vec3(-1.5, 1.5),
    }
}

#[test]
fn charged_particle_constants() {
    assert_eq!(
        <ChargedParticle as Lagrangian<3>>::COORDINATES,
        ["r.x", "r.y", "r.z"]
    );
    assert_eq!(<ChargedParticle as Lagrangian<3>>::CYCLIC, [false; 3]);
    const { assert!(<ChargedParticle as Lagrangian<3>>::AUTONOMOUS) };
}

#[test]
fn charged_particle_is_the_lorentz_force_in_every_gauge() {
    // m r̈ = q (E + ṙ × B), whatever χ is.
    let mut rng = Rng(4242);
    for gauge in [Gauge::None, Gauge::Xyz, Gauge::SinXTimesY, Gauge::Quadratic] {
        for _ in 0..STATES {
            let p = random_particle(&mut rng, gauge);
            let r = rng.vec3(-3.0, 3.0);
            let v = rng.vec3(-3.0, 3.0);
            let a = (p.e + v.cross(&p.b)) * (p.q / p.m);
            let got = p
                .accelerations(&[r.x, r.y, r.z], &[v.x, v.y, v.z], 0.0)
                .unwrap();
            assert_close(
                &got,
                &[a.x, a.y, a.z],
                REL,
                &format!("charged particle, {gauge:?}"),
            );
        }
    }
}

#[test]
fn gauge_term_drops_out_of_the_accelerations_but_not_the_momenta() {
    let mut rng = Rng(2718);
    for gauge in [Gauge::Xyz, Gauge::SinXTimesY, Gauge::Quadratic] {
        for _ in 0..1000 {
            let with = random_particle(&mut rng, gauge);
            let without = ChargedParticle {
                gauge: Gauge::None,
                lambda: 0.0,
                ..with.clone()
            };
            let r = rng.vec3(-3.0, 3.0);
            let v = rng.vec3(-3.0, 3.0);
            let (q, qd) = ([r.x, r.y, r.z], [v.x, v.y, v.z]);
            let a1 = with.accelerations(&q, &qd, 0.0).unwrap();
            let a0 = without.accelerations(&q, &qd, 0.0).unwrap();
            assert_close(&a1, &a0, REL, &format!("gauge {gauge:?}"));
            // The canonical momentum does change: p = m ṙ + q A + λ ∇χ.
            let grad_chi = match gauge {
                Gauge::Xyz => Vector3::new(r.y * r.z, r.x * r.z, r.x * r.y),
                Gauge::SinXTimesY => Vector3::new(r.x.cos() * r.y, r.x.sin(), 0.0),
                Gauge::Quadratic => with.c * with.c.dot(&r),
                Gauge::None => Vector3::zeros(),
            };
            let p_want = v * with.m + with.b.cross(&r) * (with.q / 2.0) + grad_chi * with.lambda;
            let p_got = with.momenta(&q, &qd, 0.0);
            assert_close(
                &p_got,
                &[p_want.x, p_want.y, p_want.z],
                1e-13,
                "canonical momentum",
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 5. Pendulum with a vertically driven pivot (explicit time)
// ---------------------------------------------------------------------------------------------

/// Pivot at height a cos(ωt); bob at (l sinθ, a cos ωt − l cosθ); y up.
#[derive(Debug, Clone)]
pub struct DrivenPendulum {
    pub m: f64,
    pub l: f64,
    pub g: f64,
    pub a: f64,
    pub w: f64,
}

#[lagrangian]
impl DrivenPendulum {
    /// Written in Cartesian form; the macro never sees the reduced EOM.
    fn lagrangian(&self, (theta, theta_dot): Coord, t: Time) -> Scalar {
        let (s, c) = theta.sin_cos();
        let pivot_y = self.a * (self.w * t).cos();
        let pivot_y_dot = -self.a * self.w * (self.w * t).sin();
        let speed_sq = {
            let vx = self.l * c * theta_dot;
            let vy = pivot_y_dot + self.l * s * theta_dot;
            vx * vx + vy * vy
        };
        let height = pivot_y - self.l * c;
        0.5 * self.m * speed_sq - self.m * self.g * height
    }
}

#[test]
fn driven_pendulum_constants() {
    assert_eq!(<DrivenPendulum as Lagrangian<1>>::COORDINATES, ["theta"]);
    assert_eq!(<DrivenPendulum as Lagrangian<1>>::CYCLIC, [false]);
    const { assert!(!<DrivenPendulum as Lagrangian<1>>::AUTONOMOUS) };
}

#[test]
fn driven_pendulum_matches_closed_form() {
    // l θ̈ = −(g + ÿ_p) sinθ with ÿ_p = −a ω² cos ωt (the pivot acceleration acts as extra gravity).
    let mut rng = Rng(55555);
    for _ in 0..STATES {
        let p = DrivenPendulum {
            m: rng.uniform(0.1, 5.0),
            l: rng.uniform(0.1, 3.0),
            g: rng.uniform(0.0, 20.0),
            a: rng.uniform(-0.5, 0.5),
            w: rng.uniform(0.0, 50.0),
        };
        let (q, qd, t) = (
            rng.uniform(-7.0, 7.0),
            rng.uniform(-10.0, 10.0),
            rng.uniform(0.0, 100.0),
        );
        let ypp = -p.a * p.w * p.w * (p.w * t).cos();
        let want = [-(p.g + ypp) * q.sin() / p.l];
        let got = p.accelerations(&[q], &[qd], t).unwrap();
        assert_close(&got, &want, REL, "driven pendulum");
    }
}

// ---------------------------------------------------------------------------------------------
// 6. Elastic (spring) pendulum — `if` on an f64 field
// ---------------------------------------------------------------------------------------------

/// A mass on a spring of stiffness `k` and rest length `l0`, swinging in a vertical plane.
#[derive(Debug, Clone)]
pub struct ElasticPendulum {
    pub m: f64,
    pub k: f64,
    pub l0: f64,
    pub g: f64,
}

// `if` on a parameter: the symbolic mode (the default) evaluates the condition once per call and
// derives both branches at compile time.
#[lagrangian]
impl ElasticPendulum {
    fn lagrangian(&self, (r, r_dot): Coord, (theta, theta_dot): Coord) -> Scalar {
        let spring = if self.k > 0.0 {
            let stretch = r - self.l0;
            self.k * stretch * stretch / 2.0
        } else {
            0.0
        };
        self.m / 2.0 * (r_dot * r_dot + r * r * theta_dot * theta_dot) - spring
            + self.m * self.g * r * theta.cos()
    }
}

#[test]
fn elastic_pendulum_constants() {
    assert_eq!(
        <ElasticPendulum as Lagrangian<2>>::COORDINATES,
        ["r", "theta"]
    );
    assert_eq!(<ElasticPendulum as Lagrangian<2>>::CYCLIC, [false, false]);
    const { assert!(<ElasticPendulum as Lagrangian<2>>::AUTONOMOUS) };
}

#[test]
fn elastic_pendulum_matches_closed_form_with_and_without_spring() {
    // r̈ = r θ̇² − (k/m)(r − l₀) + g cosθ;  θ̈ = −(2 ṙ θ̇ + g sinθ)/r.
    let mut rng = Rng(8080);
    for i in 0..STATES {
        let p = ElasticPendulum {
            m: rng.uniform(0.1, 5.0),
            k: if i % 5 == 0 {
                0.0
            } else {
                rng.uniform(0.1, 50.0)
            },
            l0: rng.uniform(0.1, 2.0),
            g: rng.uniform(0.0, 20.0),
        };
        let q = [rng.uniform(0.1, 4.0), rng.uniform(-7.0, 7.0)];
        let qd = [rng.uniform(-5.0, 5.0), rng.uniform(-5.0, 5.0)];
        let (r, th, rd, thd) = (q[0], q[1], qd[0], qd[1]);
        let want = [
            r * thd * thd - p.k / p.m * (r - p.l0) + p.g * th.cos(),
            -(2.0 * rd * thd + p.g * th.sin()) / r,
        ];
        let got = p.accelerations(&q, &qd, 0.0).unwrap();
        assert_close(&got, &want, REL, "elastic pendulum");
    }
}

// ---------------------------------------------------------------------------------------------
// 7. Bead on a rotating hoop — `2.0 * x` form, unused time parameter
// ---------------------------------------------------------------------------------------------

/// A bead on a hoop of radius `r` spinning at rate `w` about its vertical diameter.
#[derive(Debug, Clone)]
pub struct BeadOnHoop {
    pub m: f64,
    pub r: f64,
    pub w: f64,
    pub g: f64,
}

#[lagrangian]
impl BeadOnHoop {
    #[allow(unused_variables)]
    fn lagrangian(&self, (theta, theta_dot): Coord, t: Time) -> Scalar {
        let s = theta.sin();
        let t_kin = self.m * self.r.powi(2) * (theta_dot.powi(2) + (self.w * s).powi(2));
        t_kin / 2.0 + 2.0 * (self.m * self.g * self.r * theta.cos()) / 2.0
    }
}

#[test]
fn bead_on_hoop_constants() {
    assert_eq!(<BeadOnHoop as Lagrangian<1>>::COORDINATES, ["theta"]);
    assert_eq!(<BeadOnHoop as Lagrangian<1>>::CYCLIC, [false]);
    // `t: Time` is declared but never used: still autonomous.
    const { assert!(<BeadOnHoop as Lagrangian<1>>::AUTONOMOUS) };
}

#[test]
fn bead_on_hoop_matches_closed_form() {
    // θ̈ = sinθ (ω² cosθ − g/R).
    let mut rng = Rng(1010);
    for _ in 0..STATES {
        let p = BeadOnHoop {
            m: rng.uniform(0.1, 5.0),
            r: rng.uniform(0.1, 3.0),
            w: rng.uniform(-10.0, 10.0),
            g: rng.uniform(0.0, 20.0),
        };
        let (q, qd) = (rng.uniform(-7.0, 7.0), rng.uniform(-10.0, 10.0));
        let want = [q.sin() * (p.w * p.w * q.cos() - p.g / p.r)];
        let got = p.accelerations(&[q], &[qd], rng.uniform(0.0, 9.0)).unwrap();
        assert_close(&got, &want, REL, "bead on hoop");
    }
}

// ---------------------------------------------------------------------------------------------
// 8. Atwood machine with a massive pulley — a coordinate whose velocity alone matters
// ---------------------------------------------------------------------------------------------

/// Masses m1, m2 over a pulley of moment of inertia `i` and radius `rp`; x = drop of m1.
#[derive(Debug, Clone)]
pub struct Atwood {
    pub m1: f64,
    pub m2: f64,
    pub i: f64,
    pub rp: f64,
    pub g: f64,
}

#[lagrangian]
impl Atwood {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        let inertia = self.m1 + self.m2 + self.i / (self.rp * self.rp);
        inertia * x_dot * x_dot / 2.0 + (self.m1 - self.m2) * self.g * x
    }
}

/// A free particle in a plane: both coordinates cyclic; the momentum alone is the dynamics.
#[derive(Debug, Clone)]
pub struct FreePlanar {
    pub m: f64,
}

#[lagrangian]
impl FreePlanar {
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        self.m * (x_dot * x_dot + y_dot * y_dot) / 2.0
    }
}

#[test]
fn atwood_and_free_particle() {
    assert_eq!(<Atwood as Lagrangian<1>>::CYCLIC, [false]);
    assert_eq!(<FreePlanar as Lagrangian<2>>::CYCLIC, [true, true]);
    assert_eq!(<FreePlanar as Lagrangian<2>>::COORDINATES, ["x", "y"]);
    let mut rng = Rng(99);
    for _ in 0..STATES {
        let p = Atwood {
            m1: rng.uniform(0.1, 5.0),
            m2: rng.uniform(0.1, 5.0),
            i: rng.uniform(0.0, 2.0),
            rp: rng.uniform(0.05, 1.0),
            g: 9.81,
        };
        let want = (p.m1 - p.m2) * p.g / (p.m1 + p.m2 + p.i / (p.rp * p.rp));
        let got = p
            .accelerations(&[rng.uniform(-5.0, 5.0)], &[rng.uniform(-5.0, 5.0)], 0.0)
            .unwrap();
        assert_close(&got, &[want], REL, "atwood");
        let free = FreePlanar {
            m: rng.uniform(0.1, 5.0),
        };
        let got = free
            .accelerations(&[1.0, -2.0], &[rng.uniform(-5.0, 5.0), 3.0], 0.0)
            .unwrap();
        assert_eq!(got, [0.0, 0.0]);
    }
}

// ---------------------------------------------------------------------------------------------
// 9. Values the user spells with `Scalar` (regression: these were classified as constants)
// ---------------------------------------------------------------------------------------------

fn zero<S: Scalar>() -> S {
    S::constant(0.0)
}

/// A harmonic oscillator whose body names `Scalar` explicitly in calls.
#[derive(Debug, Clone)]
pub struct ExplicitScalar {
    pub m: f64,
    pub k: f64,
}

// This body calls generic helpers and `Scalar::constant`: the symbolic mode (the default) rejects that with a
// pointed error, so it uses the run-time jets.
#[lagrangian(mode = "jets")]
impl ExplicitScalar {
    fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
        let half_m = Scalar::constant(self.m) / 2.0;
        let origin = Vector3::<Scalar>::zeros();
        let offset = zero::<Scalar>() + <Scalar as From<f64>>::from(0.0);
        half_m * x_dot * x_dot - 0.5 * self.k * (x - offset).powi(2) + origin.norm_squared()
    }
}

#[test]
fn explicit_scalar_calls_are_values_of_the_coordinates_type() {
    let mut rng = Rng(6060);
    for _ in 0..STATES {
        let p = ExplicitScalar {
            m: rng.uniform(0.1, 5.0),
            k: rng.uniform(0.0, 20.0),
        };
        let x = rng.uniform(-3.0, 3.0);
        let got = p
            .accelerations(&[x], &[rng.uniform(-3.0, 3.0)], 0.0)
            .unwrap();
        assert_close(&got, &[-p.k / p.m * x], REL, "explicit Scalar");
    }
}
