//! Contacts together with constraints (`fn contacts` next to `fn constraints` or
//! `fn velocity_constraints`), run by `Simulation::new`, against closed forms derived here:
//!
//! - a pendulum written in x, y, its rod a constraint, striking a wall: the first two impact
//!   times from the pendulum's elliptic integrals, Newton's law on its angle (θ̇⁺ = −e θ̇⁻, the
//!   rod holding through the jump), the rod's tension between impacts, and the same motion as
//!   the pendulum written in its angle;
//! - the pendulum resting against a wall: the wall's force m g tan θ and the rod's;
//! - a skate (a knife edge, a velocity constraint) striking an oblique wall: it leaves along its
//!   own heading at −e times its speed, whatever the wall's angle.

use crate::support::gauss_legendre;
use lagrange::prelude::*;

const G: f64 = 9.81;

/// A pendulum of mass m on a rod of length l, written in x, y, with a wall at x = −d that it
/// may strike (restitution e).
pub struct RodWall {
    pub m: f64,
    pub l: f64,
    pub d: f64,
    pub e: f64,
}

#[lagrangian]
impl RodWall {
    fn lagrangian(&self, (_x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) - self.m * G * y
    }
    fn constraints(&self, (x, _): Coord, (y, _): Coord) -> [Scalar; 1] {
        [x * x + y * y - self.l * self.l]
    }
    fn contacts(&self, (x, _): Coord, (_, _): Coord) -> [Contact; 1] {
        [Contact::gap(x + self.d).restitution(self.e).named("wall")]
    }
}

/// The same pendulum written in its angle θ from the downward vertical.
pub struct AngleWall {
    pub m: f64,
    pub l: f64,
    pub d: f64,
    pub e: f64,
}

#[lagrangian]
impl AngleWall {
    fn lagrangian(&self, (th, th_dot): Coord) -> Scalar {
        0.5 * self.m * self.l * self.l * th_dot * th_dot + self.m * G * self.l * th.cos()
    }
    fn contacts(&self, (th, _): Coord) -> [Contact; 1] {
        [Contact::gap(self.l * th.sin() + self.d)
            .restitution(self.e)
            .named("wall")]
    }
}

/// F(φ, k) = ∫₀^φ dψ / √(1 − k² sin²ψ), the incomplete elliptic integral of the first kind, by
/// composite Gauss–Legendre quadrature (5 points on 64 panels: the integrand is smooth and
/// k ≤ 0.4 here, so the sum is exact to round-off).
fn elliptic_f(phi: f64, k: f64) -> f64 {
    gauss_legendre(0.0, phi, |psi| {
        1.0 / (1.0 - k * k * psi.sin().powi(2)).sqrt()
    })
}

/// The time a pendulum of amplitude a (turning at ±a) takes from the vertical to the angle θ
/// (|θ| ≤ a): √(l/g) F(φ, k) with k = sin(a/2), sin φ = sin(|θ|/2)/k; from the vertical to
/// the turning point, √(l/g) K(k) = √(l/g) F(π/2, k).
fn time_from_vertical(l: f64, a: f64, theta: f64) -> f64 {
    let k = (a / 2.0).sin();
    let phi = ((theta.abs() / 2.0).sin() / k).min(1.0).asin();
    (l / G).sqrt() * elliptic_f(phi, k)
}

/// The angle of (x, y) from the downward vertical, and its rate.
fn angle(q: &[f64; 2], v: &[f64; 2]) -> (f64, f64) {
    let (x, y) = (q[0], q[1]);
    (x.atan2(-y), (-y * v[0] + x * v[1]) / (x * x + y * y))
}

fn dop853() -> Method {
    Method::Dop853 {
        rtol: 1e-12,
        atol: 1e-14,
    }
}

/// Released at rest from θ₀ = 0.8, the pendulum swings to the wall at θ_w = −asin(d/l) and
/// strikes it at t₁ = √(l/g) (K(k₀) + F(φ_w, k₀)) (k₀ = sin(θ₀/2)) arriving at
/// θ̇⁻ = −√(2 g/l (cos θ_w − cos θ₀)); Newton's law on the gap x + d = l sin θ + d, whose rate
/// is l cos θ θ̇, is Newton's law on θ̇: θ̇⁺ = −e θ̇⁻, the rod holding. It then swings out to
/// θ₁ with cos θ₁ = cos θ_w − e² (cos θ_w − cos θ₀) and back, striking again at
/// t₂ = t₁ + 2 √(l/g) (K(k₁) + F(φ_w, k₁)).
#[test]
fn pendulum_in_x_y_strikes_a_wall_by_newtons_law_on_its_angle() {
    let (m, l, e) = (0.7, 1.3, 0.7);
    let d = 0.5 * l;
    let sys = RodWall { m, l, d, e };
    let th0: f64 = 0.8;
    let q0 = [l * th0.sin(), -l * th0.cos()];
    let tr = Simulation::new(&sys, q0, [0.0, 0.0])
        .method(dop853())
        .until(3.0)
        .sample_every(0.01)
        .run()
        .unwrap();
    let thw = -(d / l).asin();
    let th1 = (thw.cos() - e * e * (thw.cos() - th0.cos())).acos();
    let t1 = time_from_vertical(l, th0, th0) + time_from_vertical(l, th0, thw);
    let t2 = t1 + 2.0 * (time_from_vertical(l, th1, th1) + time_from_vertical(l, th1, thw));
    assert!(tr.jumps.len() >= 2, "{} impacts", tr.jumps.len());
    for (jump, t) in tr.jumps.iter().zip([t1, t2]) {
        assert!((jump.t - t).abs() < 1e-9, "impact at {} vs {t}", jump.t);
        let (a, before) = angle(&jump.before.0, &jump.before.1);
        let (_, after) = angle(&jump.after.0, &jump.after.1);
        assert!((a - thw).abs() < 1e-10, "at θ = {a}");
        assert!((after + e * before).abs() < 1e-10 * before.abs());
        // The rod holds through the jump: the velocity stays tangent to it.
        let (q, v) = (&jump.after.0, &jump.after.1);
        assert!((q[0] * v[0] + q[1] * v[1]).abs() < 1e-12 * l * before.abs());
        // The energy the impact removes: ½ m l² (1 − e²) θ̇⁻².
        let lost = 0.5 * m * l * l * (1.0 - e * e) * before * before;
        assert!((jump.energy_change + lost).abs() < 1e-10 * m * G * l);
    }
    let (_, first) = angle(&tr.jumps[0].before.0, &tr.jumps[0].before.1);
    let arrive = (2.0 * G / l * (thw.cos() - th0.cos())).sqrt();
    assert!((first + arrive).abs() < 1e-9 * arrive);
    // Between impacts: on the rod, and the rod's tension T = m (g cos θ + l θ̇²) is its
    // multiplier: Gᵀλ = 2λ (x, y) = −T (x, y)/l, so λ = −T/(2l) (column 2K + 0 = 2).
    for (k, (q, v)) in tr.q.iter().zip(&tr.qdot).enumerate() {
        assert!((q[0] * q[0] + q[1] * q[1] - l * l).abs() < 1e-10 * l * l);
        assert!((q[0] * v[0] + q[1] * v[1]).abs() < 1e-9);
        let (th, w) = angle(q, v);
        let tension = m * (G * th.cos() + l * w * w);
        let lambda = tr.lambda[k][2];
        assert!(
            (lambda + tension / (2.0 * l)).abs() < 1e-8 * m * G,
            "t = {}: λ = {lambda}, −T/2l = {}",
            tr.t[k],
            -tension / (2.0 * l)
        );
    }
}

/// The same motion as the pendulum written in its angle, sample by sample, across its impacts
/// (until the impacts accumulate), and through an `Ensemble` member alike.
#[test]
fn pendulum_in_x_y_with_a_wall_follows_its_angle_model() {
    let (m, l, e) = (1.1, 0.9, 0.6);
    let d = 0.3;
    let th0: f64 = 1.1;
    let w0 = -0.4;
    let q0 = [l * th0.sin(), -l * th0.cos()];
    let v0 = [l * th0.cos() * w0, l * th0.sin() * w0];
    let xy = Simulation::new(&RodWall { m, l, d, e }, q0, v0)
        .method(dop853())
        .until(2.5)
        .sample_every(0.05)
        .run()
        .unwrap();
    let th = Simulation::new(&AngleWall { m, l, d, e }, [th0], [w0])
        .method(dop853())
        .until(2.5)
        .sample_every(0.05)
        .run()
        .unwrap();
    assert_eq!(xy.jumps.len(), th.jumps.len());
    assert!(xy.jumps.len() >= 2, "{} impacts", xy.jumps.len());
    for (a, b) in xy.jumps.iter().zip(&th.jumps) {
        assert!((a.t - b.t).abs() < 1e-9, "{} vs {}", a.t, b.t);
    }
    assert_eq!(xy.t.len(), th.t.len());
    for k in 0..xy.t.len() {
        let (a, w) = angle(&xy.q[k], &xy.qdot[k]);
        assert!((a - th.q[k][0]).abs() < 1e-8, "t = {}", xy.t[k]);
        assert!((w - th.qdot[k][0]).abs() < 1e-7, "t = {}", xy.t[k]);
    }
    // An ensemble of two walls: each member as its single run.
    let r = Ensemble::new(2, |i| {
        Member::new(
            RodWall {
                m,
                l,
                d: d + 0.1 * i as f64,
                e,
            },
            q0,
            v0,
        )
    })
    .configure(|sim| sim.method(dop853()).until(2.5))
    .run();
    let first = r.results[0].as_ref().unwrap();
    assert_eq!(first.jumps.len(), xy.jumps.len());
    for (a, b) in first.jumps.iter().zip(&xy.jumps) {
        assert_eq!(a.t, b.t);
    }
    let second = r.results[1].as_ref().unwrap();
    assert!(
        second.jumps[0].t > xy.jumps[0].t,
        "a farther wall is struck later"
    );
}

/// A pendulum of mass m that comes to rest against a wall x ≥ d at θ = asin(d/l): with q̈ = 0,
/// 0 = (0, −m g) + λ_rod (2x, 2y) + λ_wall (1, 0), so λ_rod = m g/(2y) and
/// λ_wall = −2 λ_rod x = m g tan θ. Started on the wall at rest, and after its bounces have
/// accumulated (e = 0.5) from θ₀ = 0.9.
#[test]
fn pendulum_rests_against_a_wall_with_the_static_forces() {
    /// The wall on the right: x ≥ d.
    pub struct Leaning {
        pub m: f64,
        pub l: f64,
        pub d: f64,
    }
    #[lagrangian]
    impl Leaning {
        fn lagrangian(&self, (_x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
            0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) - self.m * G * y
        }
        fn constraints(&self, (x, _): Coord, (y, _): Coord) -> [Scalar; 1] {
            [x * x + y * y - self.l * self.l]
        }
        fn contacts(&self, (x, _): Coord, (_, _): Coord) -> [Contact; 1] {
            [Contact::gap(x - self.d).restitution(0.5).named("wall")]
        }
    }
    let (m, l) = (0.8, 1.2);
    let d = 0.5 * l;
    let sys = Leaning { m, l, d };
    let th = (d / l).asin();
    let wall = m * G * th.tan();
    let rod = m * G / (2.0 * (-l * th.cos()));
    // At rest on the wall from the start: closed, and nothing moves.
    let tr = Simulation::new(&sys, [d, -l * th.cos()], [0.0, 0.0])
        .until(1.0)
        .sample_every(0.25)
        .run()
        .unwrap();
    for (k, lam) in tr.lambda.iter().enumerate() {
        assert!((lam[0] - wall).abs() < 1e-12 * wall, "λ_wall = {}", lam[0]);
        assert!(
            (lam[2] - rod).abs() < 1e-12 * rod.abs(),
            "λ_rod = {}",
            lam[2]
        );
        assert!((tr.q[k][0] - d).abs() < 1e-14);
    }
    // Dropped from θ₀ = 0.9: its bounces accumulate and it rests on the wall.
    let th0: f64 = 0.9;
    let tr = Simulation::new(&sys, [l * th0.sin(), -l * th0.cos()], [0.0, 0.0])
        .method(dop853())
        .until(6.0)
        .run()
        .unwrap();
    let z = tr.zeno.as_ref().expect("the bounces accumulate");
    assert!(z.resting && z.t_accumulation < 6.0);
    let last = tr.lambda.last().unwrap();
    assert!((last[0] - wall).abs() < 1e-9 * wall, "λ_wall = {}", last[0]);
    assert!(
        (last[2] - rod).abs() < 1e-9 * rod.abs(),
        "λ_rod = {}",
        last[2]
    );
    let q = tr.q.last().unwrap();
    assert!((q[0] - d).abs() < 1e-12 && (q[0] * q[0] + q[1] * q[1] - l * l).abs() < 1e-12);
}

/// A skate (a knife edge at its centre of mass, heading φ, sliding only along its heading:
/// ẏ cos φ − ẋ sin φ = 0) moving along x at speed v toward a wall whose normal makes the angle
/// α with −x (gap c − x cos α − y sin α). At the impact M Δq̇ = n Λ + Aᵀ μ with A = (0, 1, 0)
/// at φ = 0, and after it ẏ⁺ = 0 (the blade) and ġ⁺ = −e ġ⁻: −ẋ⁺ cos α = e v cos α, so
/// ẋ⁺ = −e v whatever α, and the turning rate is untouched (the blade is at the centre of
/// mass: no impulse turns it).
#[test]
fn a_skate_strikes_an_oblique_wall_and_leaves_along_its_blade() {
    pub struct Skate {
        pub m: f64,
        pub i: f64,
        pub alpha: f64,
        pub e: f64,
    }
    #[lagrangian]
    impl Skate {
        fn lagrangian(&self, (_x, x_dot): Coord, (_y, y_dot): Coord, (_p, p_dot): Coord) -> Scalar {
            0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) + 0.5 * self.i * p_dot * p_dot
        }
        fn velocity_constraints(
            &self,
            (_, x_dot): Coord,
            (_, y_dot): Coord,
            (p, _): Coord,
        ) -> [Scalar; 1] {
            [y_dot * p.cos() - x_dot * p.sin()]
        }
        fn contacts(&self, (x, _): Coord, (y, _): Coord, (_, _): Coord) -> [Contact; 1] {
            [
                Contact::gap(1.0 - x * self.alpha.cos() - y * self.alpha.sin())
                    .restitution(self.e)
                    .named("wall"),
            ]
        }
    }
    let (v, e) = (2.0, 0.6);
    for alpha in [0.0, 0.3, -0.7] {
        let sys = Skate {
            m: 1.5,
            i: 0.2,
            alpha,
            e,
        };
        // Heading 0, not turning: it slides along x and strikes the wall at x = 1/cos α.
        let tr = Simulation::new(&sys, [0.0, 0.0, 0.0], [v, 0.0, 0.0])
            .method(dop853())
            .until(1.0)
            .run()
            .unwrap();
        assert_eq!(tr.jumps.len(), 1, "α = {alpha}");
        let jump = &tr.jumps[0];
        assert!(
            (jump.t - 1.0 / (alpha.cos() * v)).abs() < 1e-12,
            "α = {alpha}"
        );
        let after = jump.after.1;
        assert!((after[0] + e * v).abs() < 1e-12, "α = {alpha}: {after:?}");
        assert!(
            after[1].abs() < 1e-12 && after[2].abs() < 1e-12,
            "{after:?}"
        );
        let end = tr.qdot.last().unwrap();
        assert!((end[0] + e * v).abs() < 1e-12 && end[1].abs() < 1e-12);
    }
}

/// Bad input is refused with a typed error: a start off the rod names the residual (as for a
/// constrained run), and `project_initial_state` puts it on the rod instead; the constraints
/// alone (`Simulation::constrained`) are refused for a system that has contacts too.
#[test]
fn a_start_off_the_constraints_is_refused_or_projected() {
    let sys = RodWall {
        m: 1.0,
        l: 1.0,
        d: 0.5,
        e: 0.5,
    };
    let err = Simulation::new(&sys, [0.3, -1.2], [0.0, 0.0])
        .until(0.1)
        .run()
        .unwrap_err();
    assert!(
        matches!(err, SimulationError::OffConstraints { .. }),
        "{err}"
    );
    let tr = Simulation::new(&sys, [0.3, -1.2], [0.0, 0.0])
        .project_initial_state()
        .until(0.1)
        .run()
        .unwrap();
    let q = tr.q[0];
    assert!((q[0] * q[0] + q[1] * q[1] - 1.0).abs() < 1e-14);
    // `Simulation::constrained` runs the constraints alone: it refuses a system that also has
    // contacts (it would pass through the wall), naming `Simulation::new`.
    let err = Simulation::constrained(&sys, [0.6, -0.8], [0.0, 0.0])
        .until(0.1)
        .run()
        .unwrap_err();
    assert!(
        matches!(err, SimulationError::InvalidOptions { .. })
            && err.to_string().contains("Simulation::new"),
        "{err}"
    );
}
