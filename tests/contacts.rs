//! Unilateral contacts declared next to L (`fn contacts`, run by `Simulation::contacts`) against
//! closed forms: a bouncing ball (impact times, apex heights hₖ = e²ᵏh, the accumulation time
//! t∞ = t₁ (1 + e)/(1 − e), then resting contact with λ = m g), a rocking block (Housner's
//! ratio 1 − (3/2) sin²α across each plastic sticking impact), a rimless wheel walking down a
//! slope (its post-impact rate converging to ω* = cot 2α √(4 (g/l) sin α sin γ)), the energy
//! each impact removes, and the refusals.

use lagrange::prelude::*;

/// A ball in a vertical plane above the floor y = 0: x horizontal, y up (symbolic mode).
pub struct Ball {
    pub m: f64,
    pub g: f64,
    pub e: f64,
}

#[lagrangian]
impl Ball {
    fn lagrangian(&self, (_x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) - self.m * self.g * y
    }
    fn contacts(&self, (_, _): Coord, (y, _): Coord) -> [Contact; 1] {
        [Contact::gap(y).restitution(self.e).named("floor")]
    }
}

/// The same ball in jets mode.
pub struct JetsBall {
    pub m: f64,
    pub g: f64,
    pub e: f64,
}

#[lagrangian(mode = "jets")]
impl JetsBall {
    fn lagrangian(&self, (_x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) - self.m * self.g * y
    }
    fn contacts(&self, (_, _): Coord, (y, _): Coord) -> [Contact; 1] {
        [Contact::gap(y).restitution(self.e).named("floor")]
    }
}

const M: f64 = 0.7;
const G: f64 = 9.81;
const E: f64 = 0.8;
const H: f64 = 1.0;
const VX: f64 = 0.3;

fn ball_run<U: Unilateral<2, 1>>(ball: &U, until: f64) -> Trajectory<2> {
    Simulation::contacts(ball, [0.0, H], [VX, 0.0])
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-14,
        })
        .until(until)
        .sample_every(0.01)
        .run()
        .unwrap()
}

/// t₁ and the accumulation time t∞ = t₁ (1 + e)/(1 − e).
fn ball_times() -> (f64, f64) {
    let t1 = (2.0 * H / G).sqrt();
    (t1, t1 * (1.0 + E) / (1.0 - E))
}

#[test]
fn bouncing_ball_from_fn_contacts_rests_at_its_accumulation_time() {
    let (t1, t_inf) = ball_times();
    let v1 = G * t1;
    for tr in [
        ball_run(&Ball { m: M, g: G, e: E }, t_inf + 2.0),
        ball_run(&JetsBall { m: M, g: G, e: E }, t_inf + 2.0),
    ] {
        // Impact k at t₁ + Σ_{j<k} 2 eʲ v₁/g, arriving at e^{k−1} v₁, leaving at eᵏ v₁.
        // The last impact integrated is the one the Zeno resolution makes plastic.
        let mut tk = t1;
        let resting = tr.jumps.len() - 1;
        for (k, jump) in tr.jumps.iter().enumerate() {
            let arrive = E.powi(k as i32) * v1;
            let e = if k == resting { 0.0 } else { E };
            assert!(
                (jump.t - tk).abs() < 1e-10,
                "impact {k}: {} vs {tk}",
                jump.t
            );
            assert!((jump.before.1[1] + arrive).abs() < 1e-9 * v1);
            assert!((jump.after.1[1] - e * arrive).abs() < 1e-9 * v1);
            // The energy each impact removes: ½ m (1 − e²) v⁻².
            let lost = 0.5 * M * (1.0 - e * e) * arrive * arrive;
            assert!(
                (jump.energy_change + lost).abs() <= 1e-12 * M * G * H,
                "impact {k}: {} vs {}",
                jump.energy_change,
                -lost
            );
            // Apex after impact k: h e^{2k}.
            let apex = (E * arrive).powi(2) / (2.0 * G);
            assert!((apex - H * E.powi(2 * (k as i32 + 1))).abs() < 1e-12);
            tk += 2.0 * E * arrive / G;
        }
        // The Zeno resolution: found within a few dozen impacts, t∞ to 1e-9.
        let z = tr.zeno.as_ref().expect("the impacts accumulate");
        assert!(z.resting && z.event == "floor");
        assert!(
            (z.t_accumulation - t_inf).abs() < 1e-9,
            "t∞ {}",
            z.t_accumulation
        );
        assert!(z.hits <= 36, "{} impacts integrated", z.hits);
        assert_eq!(tr.jumps.len(), z.hits);
        assert_eq!(tr.terminated_by, None);
        // Then resting contact: y = 0, ẏ = 0, λ = m g, x still moving at VX.
        let last = tr.t.len() - 1;
        assert!((tr.t[last] - (t_inf + 2.0)).abs() < 1e-12);
        assert!(tr.q[last][1].abs() < 1e-14 && tr.qdot[last][1].abs() < 1e-14);
        assert!((tr.lambda[last][0] - M * G).abs() < 1e-9 * M * G);
        assert!((tr.q[last][0] - VX * tr.t[last]).abs() < 1e-9);
        // The work column is the energy the impacts removed: all of m g h in the end (the
        // horizontal motion keeps its kinetic energy), and h − h₀ − W = 0 at every sample.
        assert!((tr.work[last] + M * G * H).abs() <= 1e-12 * M * G * H);
        let e0 = tr.energy[0];
        for i in 0..tr.t.len() {
            let balance = tr.energy[i] - e0 - tr.work[i];
            assert!(
                balance.abs() <= 1e-11 * M * G * H,
                "t = {}: {balance:e}",
                tr.t[i]
            );
        }
    }
}

/// A rectangular block of half-width b and half-height h rocking on its bottom corners,
/// sticking and plastic (e = 0): coordinates the centre (x, y) and the tilt θ.
pub struct Block {
    pub m: f64,
    pub g: f64,
    pub b: f64,
    pub h: f64,
}

#[lagrangian]
impl Block {
    fn lagrangian(
        &self,
        (_x, x_dot): Coord,
        (y, y_dot): Coord,
        (_theta, theta_dot): Coord,
    ) -> Scalar {
        // A uniform rectangle: I = m (b² + h²)/3 about its centre.
        let inertia = self.m * (self.b * self.b + self.h * self.h) / 3.0;
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) + 0.5 * inertia * theta_dot * theta_dot
            - self.m * self.g * y
    }
    fn contacts(&self, (x, _): Coord, (y, _): Coord, (theta, _): Coord) -> [Contact; 2] {
        let (s, c) = (theta.sin(), theta.cos());
        // The bottom corners (±b, −h) of the body frame, in the world.
        let (xr, yr) = (x + self.b * c + self.h * s, y + self.b * s - self.h * c);
        let (xl, yl) = (x - self.b * c + self.h * s, y - self.b * s - self.h * c);
        [
            Contact::gap(yr).sticking(xr).named("right corner"),
            Contact::gap(yl).sticking(xl).named("left corner"),
        ]
    }
}

#[test]
fn rocking_block_loses_housners_ratio_at_each_impact() {
    let (b, h) = (0.2, 0.6);
    let block = Block { m: 3.0, g: G, b, h };
    let alpha = (b / h).atan();
    let ratio = 1.0 - 1.5 * alpha.sin().powi(2);
    // At rest on its left corner (at the origin), tilted by θ₀ < α: it falls back.
    let th0: f64 = 0.2;
    let (x0, y0) = (b * th0.cos() - h * th0.sin(), b * th0.sin() + h * th0.cos());
    let tr = Simulation::contacts(&block, [x0, y0, th0], [0.0; 3])
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-14,
        })
        .until(2.5)
        .run()
        .unwrap();
    assert!(tr.jumps.len() >= 4, "{} impacts", tr.jumps.len());
    for (k, jump) in tr.jumps.iter().enumerate() {
        let (w0, w1) = (jump.before.1[2], jump.after.1[2]);
        assert!(
            (w1 / w0 - ratio).abs() < 1e-12,
            "impact {k} ({}): {} vs {ratio}",
            jump.event,
            w1 / w0
        );
        // Each impact lands at θ = 0 on the other corner, which then stays put.
        assert!(jump.before.0[2].abs() < 1e-10);
        let expected = if k % 2 == 0 {
            "right corner"
        } else {
            "left corner"
        };
        assert_eq!(jump.event, expected);
    }
    // While pivoting the block's corner does not move: the constraint residuals stay at
    // round-off, and the normal force presses.
    let inv = tr.invariants();
    assert!(inv.constraints.unwrap().position < 1e-12);
    assert!(tr.lambda.iter().all(|l| l[0] >= 0.0 && l[2] >= 0.0));
}

/// A rimless wheel: a point mass m at the hub of `SPOKES` massless spokes of length l, 2α apart,
/// on a slope γ; (x, y) in the slope's frame (x downhill, y normal to it), θ the wheel's angle
/// (no inertia of its own). The spokes' tips stick where they land (plastic impacts).
pub struct RimlessWheel {
    pub m: f64,
    pub g: f64,
    pub l: f64,
    pub slope: f64,
}

const SPOKES: usize = 8;

#[lagrangian]
impl RimlessWheel {
    fn lagrangian(
        &self,
        (x, x_dot): Coord,
        (y, y_dot): Coord,
        (_theta, _theta_dot): Coord,
    ) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot)
            + self.m * self.g * (x * self.slope.sin() - y * self.slope.cos())
    }
    fn contacts(&self, (x, _): Coord, (y, _): Coord, (theta, _): Coord) -> [Contact; 8] {
        let spoke = |k: f64| {
            let phi = theta + k * std::f64::consts::PI / 4.0;
            let (tx, ty) = (x + self.l * phi.sin(), y - self.l * phi.cos());
            Contact::gap(ty).sticking(tx)
        };
        [
            spoke(0.0),
            spoke(1.0),
            spoke(2.0),
            spoke(3.0),
            spoke(4.0),
            spoke(5.0),
            spoke(6.0),
            spoke(7.0),
        ]
    }
}

#[test]
fn rimless_wheel_walks_to_its_limit_cycle() {
    let (g, l, gamma): (f64, f64, f64) = (G, 1.0, 0.08);
    let alpha = std::f64::consts::PI / SPOKES as f64;
    let omega_star = (4.0 * (g / l) * alpha.sin() * gamma.sin()).sqrt() / (2.0 * alpha).tan();
    let wheel = RimlessWheel {
        m: 2.0,
        g,
        l,
        slope: gamma,
    };
    // Just after an impact: spoke 0 at φ = α, its tip at the origin, the hub swinging forward
    // at 1.2 ω*, perpendicular to the spoke.
    let w0 = 1.2 * omega_star;
    let q0 = [-l * alpha.sin(), l * alpha.cos(), alpha];
    let v0 = [l * w0 * alpha.cos(), l * w0 * alpha.sin(), -w0];
    let tr = Simulation::contacts(&wheel, q0, v0)
        .method(Method::Dop853 {
            rtol: 1e-13,
            atol: 1e-15,
        })
        .until(130.0)
        .keep_samples(false)
        .run()
        .unwrap();
    assert!(tr.jumps.len() >= 40, "{} steps", tr.jumps.len());
    let omega: Vec<f64> = tr.jumps.iter().map(|j| -j.after.1[2]).collect();
    // Each impact: ω⁺ = cos 2α ω⁻ (the hub's velocity loses its component along the new spoke).
    for j in &tr.jumps {
        let r = j.after.1[2] / j.before.1[2];
        assert!((r - (2.0 * alpha).cos()).abs() < 1e-12, "{}", r);
    }
    let last = omega[omega.len() - 1];
    assert!(
        (last - omega_star).abs() < 1e-10,
        "ω = {last} against ω* = {omega_star}"
    );
    assert!((omega[0] - omega_star).abs() > 0.05 * omega_star);
}

#[test]
fn contact_runs_refuse_what_they_cannot_do() {
    let ball = Ball { m: M, g: G, e: E };
    // A state that penetrates the floor.
    let err = Simulation::contacts(&ball, [0.0, -0.1], [0.0, 0.0])
        .until(1.0)
        .run()
        .unwrap_err();
    assert!(err.to_string().contains("floor penetrates"), "{err}");
    // The implicit and variational methods.
    for method in [
        Method::VariationalMidpoint { dt: 0.01 },
        Method::Taylor { tol: 1e-12 },
        Method::Radau5 {
            rtol: 1e-8,
            atol: 1e-10,
        },
    ] {
        let err = Simulation::contacts(&ball, [0.0, 1.0], [0.0, 0.0])
            .method(method)
            .until(1.0)
            .run()
            .unwrap_err();
        assert!(err.to_string().contains("does not run contacts"), "{err}");
    }
}
