//! Sensitivities of the implicit methods' runs: Φ(t) = ∂(q, q̇)(t)/∂(q₀, q̇₀) as the derivative
//! of the method's discrete flow — Radau5 (the stages' derivatives by the implicit function
//! theorem, their Jacobians exact from the jets) and the variational integrator (its discrete
//! map's, against differences of its runs). Against the closed form of a stiff linear oscillator, against DOP853's
//! variational equations on a nonlinear, driven, damped pendulum (Φ and two parameters) and on
//! a constrained one, and with the motion of the plain Radau5 run.

use lagrange::prelude::*;
use lagrange::DMatrix;
use lagrange_examples::driven_pendulum_system::DrivenPendulum;
use lagrange_examples::stiff_system::{DampedDriven, RigidPendulumXy};

/// Radau5 at the tolerance of the comparisons.
const RADAU: Method = Method::Radau5 {
    rtol: 1e-11,
    atol: 1e-11,
};

/// DOP853 at the tolerance of the references the comparisons take.
const REFERENCE: Method = Method::Dop853 {
    rtol: 1e-13,
    atol: 1e-13,
};

/// The damped driven pendulum of the tests: m = l = 1, g = 9.81, friction 0.3, a torque
/// 1.5 cos 2t.
fn driven() -> DrivenPendulum {
    DrivenPendulum {
        m: 1.0,
        l: 1.0,
        g: 9.81,
        b: 0.3,
        a: 1.5,
        w: 2.0,
    }
}

/// The largest |a − b| relative to max(1, max |b|).
fn rel_diff(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    let scale = b.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    (a - b).amax() / scale
}

/// The stiff oscillator ẍ + 10⁴ ẋ + 10⁶ x = 10⁶ cos t (rates 101 and 9 899 per unit time) is
/// linear, so Φ(t) = exp(J t), J = [[0, 1], [−k, −c]]; with J's eigenvalues λ₁ ≠ λ₂,
/// exp(J t) = ((λ₂ e^{λ₁t} − λ₁ e^{λ₂t}) I + (e^{λ₂t} − e^{λ₁t}) J) / (λ₂ − λ₁)
/// (Cayley–Hamilton: exp(J t) = α I + β J, and both eigenvalues satisfy e^{λt} = α + β λ).
/// Radau5 at rtol = atol = 1e-10 over t ∈ [0, 0.1] (Φ decays by e^{−10} over it), Φ at every
/// sample within 1e-7 of max(1, |Φ|) (the method's global error ≈ 25 rtol on a smooth
/// problem; measured 5.2e-9 in 278 steps).
#[test]
fn radau5_phi_of_a_stiff_oscillator_is_the_matrix_exponential() {
    let sys = DampedDriven::STIFF;
    let (k, c) = (sys.k / sys.m, sys.c / sys.m);
    let disc = (c * c - 4.0 * k).sqrt();
    let (l1, l2) = ((-c + disc) / 2.0, (-c - disc) / 2.0);
    let exact = |t: f64| {
        let (e1, e2) = ((l1 * t).exp(), (l2 * t).exp());
        let (a, b) = ((l2 * e1 - l1 * e2) / (l2 - l1), (e2 - e1) / (l2 - l1));
        DMatrix::from_row_slice(2, 2, &[a, b, -k * b, a - c * b])
    };
    let run = Simulation::new(&sys, [0.3], [0.0])
        .method(Method::Radau5 {
            rtol: 1e-10,
            atol: 1e-10,
        })
        .until(0.1)
        .sample_every(0.005)
        .sensitivity()
        .run()
        .unwrap();
    let mut worst = 0.0_f64;
    for (t, phi) in run.trajectory.t.iter().zip(&run.phi) {
        worst = worst.max(rel_diff(phi, &exact(*t)));
    }
    println!(
        "stiff oscillator: max |Φ − exp(Jt)| = {worst:.2e} over {} samples, {} steps",
        run.phi.len(),
        run.trajectory.stats.steps
    );
    assert!(worst < 1e-7, "{worst}");
}

/// The damped driven pendulum (nonlinear, with dissipation and a time-dependent torque) from
/// θ₀ = 1.2, θ̇₀ = −0.4 to t = 10: Radau5's Φ (rtol = atol = 1e-11) at every sample against
/// DOP853's variational equations at 1e-13 (an independent method; its Φ good to ~1e-11),
/// within 1e-7 of max(1, |Φ|); the motion of the sensitivity run equals the plain Radau5
/// run's bit for bit (Φ does not steer the steps).
#[test]
fn radau5_phi_matches_dop853_on_a_driven_pendulum() {
    let sys = driven();
    let radau = RADAU;
    let sim = |method: Method| {
        Simulation::new(&sys, [1.2], [-0.4])
            .method(method)
            .until(10.0)
            .sample_every(0.5)
    };
    let implicit = sim(radau).sensitivity().run().unwrap();
    let explicit = sim(REFERENCE).sensitivity().run().unwrap();
    assert_eq!(implicit.phi.len(), explicit.phi.len());
    let mut worst = 0.0_f64;
    for (a, b) in implicit.phi.iter().zip(&explicit.phi) {
        worst = worst.max(rel_diff(a, b));
    }
    println!("driven pendulum: max |Φ_Radau5 − Φ_DOP853| = {worst:.2e}");
    assert!(worst < 1e-7, "{worst}");
    let plain = sim(radau).run().unwrap();
    assert_eq!(plain.t, implicit.trajectory.t);
    assert_eq!(plain.q, implicit.trajectory.q);
    assert_eq!(plain.qdot, implicit.trajectory.qdot);
}

/// The pendulum in x, y with its rod as a constraint (m = g = l = 1, θ₀ = 0.8, θ̇₀ = 0.3, to
/// t = 3): Radau5 runs the constrained accelerations with the projection after each step, and its
/// Φ (from Φ(t0) = P, the derivative of the start's projection) against DOP853's constrained
/// variational equations at 1e-13, within 1e-6 of max(1, |Φ|); every column tangent to the rod
/// (x δx + y δy = 0) to 1e-7.
#[test]
fn radau5_phi_of_a_constrained_pendulum() {
    let sys = RigidPendulumXy {
        m: 1.0,
        g: 1.0,
        l: 1.0,
    };
    let (q0, v0) = sys.state(0.8, 0.3);
    let run = |method: Method| {
        Simulation::new(&sys, q0, v0)
            .method(method)
            .until(3.0)
            .sensitivity()
            .run()
            .unwrap()
    };
    let implicit = run(RADAU);
    let explicit = run(REFERENCE);
    let d = rel_diff(implicit.final_phi(), explicit.final_phi());
    println!("constrained pendulum: |Φ_Radau5(3) − Φ_DOP853(3)| = {d:.2e}");
    assert!(d < 1e-6, "{d}");
    let q = implicit.trajectory.q.last().unwrap();
    let phi = implicit.final_phi();
    for j in 0..4 {
        let normal = q[0] * phi[(0, j)] + q[1] * phi[(1, j)];
        assert!(normal.abs() < 1e-7, "column {j}: {normal}");
    }
}

/// Parameters with Radau5: the parameters' columns move with Φ's, their stage slopes J S + ∂f/∂p
/// (∂f/∂p the fourth-order difference of the parameter's neighbouring systems, as for every
/// method). The driven pendulum's ∂(θ, θ̇)/∂b and ∂/∂a at every sample against DOP853's
/// variational equations at 1e-13, within 1e-7 of max(1, |∂y/∂p|).
#[test]
fn radau5_parameter_sensitivities_match_dop853() {
    let base = driven();
    let run = |method: Method| {
        Simulation::new(&base, [1.2], [-0.4])
            .method(method)
            .until(10.0)
            .sample_every(0.5)
            .sensitivity()
            .parameter("b", base.b, |b| DrivenPendulum { b, ..base })
            .parameter("a", base.a, |a| DrivenPendulum { a, ..base })
            .run()
            .unwrap()
    };
    let implicit = run(RADAU);
    let explicit = run(REFERENCE);
    assert_eq!(implicit.parameters, ["b", "a"]);
    let mut worst = 0.0_f64;
    for (a, b) in implicit.dparams.iter().zip(&explicit.dparams) {
        worst = worst.max(rel_diff(a, b));
    }
    println!("driven pendulum: max |∂y/∂p Radau5 − DOP853| = {worst:.2e}");
    assert!(worst < 1e-7, "{worst}");
}

/// The variational integrator's Φ is the derivative of its discrete map (q_k, p_k) ↦
/// (q_{k+1}, p_{k+1}) (the implicit function theorem on its discrete Euler–Lagrange equation,
/// with the Legendre map's derivative at the nodes and the interpolant's between them). On the
/// driven damped pendulum (the discrete Lagrange–d'Alembert forces), dt = 0.01, samples every
/// 0.1 (on nodes), to t = 5: Φ at every sample against central differences of runs with the same
/// dt, Richardson-extrapolated over h = 1e-4 and 5e-5 (truncation O(h⁴) ≈ 1e-16, the Newton
/// solves' round-off over h ≈ 1e-11): within 1e-8 of max(1, |Φ|) (measured 3.2e-11). Between
/// nodes, at the first turning point θ̇ = 0 (an event, located on the interpolant): its time's
/// sensitivity dt*/dy₀ = −∇g Φ / ġ against the differences of the hit times, to 1e-7 (measured
/// 2.3e-12). Φ there is
/// the interpolant's derivative and ġ the interpolant's rate (its q̇ is linear between nodes, so
/// the flow's rate ∇g · f would be O(dt) off: 1.2e-4 at dt = 0.01 before the run logged the
/// interpolant's rate).
#[test]
fn variational_phi_is_the_derivative_of_its_discrete_map() {
    let sys = driven();
    let method = Method::VariationalMidpoint { dt: 0.01 };
    let sim = |y0: [f64; 2]| {
        Simulation::new(&sys, [y0[0]], [y0[1]])
            .method(method)
            .until(5.0)
            .sample_every(0.1)
            .event(Event::zero_crossing("turn", |_t, _q, v: &[f64; 1]| v[0]))
    };
    let y0 = [1.2, -0.4];
    let run = sim(y0).sensitivity().run().unwrap();
    let samples = |y: [f64; 2]| {
        let tr = sim(y).run().unwrap();
        tr.q.iter()
            .zip(&tr.qdot)
            .map(|(q, v)| [q[0], v[0]])
            .collect::<Vec<_>>()
    };
    let plain = samples(y0);
    assert_eq!(plain.len(), run.phi.len());
    let column = |j: usize, h: f64| {
        let (mut up, mut down) = (y0, y0);
        up[j] += h;
        down[j] -= h;
        let (a, b) = (samples(up), samples(down));
        a.iter()
            .zip(&b)
            .map(|(a, b)| [(a[0] - b[0]) / (2.0 * h), (a[1] - b[1]) / (2.0 * h)])
            .collect::<Vec<_>>()
    };
    let mut worst = 0.0_f64;
    for j in 0..2 {
        let (d1, d2) = (column(j, 1e-4), column(j, 5e-5));
        for (k, phi) in run.phi.iter().enumerate() {
            let scale = phi.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
            for i in 0..2 {
                let fd = (4.0 * d2[k][i] - d1[k][i]) / 3.0;
                worst = worst.max((phi[(i, j)] - fd).abs() / scale);
            }
        }
    }
    println!("variational integrator: max |Φ − differences| = {worst:.2e}");
    assert!(worst < 1e-8, "{worst}");
    // The motion is the plain run's.
    for (k, s) in plain.iter().enumerate() {
        assert_eq!([run.trajectory.q[k][0], run.trajectory.qdot[k][0]], *s);
    }
    let first_hit = |y: [f64; 2]| sim(y).run().unwrap().events[0].t;
    let dt = run.events[0].dt_dx0.as_ref().unwrap();
    let mut worst_t = 0.0_f64;
    for j in 0..2 {
        let d = |h: f64| {
            let (mut up, mut down) = (y0, y0);
            up[j] += h;
            down[j] -= h;
            (first_hit(up) - first_hit(down)) / (2.0 * h)
        };
        let fd = (4.0 * d(5e-5) - d(1e-4)) / 3.0;
        worst_t = worst_t.max((dt[j] - fd).abs());
    }
    println!("variational integrator: max |dt*/dy₀ − differences| = {worst_t:.2e}");
    assert!(worst_t < 1e-7, "{worst_t}");
}

/// Parameters with the variational integrator: the derivative of its discrete map with respect
/// to p — R = p_k + (h/2)(L_q + F) − L_q̇ and p_{k+1} − p_k = h (L_q + F) at the midpoint move
/// with p, the start's momentum too (the start is given in (q, q̇)), and q̇ at a node through
/// the Legendre map's dependence on p — against Richardson differences (h = 1e-4 and 5e-5 of
/// the value) of the method's own runs on the same grid, for g (in L), b (in the dissipation)
/// and a (the drive's amplitude, a generalized force), at every sample to 1e-8 of max(1, |S|).
#[test]
fn variational_parameter_sensitivities_are_the_derivative_of_its_discrete_map() {
    let base = driven();
    let method = Method::VariationalMidpoint { dt: 0.01 };
    let sim = |sys: DrivenPendulum| {
        let tr = Simulation::new(&sys, [1.2], [-0.4])
            .method(method)
            .until(5.0)
            .sample_every(0.1)
            .run()
            .unwrap();
        tr.q.iter()
            .zip(&tr.qdot)
            .map(|(q, v)| [q[0], v[0]])
            .collect::<Vec<_>>()
    };
    let run = Simulation::new(&base, [1.2], [-0.4])
        .method(method)
        .until(5.0)
        .sample_every(0.1)
        .sensitivity()
        .parameter("g", base.g, |g| DrivenPendulum { g, ..base })
        .parameter("b", base.b, |b| DrivenPendulum { b, ..base })
        .parameter("a", base.a, |a| DrivenPendulum { a, ..base })
        .run()
        .unwrap();
    type Build = fn(f64) -> DrivenPendulum;
    let builds: [(f64, Build); 3] = [
        (base.g, |g| DrivenPendulum { g, ..driven() }),
        (base.b, |b| DrivenPendulum { b, ..driven() }),
        (base.a, |a| DrivenPendulum { a, ..driven() }),
    ];
    let mut worst = 0.0_f64;
    for (col, (value, build)) in builds.iter().enumerate() {
        let d = |h: f64| {
            let (up, down) = (sim(build(value + h)), sim(build(value - h)));
            up.iter()
                .zip(&down)
                .map(|(a, b)| [(a[0] - b[0]) / (2.0 * h), (a[1] - b[1]) / (2.0 * h)])
                .collect::<Vec<_>>()
        };
        let (d1, d2) = (d(1e-4 * value), d(5e-5 * value));
        for (k, s) in run.dparams.iter().enumerate() {
            for i in 0..2 {
                let fd = (4.0 * d2[k][i] - d1[k][i]) / 3.0;
                worst = worst.max((s[(i, col)] - fd).abs() / fd.abs().max(1.0));
            }
        }
    }
    println!("variational integrator: max |∂y/∂(g, b, a) − differences| = {worst:.2e}");
    assert!(worst < 1e-8, "{worst}");
}

/// What the variational integrator's sensitivity runs do not take is refused before any step:
/// a field alone (its discrete map is differentiated through the systems a closure builds), and
/// constrained runs (RATTLE).
#[test]
fn variational_refusals() {
    let sys = driven();
    let err = Simulation::new(&sys, [1.2], [-0.4])
        .method(Method::VariationalMidpoint { dt: 0.01 })
        .until(1.0)
        .sensitivity()
        .field("b")
        .run()
        .unwrap_err();
    assert!(err.to_string().contains("Method::Dop853"), "{err}");
    let rod = RigidPendulumXy {
        m: 1.0,
        g: 1.0,
        l: 1.0,
    };
    let (q0, v0) = rod.state(0.8, 0.3);
    let err = Simulation::new(&rod, q0, v0)
        .method(Method::VariationalMidpoint { dt: 0.01 })
        .until(1.0)
        .sensitivity()
        .run()
        .unwrap_err();
    assert!(
        matches!(err, SimulationError::InvalidOptions { .. }),
        "{err}"
    );
}
