//! Large systems on a spawned thread with the default 2 MiB stack: every method at 32 and 64
//! coordinates (Radau5 at 64), RATTLE with 16 constraints, and every path that forms a Jacobian
//! (linearize, eigenvalues, equilibrium, linearize_on_constraints, Radau5 alone and in an
//! ensemble, sensitivities, shooting, Lyapunov) at 64 coordinates. A 32-link chain's variational step, and
//! from 24 coordinates every Jacobian path (its jets carried the whole (2N)² Hessian and its
//! rate per number), overflowed such a stack and aborted the process.

use lagrange::prelude::*;
use nalgebra::Complex;

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

const CHAIN: Chain64 = Chain64 {
    m: 1.0,
    l: 0.1,
    g: 9.81,
};

/// A bent initial shape of the 64-link chain.
fn bent() -> [f64; 64] {
    core::array::from_fn(|i| 0.05 * (1.0 + (i as f64 * 0.37).sin()))
}

/// 64 unit oscillators, the last two held together (q₆₃ = q₆₂): 64 coordinates, one constraint.
#[derive(Clone, Copy)]
pub struct Held64;

#[lagrangian]
impl Held64 {
    fn lagrangian(&self, (q, q_dot): Coords<64>) -> Scalar {
        let mut lag = 0.0;
        for k in 0..q.len() {
            lag += 0.5 * (q_dot[k] * q_dot[k] - q[k] * q[k]);
        }
        lag
    }
    fn constraints(&self, (q, _q_dot): Coords<64>) -> [Scalar; 1] {
        [q[63] - q[62]]
    }
}

/// The largest |real part| of eigenvalues against their largest size.
fn worst_real_part(l: &[Complex<f64>]) -> f64 {
    let size = l.iter().fold(0.0_f64, |m, z| m.max(z.norm()));
    l.iter().fold(0.0_f64, |m, z| m.max(z.re.abs())) / size
}

/// The linearization, its eigenvalues and the equilibrium of a 64-link chain: the hanging chain
/// is a centre (2N imaginary eigenvalues), found again from a bent guess.
#[test]
fn linearize_and_equilibrium_of_a_64_link_chain_on_a_2_mib_stack() {
    let (worst, q, n) = in_thread(|| {
        let lin = CHAIN.linearize(&[0.0; 64], &[0.0; 64], 0.0).unwrap();
        let l = lin.eigenvalues().unwrap();
        let q = equilibrium(&CHAIN, &bent(), 0.0).unwrap();
        (worst_real_part(&l), q, l.len())
    });
    assert_eq!(n, 128);
    assert!(worst < 1e-9, "hanging chain: relative real part {worst:e}");
    assert!(q.iter().all(|x| x.abs() < 1e-10), "{q:?}");
}

/// `linearize_on_constraints` of 64 coordinates with one constraint: the 63 independent
/// coordinates oscillate at ω = 1.
#[test]
fn linearize_on_constraints_of_a_64_coordinate_chain_on_a_2_mib_stack() {
    let l = in_thread(|| {
        let lin = Held64
            .linearize_on_constraints(&[0.0; 64], &[0.0; 64], 0.0)
            .unwrap();
        let names = &Held64::COORDINATES[..63];
        lin.eigenvalues(names, names).unwrap()
    });
    // ±i for the 62 free oscillators and for the held pair (its mass and stiffness both double).
    assert_eq!(l.len(), 126);
    for z in &l {
        assert!(
            z.re.abs() < 1e-12 && (z.im.abs() - 1.0).abs() < 1e-12,
            "{z}"
        );
    }
}

/// Φ of a 64-link chain (DOP853 with the variational equations): its first column against the
/// difference of two runs.
#[test]
fn sensitivities_of_a_64_link_chain_on_a_2_mib_stack() {
    let (column, fd) = in_thread(|| {
        let method = Method::Dop853 {
            rtol: 1e-11,
            atol: 1e-11,
        };
        let until = 0.02;
        let run = Simulation::new(&CHAIN, bent(), [0.0; 64])
            .method(method)
            .until(until)
            .sensitivity()
            .run()
            .unwrap();
        let phi = run.final_phi();
        let column: Vec<f64> = (0..128).map(|i| phi[(i, 0)]).collect();
        let h = 1e-6;
        let end = |dq: f64| {
            let mut q0 = bent();
            q0[0] += dq;
            let tr = Simulation::new(&CHAIN, q0, [0.0; 64])
                .method(method)
                .until(until)
                .run()
                .unwrap();
            let (q, v) = (*tr.q.last().unwrap(), *tr.qdot.last().unwrap());
            q.into_iter().chain(v).collect::<Vec<f64>>()
        };
        let (up, down) = (end(h), end(-h));
        let fd: Vec<f64> = up
            .iter()
            .zip(&down)
            .map(|(a, b)| (a - b) / (2.0 * h))
            .collect();
        (column, fd)
    });
    let size = fd.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    for (i, (a, b)) in column.iter().zip(&fd).enumerate() {
        assert!((a - b).abs() <= 1e-6 * size, "Φ[{i}, 0] = {a} against {b}");
    }
}

/// Lyapunov exponents and one shooting iteration of the 64-link chain: they run (a shooting
/// iteration that does not converge is a typed error, not an abort).
#[test]
fn lyapunov_and_shooting_of_a_64_link_chain_on_a_2_mib_stack() {
    use lagrange::sensitivity::{Lyapunov, Shooting};
    let (exponents, shooting) = in_thread(|| {
        let s = Lyapunov::new(&CHAIN, bent(), [0.0; 64])
            .duration(0.02)
            .renormalize_every(0.01)
            .directions(2)
            .tolerances(1e-8, 1e-8)
            .compute()
            .unwrap();
        let shooting = Shooting::autonomous(&CHAIN, bent(), [0.0; 64], 0.02)
            .method(Method::Dop853 {
                rtol: 1e-6,
                atol: 1e-6,
            })
            .max_iterations(1)
            .find()
            .map(|o| o.period)
            .map_err(|e| e.to_string());
        (s.exponents, shooting)
    });
    assert!(
        exponents.len() == 2 && exponents[0] >= exponents[1] && exponents[1].is_finite(),
        "{exponents:?}"
    );
    if let Err(e) = shooting {
        assert!(e.contains("iteration") || e.contains("converge"), "{e}");
    }
}

/// Radau5 on the 64-link chain, alone on a 2 MiB thread and as an ensemble of members on two
/// threads (rayon's threads have the default stack: one member's Newton matrix aborted the
/// whole process).
#[test]
fn radau5_runs_a_64_link_chain_alone_and_in_an_ensemble() {
    let drift = in_thread(|| {
        Simulation::new(&CHAIN, bent(), [0.0; 64])
            .method(Method::Radau5 {
                rtol: 1e-8,
                atol: 1e-8,
            })
            .until(0.02)
            .run()
            .map(|tr| tr.invariants().energy.map(|d| d.max_rel))
            .map_err(|e| e.to_string())
    });
    let drift = drift.unwrap().unwrap();
    assert!(drift < 1e-4, "energy drift {drift:e}");
    use lagrange::ensemble::{Ensemble, Member};
    let r = Ensemble::new(2, |i| {
        let mut q0 = bent();
        q0[0] += 0.01 * i as f64;
        Member::new(CHAIN, q0, [0.0; 64])
    })
    .configure(|s| {
        s.method(Method::Radau5 {
            rtol: 1e-8,
            atol: 1e-8,
        })
        .until(0.02)
    })
    .threads(2)
    .run();
    for tr in &r.results {
        let tr = tr.as_ref().expect("a regular run");
        let drift = tr.invariants().energy.map(|d| d.max_rel).unwrap();
        assert!(drift < 1e-4, "energy drift {drift:e}");
    }
}

/// A system above 300 generated operations has no lanes code: every
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
