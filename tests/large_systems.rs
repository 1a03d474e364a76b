//! Regressions of the adversarial review (issue 33) on large systems: every method at 32 and 64
//! coordinates, and RATTLE with 16 constraints, inside a spawned thread with the default 2 MiB
//! stack (a 32-link chain's variational step overflowed it and aborted the process).

use lagrange::prelude::*;

/// An N-link pendulum chain written with `Coords<N>` and a loop.
macro_rules! chain {
    ($name:ident, $n:literal $(, $arg:ident)?) => {
        #[derive(Clone, Copy, Debug)]
        pub struct $name {
            pub m: f64,
            pub l: f64,
            pub g: f64,
        }

        #[lagrangian$(($arg))?]
        impl $name {
            fn lagrangian(&self, (q, q_dot): Coords<$n>) -> Scalar {
                let (s, c) = q[0].sin_cos();
                let mut vx = self.l * c * q_dot[0];
                let mut vy = self.l * s * q_dot[0];
                let mut y = -self.l * c;
                let mut lag = 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
                for k in 1..q.len() {
                    let (s, c) = q[k].sin_cos();
                    vx += self.l * c * q_dot[k];
                    vy += self.l * s * q_dot[k];
                    y -= self.l * c;
                    lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
                }
                lag
            }
        }
    };
}

chain!(Chain32, 32);
chain!(Chain64, 64);

// An 8-link chain (478 generated operations) with `#[lagrangian(lanes)]`: its lanes code
// whatever its size.
chain!(Chain8Lanes, 8, lanes);

/// 16 particles in the plane, each on the unit circle, under gravity: 32 coordinates, 16
/// constraints.
#[derive(Clone, Copy, Debug)]
pub struct Beads16;

#[lagrangian]
impl Beads16 {
    fn lagrangian(&self, (q, q_dot): Coords<32>) -> Scalar {
        let mut l = 0.0;
        for i in 0..16 {
            l += 0.5 * (q_dot[2 * i] * q_dot[2 * i] + q_dot[2 * i + 1] * q_dot[2 * i + 1])
                - 9.81 * q[2 * i + 1];
        }
        l
    }
    fn constraints(&self, (q, _q_dot): Coords<32>) -> [Scalar; 16] {
        [
            q[0] * q[0] + q[1] * q[1] - 1.0,
            q[2] * q[2] + q[3] * q[3] - 1.0,
            q[4] * q[4] + q[5] * q[5] - 1.0,
            q[6] * q[6] + q[7] * q[7] - 1.0,
            q[8] * q[8] + q[9] * q[9] - 1.0,
            q[10] * q[10] + q[11] * q[11] - 1.0,
            q[12] * q[12] + q[13] * q[13] - 1.0,
            q[14] * q[14] + q[15] * q[15] - 1.0,
            q[16] * q[16] + q[17] * q[17] - 1.0,
            q[18] * q[18] + q[19] * q[19] - 1.0,
            q[20] * q[20] + q[21] * q[21] - 1.0,
            q[22] * q[22] + q[23] * q[23] - 1.0,
            q[24] * q[24] + q[25] * q[25] - 1.0,
            q[26] * q[26] + q[27] * q[27] - 1.0,
            q[28] * q[28] + q[29] * q[29] - 1.0,
            q[30] * q[30] + q[31] * q[31] - 1.0,
        ]
    }
}

/// Runs `f` in a thread with the default 2 MiB stack (a stack overflow aborts the test binary).
fn in_thread<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    match std::thread::Builder::new()
        .stack_size(2 << 20)
        .spawn(f)
        .map(|h| h.join())
    {
        Ok(Ok(t)) => t,
        Ok(Err(_)) => panic!("the run panicked"),
        Err(e) => panic!("no thread: {e}"),
    }
}

const METHODS: [Method; 5] = [
    Method::Rk4 { dt: 1e-2 },
    Method::DormandPrince {
        rtol: 1e-8,
        atol: 1e-8,
    },
    Method::Dop853 {
        rtol: 1e-8,
        atol: 1e-8,
    },
    Method::VariationalMidpoint { dt: 1e-2 },
    Method::Taylor { tol: 1e-10 },
];

/// Every method on a chain of N links from a bent state: a run, or a typed refusal (the Taylor
/// method has no series above 1024 slots), never an abort; the energy is kept.
fn every_method<L, const N: usize>(sys: L)
where
    L: Lagrangian<N> + Copy + Send + 'static,
{
    for method in METHODS {
        let r = in_thread(move || {
            let q0: [f64; N] = core::array::from_fn(|i| 0.3 + 0.01 * i as f64);
            Simulation::new(&sys, q0, [0.0; N])
                .method(method)
                .until(0.03)
                .run()
                .map(|tr| tr.invariants().energy.map(|d| d.max_rel))
                .map_err(|e| e.to_string())
        });
        match (method, r) {
            (_, Ok(drift)) => {
                let drift = drift.expect("a conservative chain reports its energy drift");
                assert!(
                    drift < 1e-3,
                    "{method:?} at N = {N}: energy drift {drift:e}"
                );
            }
            (Method::Taylor { .. }, Err(e)) => assert!(e.contains("Taylor"), "{e}"),
            (_, Err(e)) => panic!("{method:?} at N = {N}: {e}"),
        }
    }
}

#[test]
fn every_method_runs_a_32_link_chain_on_a_2_mib_stack() {
    every_method(Chain32 {
        m: 1.0,
        l: 0.1,
        g: 9.81,
    });
}

#[test]
fn every_method_runs_a_64_link_chain_on_a_2_mib_stack() {
    every_method(Chain64 {
        m: 1.0,
        l: 0.1,
        g: 9.81,
    });
}

/// RATTLE (the variational method with constraints) and the projected DOP853 with 32
/// coordinates and 16 constraints.
#[test]
fn constrained_runs_with_16_constraints_on_a_2_mib_stack() {
    for method in [
        Method::VariationalMidpoint { dt: 1e-2 },
        Method::Dop853 {
            rtol: 1e-8,
            atol: 1e-8,
        },
    ] {
        let pos = in_thread(move || {
            let q0: [f64; 32] = core::array::from_fn(|i| if i % 2 == 0 { 1.0 } else { 0.0 });
            let v0: [f64; 32] = core::array::from_fn(|i| if i % 2 == 0 { 0.0 } else { 0.5 });
            Simulation::constrained(&Beads16, q0, v0)
                .method(method)
                .until(0.05)
                .run()
                .map(|tr| tr.invariants().constraints.map(|c| c.position))
                .map_err(|e| e.to_string())
        });
        match pos {
            Ok(Some(p)) => assert!(p < 1e-9, "{method:?}: |g| = {p:e}"),
            other => panic!("{method:?}: {other:?}"),
        }
    }
}

/// A system above 300 generated operations has no lanes code (issue 33, item 6): every
/// `Ensemble` instantiates the lanes engines, which inlined a 12-link chain's lanes code at each
/// DOP853 stage and took its release build from 11 s to 123 s. Small systems keep theirs.
#[test]
fn only_small_systems_get_lanes_code() {
    const { assert!(!Chain32::COMPILED.lanes && !Chain64::COMPILED.lanes) };
    const { assert!(crate::support::systems::HeavyTop::COMPILED.lanes) };
    const { assert!(!crate::support::systems::Chain16::COMPILED.lanes) };
    const { assert!(Chain8Lanes::COMPILED.lanes) };
}

/// `#[lagrangian(lanes)]` on a system above the size bound: its ensemble runs in lanes, and each
/// member equals its single run to round-off (the vector sin and cos are within 1 ulp).
#[test]
fn lanes_on_request_equal_single_runs() {
    use lagrange::ensemble::{Ensemble, Member};
    let c = Chain8Lanes {
        m: 1.0,
        l: 1.0,
        g: 9.81,
    };
    let q0 = |i: usize| [0.3 + 0.01 * i as f64; 8];
    let method = Method::Dop853 {
        rtol: 1e-10,
        atol: 1e-10,
    };
    let r = Ensemble::new(6, |i| Member::new(c, q0(i), [0.0; 8]))
        .configure(move |s| s.method(method).until(2.0).sample_at([0.0; 0]))
        .threads(1)
        .run();
    for (i, tr) in r.results.iter().enumerate() {
        let lane = tr.as_ref().expect("a regular run");
        let single = Simulation::new(&c, q0(i), [0.0; 8])
            .method(method)
            .until(2.0)
            .sample_at([0.0; 0])
            .run()
            .expect("a regular run");
        let (a, b) = (lane.q[lane.q.len() - 1], single.q[single.q.len() - 1]);
        for k in 0..8 {
            assert!(
                (a[k] - b[k]).abs() < 1e-9,
                "member {i}, q[{k}]: {} against {}",
                a[k],
                b[k]
            );
        }
    }
}
