//! A system with dissipation and a generalized force costs no more than the same terms written
//! by hand: the damped driven pendulum's accelerations (16 states per iteration) and a DOP853
//! run, `#[lagrangian]` (symbolic and jets) against a hand-written closed form, in one run.
//!
//! Run: `cargo bench --bench forces`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use lagrange::prelude::*;

use driven_pendulum_system::DrivenPendulum;
use lagrange_examples::driven_pendulum_system;

/// The same pendulum in run-time jets.
pub struct DrivenPendulumJets {
    pub m: f64,
    pub l: f64,
    pub g: f64,
    pub b: f64,
    pub a: f64,
    pub w: f64,
}

#[lagrangian(mode = "jets")]
impl DrivenPendulumJets {
    fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
        0.5 * self.m * self.l * self.l * theta_dot.powi(2) + self.m * self.g * self.l * theta.cos()
    }
    fn dissipation(&self, (theta, theta_dot): Coord) -> Scalar {
        0.5 * self.b * theta_dot.powi(2)
    }
    fn forces(&self, (theta, theta_dot): Coord, t: Time) -> [Scalar; 1] {
        [self.a * (self.w * t).cos()]
    }
}

/// The baseline: the equation of motion written by hand, behind the same trait.
pub struct HandPendulum(DrivenPendulum);

impl Lagrangian<1> for HandPendulum {
    const COORDINATES: [&'static str; 1] = ["theta"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    const ENERGY_CONSERVED: bool = false;
    fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
        let p = &self.0;
        v[0] * v[0] * (0.5 * p.m * p.l * p.l) + q[0].cos() * (p.m * p.g * p.l)
    }
    fn dissipation<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S {
        v[0] * v[0] * (0.5 * self.0.b)
    }
    fn generalized_forces<S: Scalar>(&self, _q: &[S; 1], _v: &[S; 1], t: S) -> [S; 1] {
        [(t * self.0.w).cos() * self.0.a]
    }
    #[inline(always)]
    fn accelerations(&self, q: &[f64; 1], v: &[f64; 1], t: f64) -> Result<[f64; 1], DynamicsError> {
        let p = &self.0;
        let ml2 = p.m * p.l * p.l;
        Ok([(p.a * (p.w * t).cos() - p.b * v[0] - p.m * p.g * p.l * q[0].sin()) / ml2])
    }
}

#[inline(never)]
fn via_trait<L: Lagrangian<1>>(sys: &L, q: &[f64; 1], v: &[f64; 1], t: f64) -> [f64; 1] {
    sys.accelerations(q, v, t).unwrap_or([f64::NAN])
}

fn run<L: Lagrangian<1>>(sys: &L) -> Trajectory<1> {
    Simulation::new(sys, [0.2], [0.0])
        .method(Method::Dop853 {
            rtol: 1e-10,
            atol: 1e-12,
        })
        .until(200.0)
        .run()
        .expect("the pendulum integrates")
}

fn bench(c: &mut Criterion) {
    let params = || DrivenPendulum {
        m: 1.3,
        l: 0.8,
        g: 9.81,
        b: 0.6,
        a: 7.0,
        w: 2.0 / 3.0 * (9.81_f64 / 0.8).sqrt(),
    };
    let sym = params();
    let p = params();
    let jets = DrivenPendulumJets {
        m: p.m,
        l: p.l,
        g: p.g,
        b: p.b,
        a: p.a,
        w: p.w,
    };
    let hand = HandPendulum(params());
    let states: Vec<([f64; 1], [f64; 1], f64)> = (0..16)
        .map(|k| {
            let x = f64::from(k);
            ([-2.5 + 0.33 * x], [1.7 - 0.2 * x], 0.37 * x)
        })
        .collect();
    for (q, v, t) in &states {
        let want = via_trait(&hand, q, v, *t)[0];
        for got in [via_trait(&sym, q, v, *t)[0], via_trait(&jets, q, v, *t)[0]] {
            assert!(
                (got - want).abs() <= 1e-12 * want.abs().max(1.0),
                "{got} vs {want}"
            );
        }
    }
    let mut g = c.benchmark_group("driven_pendulum_accelerations_x16");
    for (name, f) in [
        (
            "hand_written",
            &(|q: &[f64; 1], v: &[f64; 1], t: f64| via_trait(&hand, q, v, t))
                as &dyn Fn(&[f64; 1], &[f64; 1], f64) -> [f64; 1],
        ),
        ("lagrangian_symbolic", &|q, v, t| via_trait(&sym, q, v, t)),
        ("lagrangian_jets", &|q, v, t| via_trait(&jets, q, v, t)),
    ] {
        g.bench_function(name, |b| {
            b.iter(|| {
                for (q, v, t) in black_box(&states) {
                    black_box(f(q, v, *t));
                }
            })
        });
    }
    g.finish();
    let mut g = c.benchmark_group("driven_pendulum_dop853_t200");
    g.sample_size(20);
    g.bench_function("hand_written", |b| b.iter(|| run(black_box(&hand))));
    g.bench_function("lagrangian_symbolic", |b| b.iter(|| run(black_box(&sym))));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
