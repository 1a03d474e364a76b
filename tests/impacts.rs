//! Events that reset the state (`Event::reset`): a bouncing ball against its closed forms
//! (impact times, apex heights hₖ = e²ᵏh, the energy each impact removes, the accumulation time
//! t∞ = t₁ (1 + e)/(1 − e) of a Zeno run), with every method; samples, the work column and the
//! dense output across the jumps; the refusal on a constrained run.

use lagrange::prelude::*;

/// A ball in a vertical plane: x horizontal, y up.
pub struct Ball {
    pub m: f64,
    pub g: f64,
}

#[lagrangian]
impl Ball {
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) - self.m * self.g * y
    }
}

const G: f64 = 9.81;
const E: f64 = 0.8;
const H: f64 = 1.0;
const VX: f64 = 0.3;

/// The closed form of the ball dropped from (0, H) with horizontal speed VX: impact k (k ≥ 1)
/// at tₖ, leaving upward at vₖ = eᵏ v₁.
struct Closed {
    t1: f64,
    v1: f64,
}

impl Closed {
    fn new() -> Self {
        let t1 = (2.0 * H / G).sqrt();
        Closed { t1, v1: G * t1 }
    }
    /// The time of impact k ≥ 1.
    fn impact(&self, k: i32) -> f64 {
        // t_{k+1} = t_k + 2 e^k v₁ / g
        self.t1 + (1..k).map(|j| 2.0 * E.powi(j) * self.v1 / G).sum::<f64>()
    }
    fn accumulation(&self) -> f64 {
        self.t1 * (1.0 + E) / (1.0 - E)
    }
    /// (x, y, ẋ, ẏ) at t before the accumulation.
    fn state(&self, t: f64) -> [f64; 4] {
        let x = VX * t;
        if t <= self.t1 {
            return [x, H - 0.5 * G * t * t, VX, -G * t];
        }
        let mut k = 1;
        while self.impact(k + 1) <= t {
            k += 1;
        }
        let (tk, vk) = (self.impact(k), E.powi(k) * self.v1);
        let s = t - tk;
        [x, vk * s - 0.5 * G * s * s, VX, vk - G * s]
    }
}

fn floor<'a>() -> Event<'a, 2> {
    Event::zero_crossing("floor", |_t, q: &[f64; 2], _v| q[1])
        .falling()
        .reset(|_t, q, v| (*q, [v[0], -E * v[1]]))
}

fn run(method: Method) -> Trajectory<2> {
    let ball = Ball { m: 0.5, g: G };
    Simulation::new(&ball, [0.0, H], [VX, 0.0])
        .method(method)
        .event(floor())
        .event(Event::zero_crossing("apex", |_t, _q, v: &[f64; 2]| v[1]).falling())
        .until(10.0)
        .run()
        .expect("the ball runs")
}

#[test]
fn bouncing_ball_against_its_closed_forms() {
    let c = Closed::new();
    let tr = run(Method::Dop853 {
        rtol: 1e-12,
        atol: 1e-14,
    });
    let impacts: Vec<&EventHit<2>> = tr.events.iter().filter(|h| h.name == "floor").collect();
    assert!(impacts.len() >= 6, "{} impacts", impacts.len());
    for (k, hit) in impacts.iter().enumerate() {
        let want = c.impact(k as i32 + 1);
        assert!(
            (hit.t - want).abs() <= 1e-9,
            "impact {}: {} vs {want}",
            k + 1,
            hit.t
        );
    }
    // Apex k (after impact k) at height e^(2k) h.
    let apexes: Vec<&EventHit<2>> = tr.events.iter().filter(|h| h.name == "apex").collect();
    assert!(apexes.len() >= 5);
    for (k, hit) in apexes.iter().enumerate() {
        let want = E.powi(2 * (k as i32 + 1)) * H;
        assert!(
            (hit.q[1] - want).abs() <= 1e-9,
            "apex {}: {} vs {want}",
            k + 1,
            hit.q[1]
        );
    }
    // Each jump removes ½ m v² (1 − e²) and the work column carries it.
    let m = 0.5;
    let mut removed = 0.0;
    for (k, j) in tr.jumps.iter().enumerate() {
        // Newton's law on the speed that arrived, which is the closed form's eᵏ v₁ to 1e-9.
        let v = j.before.1[1];
        assert!((v + E.powi(k as i32) * c.v1).abs() <= 1e-9, "{j:?}");
        let want = -0.5 * m * v * v * (1.0 - E * E);
        assert!(
            (j.energy_change - want).abs() <= 1e-12 * want.abs(),
            "{j:?}"
        );
        assert_eq!(
            (j.before.0, j.after.0),
            (j.before.0, j.before.0),
            "the position does not jump"
        );
        removed += j.energy_change;
    }
    let w_end = *tr.work.last().unwrap();
    assert!(
        (w_end - removed).abs() <= 1e-12 * removed.abs(),
        "{w_end} vs {removed}"
    );
    let balance = tr
        .invariants()
        .energy_balance
        .expect("the energy is not conserved");
    assert!(balance.max_rel <= 1e-11, "{balance}");
    // The hits accumulate: the run stops at the last one with t∞.
    let z = tr.zeno.as_ref().expect("a Zeno run");
    assert!((z.t_accumulation - c.accumulation()).abs() <= 1e-9, "{z}");
    assert!((z.ratio - E).abs() <= 1e-9);
    assert!(z.hits <= 36, "{} impacts integrated", z.hits);
    assert_eq!(tr.terminated_by.as_deref(), Some("floor (Zeno)"));
    assert_eq!(*tr.t.last().unwrap(), z.t_last);
}

#[test]
fn every_method_finds_the_impacts_and_their_accumulation() {
    let c = Closed::new();
    for method in [
        Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-14,
        },
        Method::DormandPrince {
            rtol: 1e-12,
            atol: 1e-14,
        },
        Method::Taylor { tol: 1e-16 },
        Method::Radau5 {
            rtol: 1e-12,
            atol: 1e-14,
        },
        Method::Rk4 { dt: 1e-2 },
        Method::VariationalMidpoint { dt: 1e-2 },
    ] {
        let tr = run(method);
        let first = tr
            .events
            .iter()
            .find(|h| h.name == "floor")
            .expect("an impact");
        assert!((first.t - c.t1).abs() <= 1e-9, "{method:?}: {}", first.t);
        let z = tr
            .zeno
            .as_ref()
            .unwrap_or_else(|| panic!("{method:?}: no Zeno"));
        assert!(
            (z.t_accumulation - c.accumulation()).abs() <= 1e-9,
            "{method:?}: {} vs {}",
            z.t_accumulation,
            c.accumulation()
        );
    }
}

#[test]
fn samples_and_dense_output_across_the_jumps() {
    let c = Closed::new();
    let ball = Ball { m: 0.5, g: G };
    let tr = Simulation::new(&ball, [0.0, H], [VX, 0.0])
        .method(Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-14,
        })
        .event(floor())
        .sample_every(0.01)
        .keep_dense_output(true)
        .until(2.0)
        .run()
        .expect("the ball runs");
    assert!(tr.jumps.len() >= 3);
    for (k, &t) in tr.t.iter().enumerate() {
        // a sample at an impact is the state before the jump
        if tr.jumps.iter().any(|j| j.t == t) {
            continue;
        }
        let want = c.state(t);
        assert!(
            (tr.q[k][1] - want[1]).abs() <= 1e-9,
            "t = {t}: {:?} vs {want:?}",
            tr.q[k]
        );
        assert!((tr.qdot[k][1] - want[3]).abs() <= 1e-9, "t = {t}");
    }
    for i in 0..400 {
        let t = 0.0049 * f64::from(i) + 1e-4;
        if tr.jumps.iter().any(|j| (j.t - t).abs() < 1e-6) {
            continue;
        }
        let (q, v) = tr.at(t).expect("inside the run");
        let want = c.state(t);
        assert!(
            (q[1] - want[1]).abs() <= 1e-9 && (v[1] - want[3]).abs() <= 1e-9,
            "t = {t}"
        );
    }
}

#[test]
fn resetting_events_on_a_constrained_run_are_refused() {
    use crate::support::quaternion_top::QuaternionTop;
    let top = QuaternionTop {
        i_perp: 1.0,
        i_par: 0.5,
        mgl: 1.0,
    };
    let e = Simulation::constrained(&top, [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0])
        .event(Event::zero_crossing("w", |_t, q: &[f64; 4], _v| q[0]).reset(|_t, q, v| (*q, *v)))
        .until(1.0)
        .run()
        .expect_err("refused");
    assert!(e.to_string().contains("resets the state"), "{e}");
}
