//! Large systems on a spawned thread with the default 2 MiB stack: every method at 32 and 64
//! coordinates (Radau5 at 64), RATTLE with 16 constraints, and every path that forms a Jacobian
//! (linearize, eigenvalues, equilibrium, linearize_on_constraints, Radau5 alone and in an
//! ensemble, sensitivities, shooting, Lyapunov) at 64 coordinates. A 32-link chain's variational step, and
//! from 24 coordinates every Jacobian path (its jets carried the whole (2N)² Hessian and its
//! rate per number), overflowed such a stack and aborted the process. So did every path of a
//! 64-coordinate system in jets mode or written by hand (its pieces, momenta and energy came from
//! one `ElJet` of N² + 3N + 3 numbers: 9 MiB of stack at 64): they are checked here against closed
//! forms, and the pieces by columns against the `ElJet`'s where both run (17 to 24 coordinates).

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

// ---- Jets mode and hand-written impls at 64 coordinates: their pieces are taken by columns
// above `EL_BY_COLUMNS_ABOVE` (a 64-coordinate `ElJet` evaluation needs 9 MiB of stack). ----

/// 64 unit masses in a line between two walls, joined by springs k, with a constant kinetic
/// coupling c between neighbours and a mass that grows with the displacement:
/// L = Σ ½ (1 + ε qᵢ²) q̇ᵢ² + c Σ q̇ᵢ q̇ᵢ₋₁ − ½ k (q₀² + q₆₃² + Σ (qᵢ − qᵢ₋₁)²), in jets mode.
#[derive(Clone, Copy, Debug)]
pub struct Springs64 {
    pub k: f64,
    pub c: f64,
    pub eps: f64,
}

#[lagrangian(mode = "jets")]
impl Springs64 {
    fn lagrangian(&self, (q, q_dot): Coords<64>) -> Scalar {
        let mut lag = -0.5 * self.k * (q[0] * q[0] + q[63] * q[63]);
        for i in 0..q.len() {
            lag += 0.5 * (1.0 + self.eps * q[i] * q[i]) * q_dot[i] * q_dot[i];
        }
        // The left neighbour carried along (`q[i - 1]` does not compile in jets mode: the
        // rewrite takes the index arithmetic for a mixed operation on numbers).
        let (mut left, mut left_dot) = (q[0], q_dot[0]);
        for i in 1..q.len() {
            let d = q[i] - left;
            lag += self.c * q_dot[i] * left_dot - 0.5 * self.k * d * d;
            left = q[i];
            left_dot = q_dot[i];
        }
        lag
    }
}

/// [`Springs64`] written by hand, for any number of masses.
#[derive(Clone, Copy, Debug)]
pub struct HandSprings<const N: usize> {
    pub k: f64,
    pub c: f64,
    pub eps: f64,
}

impl<const N: usize> Lagrangian<N> for HandSprings<N> {
    const COORDINATES: [&'static str; N] = ["q"; N];
    const CYCLIC: [bool; N] = [false; N];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; N], v: &[S; N], _t: S) -> S {
        let mut l = (q[0] * q[0] + q[N - 1] * q[N - 1]) * (-0.5 * self.k);
        for i in 0..N {
            l += (q[i] * q[i] * self.eps + 1.0) * v[i] * v[i] * 0.5;
        }
        for i in 1..N {
            let d = q[i] - q[i - 1];
            l += v[i] * v[i - 1] * self.c - d * d * (0.5 * self.k);
        }
        l
    }
}

const K: f64 = 1.3;
const C: f64 = 0.1;
const JETS: Springs64 = Springs64 {
    k: K,
    c: C,
    eps: 0.3,
};
const HAND: HandSprings<64> = HandSprings {
    k: K,
    c: C,
    eps: 0.3,
};
/// The same without the growing mass: linear, its normal modes are the motions.
const JETS_LINEAR: Springs64 = Springs64 {
    k: K,
    c: C,
    eps: 0.0,
};
const HAND_LINEAR: HandSprings<64> = HandSprings {
    k: K,
    c: C,
    eps: 0.0,
};

/// Normal mode j (1-based) of n masses with fixed ends: the shape sin((i + 1) θ), θ = jπ/(n + 1),
/// and ω² = 4k sin²(θ/2) / (1 + 2c cos θ) (M = 1 + c T and K = k (2 − T) share the shapes, T the
/// neighbour matrix with eigenvalue 2 cos θ); at c = 0, ω = 2√k sin(jπ/(2(n + 1))).
fn mode(j: usize, n: usize, k: f64, c: f64) -> (Vec<f64>, f64) {
    let theta = j as f64 * std::f64::consts::PI / (n + 1) as f64;
    let shape = (0..n).map(|i| ((i + 1) as f64 * theta).sin()).collect();
    let s = (theta / 2.0).sin();
    (
        shape,
        (4.0 * k * s * s / (1.0 + 2.0 * c * theta.cos())).sqrt(),
    )
}

/// The largest |a − b| against the largest |b|.
fn rel(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let size = b.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
        / size
}

/// A state away from every symmetry.
fn state64() -> ([f64; 64], [f64; 64]) {
    (
        core::array::from_fn(|i| 0.3 * (i as f64 * 0.7).sin()),
        core::array::from_fn(|i| 0.5 * (i as f64 * 0.3).cos() + 0.1),
    )
}

/// pieces, accelerations, mass_matrix, energy, momenta and energy_and_momenta of a spring chain
/// (k, c, ε) at 64 coordinates on a 2 MiB thread, against the closed forms M = 1 + ε q² on the
/// diagonal and c beside it, f = −ε q q̇² − k (2qᵢ − qᵢ₋₁ − qᵢ₊₁), h = T + V,
/// p = (1 + ε q²) q̇ + c (q̇ᵢ₋₁ + q̇ᵢ₊₁): 1e-13 relative to each piece's largest entry, and
/// M q̈ = f to 1e-12.
fn closed_form_pieces<L: Lagrangian<64> + Copy + Send + 'static>(sys: L, k: f64, c: f64, eps: f64) {
    in_thread(move || {
        let (q, v) = state64();
        let at = |x: &[f64; 64], i: isize| {
            if (0..64).contains(&i) {
                x[i as usize]
            } else {
                0.0
            }
        };
        let mut mass = vec![0.0; 64 * 64];
        let (mut f, mut p) = (vec![0.0; 64], vec![0.0; 64]);
        let mut h = 0.0;
        for i in 0..64 {
            let ii = i as isize;
            mass[i * 64 + i] = 1.0 + eps * q[i] * q[i];
            if i > 0 {
                mass[i * 64 + i - 1] = c;
                mass[(i - 1) * 64 + i] = c;
                h += c * v[i] * v[i - 1] + 0.5 * k * (q[i] - q[i - 1]).powi(2);
            }
            f[i] = -eps * q[i] * v[i] * v[i] - k * (2.0 * q[i] - at(&q, ii - 1) - at(&q, ii + 1));
            p[i] = (1.0 + eps * q[i] * q[i]) * v[i] + c * (at(&v, ii - 1) + at(&v, ii + 1));
            h += 0.5 * (1.0 + eps * q[i] * q[i]) * v[i] * v[i];
        }
        h += 0.5 * k * (q[0] * q[0] + q[63] * q[63]);

        let pieces = sys.pieces(&q, &v, 0.0);
        let upper: Vec<f64> = (0..64 * 64)
            .map(|e| pieces.mass_entry(e / 64, e % 64))
            .collect();
        assert!(rel(&upper, &mass) < 1e-13, "M: {:e}", rel(&upper, &mass));
        let fl = pieces.lagrangian_force;
        assert!(rel(&fl, &f) < 1e-13, "f: {:e}", rel(&fl, &f));
        assert_eq!(pieces.applied, [0.0; 64]);
        let mm = sys.mass_matrix(&q, &v, 0.0);
        let mm: Vec<f64> = (0..64 * 64).map(|e| mm[(e / 64, e % 64)]).collect();
        assert!(rel(&mm, &mass) < 1e-13, "mass_matrix");

        let a = sys
            .accelerations(&q, &v, 0.0)
            .expect("M is positive definite");
        let ma: Vec<f64> = (0..64)
            .map(|i| (0..64).map(|j| mass[i * 64 + j] * a[j]).sum())
            .collect();
        assert!(rel(&ma, &f) < 1e-12, "M q̈ − f: {:e}", rel(&ma, &f));

        let (e, mom) = sys.energy_and_momenta(&q, &v, 0.0);
        assert!((e - h).abs() < 1e-13 * h, "h = {e} against {h}");
        assert!((sys.energy(&q, &v, 0.0) - h).abs() < 1e-13 * h);
        assert!(rel(&mom, &p) < 1e-13 && rel(&sys.momenta(&q, &v, 0.0), &p) < 1e-13);
        assert_eq!(sys.power(&q, &v, 0.0), 0.0);
    });
}

#[test]
fn pieces_of_64_coordinates_in_jets_mode_and_by_hand_match_closed_forms_on_a_2_mib_stack() {
    closed_form_pieces(JETS, K, C, 0.3);
    closed_form_pieces(HAND, K, C, 0.3);
}

/// A chain of N pendulums (unit lengths and masses) under a gravity that varies in time, with
/// an explicit q̇-t coupling, dissipation and a generalized force: every part of the pieces
/// (a full M that depends on q, ∂²L/∂q̇∂q q̇, ∂²L/∂q̇∂t, −∂D/∂q̇, Q), for any N.
#[derive(Clone, Copy, Debug)]
pub struct Rich<const N: usize>;

impl<const N: usize> Lagrangian<N> for Rich<N> {
    const COORDINATES: [&'static str; N] = ["q"; N];
    const CYCLIC: [bool; N] = [false; N];
    const AUTONOMOUS: bool = false;
    const ENERGY_CONSERVED: bool = false;
    const MOMENTUM_CONSERVED: [bool; N] = [false; N];
    fn lagrangian<S: Scalar>(&self, q: &[S; N], v: &[S; N], t: S) -> S {
        let zero = S::constant(0.0);
        let (mut vx, mut vy, mut y, mut l) = (zero, zero, zero, zero);
        let g = (t * 0.7).cos() * 2.0 + 9.81;
        for i in 0..N {
            let (s, c) = (q[i].sin(), q[i].cos());
            vx += c * v[i];
            vy += s * v[i];
            y -= c;
            l += (vx * vx + vy * vy) * 0.5 - y * g;
        }
        l + v[0] * q[N - 1] * t * 0.2
    }
    fn dissipation<S: Scalar>(&self, q: &[S; N], v: &[S; N], _t: S) -> S {
        let mut d = S::constant(0.0);
        for i in 0..N {
            d += v[i] * v[i] * (q[i] * q[i] + 1.0) * 0.05;
        }
        d
    }
    fn generalized_forces<S: Scalar>(&self, q: &[S; N], _v: &[S; N], t: S) -> [S; N] {
        core::array::from_fn(|i| (q[i] + t).sin() * 0.1)
    }
}

/// The pieces by columns against the pieces from one `ElJet` where both are valid (17 to 24
/// coordinates, just above the threshold): M, f_L and Q − ∂D/∂q̇ to 1e-13 relative to each
/// piece's largest entry; and the defaults (by columns) of the momenta and the energy against
/// the `ElJet`'s.
fn columns_against_el_jet<const N: usize>() {
    use lagrange::lagrangian::{jet_pieces_by_columns, jet_pieces_whole};
    const { assert!(N > lagrange::jet::EL_BY_COLUMNS_ABOVE) };
    in_thread(|| {
        let q: [f64; N] = core::array::from_fn(|i| 0.4 * (i as f64 * 0.9).sin() + 0.1);
        let v: [f64; N] = core::array::from_fn(|i| 0.6 * (i as f64 * 0.4).cos() - 0.2);
        let t = 1.7;
        let (a, b) = (
            jet_pieces_by_columns(&Rich::<N>, &q, &v, t),
            jet_pieces_whole(&Rich::<N>, &q, &v, t),
        );
        // The default is the by-columns one, bit for bit.
        assert_eq!(Rich::<N>.pieces(&q, &v, t), a);
        let upper = |p: &lagrange::eom::Pieces<N>| -> Vec<f64> {
            (0..N * N).map(|e| p.mass_entry(e / N, e % N)).collect()
        };
        let (m, f, app) = (
            rel(&upper(&a), &upper(&b)),
            rel(&a.lagrangian_force, &b.lagrangian_force),
            rel(&a.applied, &b.applied),
        );
        assert!(
            m < 1e-13 && f < 1e-13 && app < 1e-13,
            "N = {N}: M {m:e}, f {f:e}, Q − ∂D/∂q̇ {app:e}"
        );
        let el = lagrange::el_jet(&Rich::<N>, &q, &v, t);
        let p = Rich::<N>.momenta(&q, &v, t);
        assert!(rel(&p, &el.grad_qdot()) < 1e-14, "N = {N}: momenta");
        let h: f64 = (0..N).map(|i| v[i] * el.grad_qdot()[i]).sum::<f64>() - el.value();
        assert!(
            (Rich::<N>.energy(&q, &v, t) - h).abs() < 1e-13 * h.abs(),
            "N = {N}: energy"
        );
        // The power: (Q − ∂D/∂q̇)·q̇ − ∂L/∂t, with ∂L/∂t by a central difference (1e-7).
        let dt = 1e-5;
        let lt = |t: f64| Rich::<N>.lagrangian(&q, &v, t);
        let dl = (lt(t + dt) - lt(t - dt)) / (2.0 * dt);
        let power: f64 = (0..N).map(|i| b.applied[i] * v[i]).sum::<f64>() - dl;
        assert!(
            (Rich::<N>.power(&q, &v, t) - power).abs() < 1e-7 * power.abs(),
            "N = {N}: power"
        );
    });
}

#[test]
fn pieces_by_columns_equal_the_el_jet_from_17_to_24_coordinates() {
    columns_against_el_jet::<17>();
    columns_against_el_jet::<18>();
    columns_against_el_jet::<19>();
    columns_against_el_jet::<20>();
    columns_against_el_jet::<21>();
    columns_against_el_jet::<22>();
    columns_against_el_jet::<23>();
    columns_against_el_jet::<24>();
}

/// Linearize and eigenvalues at rest: ±iωⱼ with the closed-form ωⱼ of [`mode`] (1e-10
/// relative); the equilibrium found again from a bent guess (1e-10).
fn linearize_closed_form<L: Lagrangian<64> + Copy + Send + 'static>(sys: L) {
    let (mut im, q) = in_thread(move || {
        let lin = sys.linearize(&[0.0; 64], &[0.0; 64], 0.0).unwrap();
        let l = lin.eigenvalues().unwrap();
        assert!(worst_real_part(&l) < 1e-9, "{:e}", worst_real_part(&l));
        let im: Vec<f64> = l.iter().map(|z| z.im.abs()).collect();
        (im, equilibrium(&sys, &bent(), 0.0).unwrap())
    });
    im.sort_by(f64::total_cmp);
    let mut omega: Vec<f64> = (1..=64).flat_map(|j| [mode(j, 64, K, C).1; 2]).collect();
    omega.sort_by(f64::total_cmp);
    assert!(rel(&im, &omega) < 1e-10, "ω: {:e}", rel(&im, &omega));
    assert!(q.iter().all(|x| x.abs() < 1e-10), "{q:?}");
}

#[test]
fn linearize_eigenvalues_and_equilibrium_of_64_coordinates_in_jets_mode_and_by_hand() {
    linearize_closed_form(JETS);
    linearize_closed_form(HAND);
}

/// Normal mode 48 of the linear chain, amplitude 0.1, from rest: q(t) = 0.1 shape cos ωt.
fn mode_start() -> ([f64; 64], Vec<f64>, f64) {
    let (shape, omega) = mode(48, 64, K, C);
    (core::array::from_fn(|i| 0.1 * shape[i]), shape, omega)
}

const T_RUN: f64 = 0.2;

/// Every method on the linear chain (64 coordinates) on a 2 MiB thread, from a normal mode:
/// q(T) against 0.1 shape cos ωT (DOP853 and Dormand–Prince at 1e-10: 1e-8; Radau5 at 1e-8:
/// 1e-6; RK4 and the variational midpoint method at dt = 0.01: 1e-6 and 1e-4 relative to the
/// amplitude); the Taylor method refused with a typed error (no series in jets mode or by hand).
fn every_method_closed_form<L: Lagrangian<64> + Copy + Send + 'static>(sys: L) {
    let (q0, shape, omega) = mode_start();
    let exact: Vec<f64> = shape
        .iter()
        .map(|s| 0.1 * s * (omega * T_RUN).cos())
        .collect();
    let tight = 1e-10;
    for (method, tol) in [
        (
            Method::Dop853 {
                rtol: tight,
                atol: tight,
            },
            1e-8,
        ),
        (
            Method::DormandPrince {
                rtol: tight,
                atol: tight,
            },
            1e-8,
        ),
        (
            Method::Radau5 {
                rtol: 1e-8,
                atol: 1e-8,
            },
            1e-6,
        ),
        (Method::Rk4 { dt: 1e-2 }, 1e-6),
        (Method::VariationalMidpoint { dt: 1e-2 }, 1e-4),
        (Method::Taylor { tol: 1e-10 }, 0.0),
    ] {
        let r = in_thread(move || {
            Simulation::new(&sys, q0, [0.0; 64])
                .method(method)
                .until(T_RUN)
                .run()
                .map(|tr| *tr.q.last().unwrap())
                .map_err(|e| e.to_string())
        });
        match (method, r) {
            (Method::Taylor { .. }, Err(e)) => assert!(e.contains("Taylor"), "{e}"),
            (_, Ok(q)) => {
                let err = rel(&q, &exact) * exact.iter().fold(0.0_f64, |m, x| m.max(x.abs())) / 0.1;
                assert!(err < tol, "{method:?}: {err:e}");
            }
            (_, r) => panic!("{method:?}: {r:?}"),
        }
    }
}

#[test]
fn every_method_runs_64_coordinates_in_jets_mode_on_a_2_mib_stack() {
    every_method_closed_form(JETS_LINEAR);
}

#[test]
fn every_method_runs_64_coordinates_by_hand_on_a_2_mib_stack() {
    every_method_closed_form(HAND_LINEAR);
}

/// `.sensitivity()` with the parameter k on the linear chain from a normal mode, on a 2 MiB
/// thread: ∂q(T)/∂k = −0.1 shape T sin(ωT) ω/(2k) (ω² ∝ k), to 1e-7 of its largest entry,
/// and against a central difference of two runs at k ± 1e-4 to 1e-6.
fn sensitivity_closed_form<L, F>(sys: L, build: F)
where
    L: Lagrangian<64> + Copy + Send + 'static,
    F: Fn(f64) -> L + Copy + Send + 'static,
{
    let (q0, shape, omega) = mode_start();
    let exact: Vec<f64> = shape
        .iter()
        .map(|s| -0.1 * s * T_RUN * (omega * T_RUN).sin() * omega / (2.0 * K))
        .collect();
    let (dk, fd) = in_thread(move || {
        let method = Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-12,
        };
        let run = Simulation::new(&sys, q0, [0.0; 64])
            .method(method)
            .until(T_RUN)
            .sensitivity()
            .parameter("k", K, build)
            .run()
            .unwrap();
        let d = run.dparams.last().unwrap();
        let dk: Vec<f64> = (0..64).map(|i| d[(i, 0)]).collect();
        let end = |k: f64| {
            let tr = Simulation::new(&build(k), q0, [0.0; 64])
                .method(method)
                .until(T_RUN)
                .run()
                .unwrap();
            *tr.q.last().unwrap()
        };
        let h = 1e-4;
        let (up, down) = (end(K + h), end(K - h));
        let fd: Vec<f64> = (0..64).map(|i| (up[i] - down[i]) / (2.0 * h)).collect();
        (dk, fd)
    });
    assert!(rel(&dk, &exact) < 1e-7, "∂q/∂k: {:e}", rel(&dk, &exact));
    assert!(
        rel(&fd, &dk) < 1e-6,
        "∂q/∂k against differences: {:e}",
        rel(&fd, &dk)
    );
}

#[test]
fn sensitivity_to_a_parameter_of_64_coordinates_in_jets_mode_and_by_hand() {
    sensitivity_closed_form(JETS_LINEAR, |k| Springs64 { k, ..JETS_LINEAR });
    sensitivity_closed_form(HAND_LINEAR, |k| HandSprings { k, ..HAND_LINEAR });
}

/// Lyapunov exponents (a linear centre: both near 0) and one shooting iteration (a typed
/// result, never an abort), on a 2 MiB thread.
fn lyapunov_and_shooting<L: Lagrangian<64> + Copy + Send + 'static>(sys: L) {
    use lagrange::sensitivity::{Lyapunov, Shooting};
    let (exponents, shooting) = in_thread(move || {
        let (q0, _, _) = mode_start();
        let s = Lyapunov::new(&sys, q0, [0.0; 64])
            .duration(0.04)
            .renormalize_every(0.02)
            .directions(2)
            .tolerances(1e-8, 1e-8)
            .compute()
            .unwrap();
        let shooting = Shooting::autonomous(&sys, q0, [0.0; 64], 0.02)
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
    // Over 0.04 s the growth of a linear centre's variations is bounded by its largest ω, about 2.3.
    assert!(
        exponents.len() == 2 && exponents[0] >= exponents[1] && exponents[0].abs() < 3.0,
        "{exponents:?}"
    );
    if let Err(e) = shooting {
        assert!(e.contains("iteration") || e.contains("converge"), "{e}");
    }
}

#[test]
fn lyapunov_and_shooting_of_64_coordinates_in_jets_mode_and_by_hand() {
    lyapunov_and_shooting(JETS_LINEAR);
    lyapunov_and_shooting(HAND_LINEAR);
}

/// An ensemble of two members on two threads (rayon's, with the default stack), each against
/// its normal mode (amplitudes 0.1 and 0.2) to 1e-8.
fn ensemble_closed_form<L: Lagrangian<64> + Copy + Send + Sync + 'static>(sys: L) {
    use lagrange::ensemble::{Ensemble, Member};
    let (q0, shape, omega) = mode_start();
    let r = Ensemble::new(2, |i| {
        Member::new(sys, q0.map(|x| x * (1.0 + i as f64)), [0.0; 64])
    })
    .configure(|s| {
        s.method(Method::Dop853 {
            rtol: 1e-10,
            atol: 1e-10,
        })
        .until(T_RUN)
    })
    .threads(2)
    .run();
    for (i, tr) in r.results.iter().enumerate() {
        let q = *tr.as_ref().expect("a regular run").q.last().unwrap();
        let a = 0.1 * (1.0 + i as f64);
        let exact: Vec<f64> = shape
            .iter()
            .map(|s| a * s * (omega * T_RUN).cos())
            .collect();
        assert!(
            rel(&q, &exact) < 1e-8 / 0.1,
            "member {i}: {:e}",
            rel(&q, &exact)
        );
    }
}

#[test]
fn an_ensemble_of_64_coordinates_in_jets_mode_and_by_hand() {
    ensemble_closed_form(JETS_LINEAR);
    ensemble_closed_form(HAND_LINEAR);
}

/// [`Held64`] in jets mode: 64 unit oscillators, the last two held together.
#[derive(Clone, Copy)]
pub struct HeldJets64;

#[lagrangian(mode = "jets")]
impl HeldJets64 {
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

/// [`Held64`] by hand: `impl Holonomic`, declared to the run.
#[derive(Clone, Copy)]
pub struct HeldHand64;

/// Distinct names, for `linearize_on_constraints` to pick the independent coordinates by.
const NAMES_64: [&str; 64] = [
    "q0", "q1", "q2", "q3", "q4", "q5", "q6", "q7", "q8", "q9", "q10", "q11", "q12", "q13", "q14",
    "q15", "q16", "q17", "q18", "q19", "q20", "q21", "q22", "q23", "q24", "q25", "q26", "q27",
    "q28", "q29", "q30", "q31", "q32", "q33", "q34", "q35", "q36", "q37", "q38", "q39", "q40",
    "q41", "q42", "q43", "q44", "q45", "q46", "q47", "q48", "q49", "q50", "q51", "q52", "q53",
    "q54", "q55", "q56", "q57", "q58", "q59", "q60", "q61", "q62", "q63",
];

impl Lagrangian<64> for HeldHand64 {
    const COORDINATES: [&'static str; 64] = NAMES_64;
    const CYCLIC: [bool; 64] = [false; 64];
    const AUTONOMOUS: bool = true;
    const COMPILED: lagrange::lagrangian::Compiled = lagrange::lagrangian::Compiled {
        constrained: true,
        ..lagrange::lagrangian::Compiled::NONE
    };
    fn lagrangian<S: Scalar>(&self, q: &[S; 64], v: &[S; 64], _t: S) -> S {
        let mut l = S::constant(0.0);
        for k in 0..64 {
            l += (v[k] * v[k] - q[k] * q[k]) * 0.5;
        }
        l
    }
    fn declared<'s, V: lagrange::Declared<'s, Self, 64>>(&'s self, v: V) -> V::Output {
        v.constrained::<1>(self)
    }
}

impl Holonomic<64, 1> for HeldHand64 {
    const SCLERONOMIC: bool = true;
    fn constraints<S: Scalar>(&self, q: &[S; 64], _t: S) -> [S; 1] {
        [q[63] - q[62]]
    }
}

/// A constrained run (DOP853 projected, RATTLE) and `linearize_on_constraints` of 64
/// coordinates with one constraint, on a 2 MiB thread: from q = 0.1 (every oscillator at ω = 1,
/// the held pair too) q(T) = 0.1 cos T to 1e-8 (DOP853) and 1e-5 (RATTLE at dt = 0.01, relative
/// to the amplitude), |g| < 1e-12; the eigenvalues are ±i.
fn constrained_closed_form<L>(sys: L)
where
    L: Lagrangian<64> + Holonomic<64, 1> + Copy + Send + 'static,
{
    for (method, tol) in [
        (
            Method::Dop853 {
                rtol: 1e-10,
                atol: 1e-10,
            },
            1e-8,
        ),
        (Method::VariationalMidpoint { dt: 1e-2 }, 1e-5),
    ] {
        let (q, g) = in_thread(move || {
            let tr = Simulation::new(&sys, [0.1; 64], [0.0; 64])
                .method(method)
                .until(T_RUN)
                .run()
                .unwrap();
            let g = tr.invariants().constraints.map(|c| c.position);
            (*tr.q.last().unwrap(), g)
        });
        let exact = [0.1 * T_RUN.cos(); 64];
        assert!(
            rel(&q, &exact) < tol / 0.1,
            "{method:?}: {:e}",
            rel(&q, &exact)
        );
        let g = g.expect("a constrained run reports its residual");
        assert!(g < 1e-12, "{method:?}: |g| = {g:e}");
    }
    let l = in_thread(move || {
        let lin = sys
            .linearize_on_constraints(&[0.0; 64], &[0.0; 64], 0.0)
            .unwrap();
        let names = &L::COORDINATES[..63];
        lin.eigenvalues(names, names).unwrap()
    });
    assert_eq!(l.len(), 126);
    assert!(l
        .iter()
        .all(|z| z.re.abs() < 1e-12 && (z.im.abs() - 1.0).abs() < 1e-12));
}

#[test]
fn constrained_64_coordinates_in_jets_mode_and_by_hand_on_a_2_mib_stack() {
    constrained_closed_form(HeldJets64);
    constrained_closed_form(HeldHand64);
}

/// 64 unit oscillators in jets mode, the first bouncing elastically off a wall at q₀ = −0.05.
#[derive(Clone, Copy)]
pub struct Walled64;

#[lagrangian(mode = "jets")]
impl Walled64 {
    fn lagrangian(&self, (q, q_dot): Coords<64>) -> Scalar {
        let mut lag = 0.0;
        for k in 0..q.len() {
            lag += 0.5 * (q_dot[k] * q_dot[k] - q[k] * q[k]);
        }
        lag
    }
    fn contacts(&self, (q, _q_dot): Coords<64>) -> [Contact; 1] {
        [Contact::gap(q[0] + 0.05).restitution(1.0).named("wall")]
    }
}

/// A run with contacts at 64 coordinates on a 2 MiB thread: q₀ = −sin t from 0 meets the wall at
/// t* = asin 0.05 and comes back mirrored, q₀(T) = −sin(2t* − T), to 1e-7; the others stay at 0.
#[test]
fn contacts_of_64_coordinates_in_jets_mode_on_a_2_mib_stack() {
    let mut v0 = [0.0; 64];
    v0[0] = -1.0;
    let q = in_thread(move || {
        let tr = Simulation::new(&Walled64, [0.0; 64], v0)
            .method(Method::Dop853 {
                rtol: 1e-10,
                atol: 1e-10,
            })
            .until(T_RUN)
            .run()
            .unwrap();
        *tr.q.last().unwrap()
    });
    let t_star = 0.05_f64.asin();
    assert!(
        (q[0] + (2.0 * t_star - T_RUN).sin()).abs() < 1e-7,
        "q₀ = {}",
        q[0]
    );
    assert!(q[1..].iter().all(|x| *x == 0.0), "{q:?}");
}
