//! Unilateral contacts declared next to L (`fn contacts`, run by `Simulation::contacts`) against
//! closed forms: a bouncing ball (impact times, apex heights hₖ = e²ᵏh, the accumulation time
//! t∞ = t₁ (1 + e)/(1 − e), then resting contact with λ = m g), a rocking block (Housner's
//! ratio 1 − (3/2) sin²α across each plastic sticking impact), a rimless wheel walking down a
//! slope (its post-impact rate converging to ω* = cot 2α √(4 (g/l) sin α sin γ)), the energy
//! each impact removes, and the refusals.

use lagrange::prelude::*;
use lagrange_examples::contact_systems::{omega_star, Ball, Block, RimlessWheel, SPOKES};

/// The ball of the `impacts` example ([`Ball`]) in jets mode.
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
            // The apex after impact k (k ≥ 0), from the run's velocity after it: h e^{2(k+1)}.
            let apex = jump.after.1[1].powi(2) / (2.0 * G);
            let want = if k == resting {
                0.0
            } else {
                H * E.powi(2 * (k as i32 + 1))
            };
            assert!(
                (apex - want).abs() < 1e-12 * H,
                "apex {k}: {apex} vs {want}"
            );
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

#[test]
fn rimless_wheel_walks_to_its_limit_cycle() {
    let (g, l, gamma): (f64, f64, f64) = (G, 1.0, 0.08);
    let alpha = std::f64::consts::PI / SPOKES as f64;
    let wheel = RimlessWheel {
        m: 2.0,
        g,
        l,
        slope: gamma,
    };
    let omega_star = omega_star(&wheel);
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
    // The variational method and the Taylor method (Radau5 runs contacts:
    // `radau5_runs_contacts` below).
    for method in [
        Method::VariationalMidpoint { dt: 0.01 },
        Method::Taylor { tol: 1e-12 },
    ] {
        let err = Simulation::contacts(&ball, [0.0, 1.0], [0.0, 0.0])
            .method(method)
            .until(1.0)
            .run()
            .unwrap_err();
        assert!(err.to_string().contains("does not run contacts"), "{err}");
    }
}

/// A particle of mass m on the outside of a smooth sphere (a circle of radius r in the
/// vertical plane): the contact is closed while the sphere pushes.
pub struct OnSphere {
    pub m: f64,
    pub g: f64,
    pub r: f64,
}

#[lagrangian]
impl OnSphere {
    fn lagrangian(&self, (_x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) - self.m * self.g * y
    }
    fn contacts(&self, (x, _): Coord, (y, _): Coord) -> [Contact; 1] {
        [Contact::gap((x * x + y * y).sqrt() - self.r).named("sphere")]
    }
}

#[test]
fn particle_leaves_the_sphere_where_its_normal_force_vanishes() {
    // From the top at speed v₀ along the surface, it leaves at cos θ = (2 + v₀²/(g r))/3,
    // where m v²/r = m g cos θ and v² = v₀² + 2 g r (1 − cos θ).
    let (m, g, r, v0) = (1.5, G, 2.0, 0.8);
    let sphere = OnSphere { m, g, r };
    let cos_leave = (2.0 + v0 * v0 / (g * r)) / 3.0;
    let tr = Simulation::contacts(&sphere, [0.0, r], [v0, 0.0])
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-14,
        })
        .until(1.5)
        .sample_every(0.01)
        .run()
        .unwrap();
    let leave = &tr.jumps[0];
    assert_eq!(leave.event, "sphere");
    // Lift-off changes no state and no energy.
    assert_eq!(leave.before, leave.after);
    assert_eq!(leave.energy_change, 0.0);
    let (x, y) = (leave.before.0[0], leave.before.0[1]);
    assert!(((x * x + y * y).sqrt() - r).abs() < 1e-12);
    assert!((y / r - cos_leave).abs() < 1e-9, "{} vs {cos_leave}", y / r);
    // Before it the sphere pushes with λ ≥ 0 (the gap's gradient has unit length: λ is the
    // normal force), m g cos θ − m v²/r; after it, free flight.
    for (i, &t) in tr.t.iter().enumerate() {
        let (x, y) = (tr.q[i][0], tr.q[i][1]);
        if t < leave.t {
            let v2 = tr.qdot[i][0].powi(2) + tr.qdot[i][1].powi(2);
            let expected = m * g * y / r - m * v2 / r;
            assert!((tr.lambda[i][0] - expected).abs() < 1e-9, "t = {t}");
            assert!(((x * x + y * y).sqrt() - r).abs() < 1e-12);
        } else if t > leave.t {
            assert_eq!(tr.lambda[i][0], 0.0);
            assert!((x * x + y * y).sqrt() > r);
        }
    }
    // No contact force does work: the energy is conserved throughout (and the work column,
    // which carries the jumps' energy, stays zero).
    for i in 0..tr.t.len() {
        assert!((tr.energy[i] - tr.energy[0]).abs() < 1e-10 * m * g * r);
        assert_eq!(tr.work[i], 0.0);
    }
}

#[test]
fn rocking_block_comes_to_rest_on_both_corners() {
    // The rocking decays by Housner's ratio at each impact; the impacts accumulate and the
    // block rests on both sticking corners (four rows on three coordinates: the corners'
    // tangential rows are one row, kept once), pressing with m g in all.
    let (b, h, m) = (0.2, 0.6, 3.0);
    let block = Block { m, g: G, b, h };
    let th0: f64 = 0.2;
    let (x0, y0) = (b * th0.cos() - h * th0.sin(), b * th0.sin() + h * th0.cos());
    let tr = Simulation::contacts(&block, [x0, y0, th0], [0.0; 3])
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-14,
        })
        .until(8.0)
        .run()
        .unwrap();
    let z = tr.zeno.as_ref().expect("the rocking accumulates");
    assert!(z.resting && z.t_accumulation < 8.0, "{z}");
    assert!(
        tr.jumps.len() <= 40,
        "{} impacts integrated",
        tr.jumps.len()
    );
    assert_eq!(tr.terminated_by, None);
    let last = tr.t.len() - 1;
    let (q, v) = (tr.q[last], tr.qdot[last]);
    assert!(
        q[2].abs() < 1e-9 && v.iter().all(|x| x.abs() < 1e-9),
        "{q:?} {v:?}"
    );
    let normal = tr.lambda[last][0] + tr.lambda[last][2];
    assert!(
        (normal - m * G).abs() < 1e-9 * m * G,
        "{:?}",
        tr.lambda[last]
    );
    assert!(tr.lambda[last][0] > 0.0 && tr.lambda[last][2] > 0.0);
}

/// Radau5 runs contacts as the explicit methods do (the contact view's accelerations, their
/// Jacobian by differences while a contact is closed; the method restarted at every jump): the
/// bouncing ball's impacts at t₁ + Σ 2eʲ v₁/g to 1e-9 (Radau5 at rtol 1e-12, its global error
/// ≈ 25 × 0.1 rtol^(2/3)), its Zeno completion at t∞ and then resting contact with λ = m g to
/// 1e-8; the particle leaving the sphere where cos θ = (2 + v₀²/(g r))/3, to 1e-8.
#[test]
fn radau5_runs_contacts() {
    let radau = Method::Radau5 {
        rtol: 1e-12,
        atol: 1e-12,
    };
    let (t1, t_inf) = ball_times();
    let v1 = G * t1;
    let tr = Simulation::contacts(&Ball { m: M, g: G, e: E }, [0.0, H], [VX, 0.0])
        .method(radau)
        .until(t_inf + 1.0)
        .sample_every(0.01)
        .run()
        .unwrap();
    let mut tk = t1;
    let resting = tr.jumps.len() - 1;
    for (k, jump) in tr.jumps.iter().enumerate().take(resting) {
        assert!((jump.t - tk).abs() < 1e-9, "impact {k}: {} vs {tk}", jump.t);
        tk += 2.0 * E.powi(k as i32 + 1) * v1 / G;
    }
    let z = tr.zeno.as_ref().unwrap();
    assert!(
        z.resting && (z.t_accumulation - t_inf).abs() < 1e-8,
        "{z:?}"
    );
    let lambda = tr.lambda.last().unwrap()[0];
    assert!((lambda - M * G).abs() < 1e-8 * M * G, "λ = {lambda}");
    assert!(tr.q.last().unwrap()[1].abs() < 1e-12);
    // Off the sphere.
    let (m, g, r, v0) = (0.5, G, 1.0, 0.8);
    let tr = Simulation::new(&OnSphere { m, g, r }, [0.0, r], [v0, 0.0])
        .method(radau)
        .until(1.0)
        .run()
        .unwrap();
    let leave = &tr.jumps[0];
    let cos = leave.before.0[1] / r;
    let want = (2.0 + v0 * v0 / (g * r)) / 3.0;
    eprintln!(
        "Radau5: {} impacts, leaves the sphere at cos θ off by {:.1e}",
        resting,
        cos - want
    );
    assert!((cos - want).abs() < 1e-8, "{cos} vs {want}");
}
