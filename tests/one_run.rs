//! One system, one run: `Simulation::new` and the members of an `Ensemble` run a system as its
//! `#[lagrangian]` impl declares it — with its holonomic constraints, its velocity constraints
//! or its contacts — never its unconstrained motion. Three systems a new user writes first,
//! each against its closed form: a Chaplygin sleigh (a knife edge behind the centre of mass), a
//! pendulum written in x, y, z on a conical orbit, and two masses colliding on a line.

use lagrange::prelude::*;

/// A Chaplygin sleigh: a body of mass m and inertia i about its centre of mass (x, y), heading
/// φ, on a knife edge a behind the centre, which cannot slide sideways.
pub struct Sleigh {
    pub m: f64,
    pub i: f64,
    pub a: f64,
}

#[lagrangian]
impl Sleigh {
    fn lagrangian(&self, (_x, x_dot): Coord, (_y, y_dot): Coord, (_phi, phi_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) + 0.5 * self.i * phi_dot * phi_dot
    }
    /// The blade's point P = c − a e has no velocity along n = (−sin φ, cos φ).
    fn velocity_constraints(
        &self,
        (_, x_dot): Coord,
        (_, y_dot): Coord,
        (phi, phi_dot): Coord,
    ) -> [Scalar; 1] {
        [y_dot * phi.cos() - x_dot * phi.sin() - self.a * phi_dot]
    }
}

/// The sleigh's forward speed u and turning rate ω at t from u₀, ω₀ (derived in
/// `the_sleigh_does_not_slide`).
pub fn sleigh_closed_form(s: &Sleigh, u0: f64, w0: f64, t: f64) -> (f64, f64) {
    let j = s.i + s.m * s.a * s.a;
    let energy = 0.5 * (s.m * u0 * u0 + j * w0 * w0);
    let u_max = (2.0 * energy / s.m).sqrt();
    let k = s.a * s.m * u_max / j;
    let u = u_max * (k * t + (u0 / u_max).atanh()).tanh();
    let w = w0.signum() * ((2.0 * energy - s.m * u * u) / j).max(0.0).sqrt();
    (u, w)
}

/// The state of the sleigh at heading 0 moving at u₀ along it while turning at ω₀.
pub fn sleigh_start(s: &Sleigh, u0: f64, w0: f64) -> ([f64; 3], [f64; 3]) {
    ([0.0; 3], [u0, s.a * w0, w0])
}

/// (u, ω) of a sleigh's state: the velocity of its centre along its heading, and φ̇.
pub fn sleigh_rates(q: &[f64; 3], v: &[f64; 3]) -> (f64, f64) {
    (v[0] * q[2].cos() + v[1] * q[2].sin(), v[2])
}

/// In body axes (e along the heading, n across it) with u = v·e, w = v·n: the blade makes
/// w = a ω, its force λ n at P = c − a e has torque −a λ, so m(u̇ − ω w) = 0,
/// m(ẇ + ω u) = λ, i ω̇ = −a λ, which give u̇ = a ω² and (i + m a²) ω̇ = −m a u ω. The energy
/// E = (m u² + J ω²)/2 (J = i + m a²) is conserved, so u̇ = (a m / J)(U² − u²) with
/// U² = 2E/m: u = U tanh(k t + atanh(u₀/U)), k = a m U / J, and ω² = (2E − m u²)/J with the sign
/// of ω₀. A free body (the blade dropped) would keep u and ω.
#[test]
fn the_sleigh_does_not_slide() {
    let s = Sleigh {
        m: 2.0,
        i: 0.3,
        a: 0.4,
    };
    let (u0, w0) = (0.2, 1.5);
    let (q0, v0) = sleigh_start(&s, u0, w0);
    let tr = Simulation::new(&s, q0, v0)
        .until(6.0)
        .sample_every(1.0)
        .run()
        .unwrap();
    for ((t, q), v) in tr.t.iter().zip(&tr.q).zip(&tr.qdot) {
        let (u, w) = sleigh_rates(q, v);
        let (u_exact, w_exact) = sleigh_closed_form(&s, u0, w0, *t);
        assert!(
            (u - u_exact).abs() < 1e-9,
            "t = {t}: u {u} against {u_exact}"
        );
        assert!(
            (w - w_exact).abs() < 1e-9,
            "t = {t}: ω {w} against {w_exact}"
        );
    }
    // The sleigh straightens out: most of its energy has gone into u.
    let (u_end, w_end) = sleigh_rates(tr.q.last().unwrap(), tr.qdot.last().unwrap());
    assert!(u_end > 3.0 * u0 && w_end.abs() < 0.5 * w0);
    let inv = tr.invariants();
    assert!(inv.constraints.unwrap().velocity < 1e-12);
    assert!(inv.energy.unwrap().max_abs < 1e-9);
    assert_eq!(tr.lambda.len(), tr.t.len());
    // The same run as the explicit constructor's, bit for bit.
    let explicit = Simulation::constrained(&s, q0, v0)
        .until(6.0)
        .sample_every(1.0)
        .run()
        .unwrap();
    assert_eq!(
        (tr.q, tr.qdot, tr.lambda),
        (explicit.q, explicit.qdot, explicit.lambda)
    );
}

/// A pendulum of length l written in x, y, z (z up) with g along −z.
pub struct Spherical {
    pub m: f64,
    pub g: f64,
    pub l: f64,
}

#[lagrangian]
impl Spherical {
    fn lagrangian(&self, (_x, x_dot): Coord, (_y, y_dot): Coord, (z, z_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot + z_dot * z_dot) - self.m * self.g * z
    }
    fn constraints(&self, (x, _): Coord, (y, _): Coord, (z, _): Coord) -> [Scalar; 1] {
        [x * x + y * y + z * z - self.l * self.l]
    }
}

/// The conical orbit at angle θ from the downward vertical: radius r = l sin θ, height
/// z = −l cos θ, rate Ω with m Ω² r = T sin θ and T cos θ = m g, so Ω² = g / (l cos θ) and the
/// rod's tension is T = m g / cos θ. The rod's force is Gᵀλ = 2λ (x, y, z), of size −2λ l = T:
/// λ = −m g / (2 l cos θ).
fn conical(p: &Spherical, theta: f64) -> ([f64; 3], [f64; 3], f64, f64) {
    let (r, z) = (p.l * theta.sin(), -p.l * theta.cos());
    let omega = (p.g / (p.l * theta.cos())).sqrt();
    let lambda = -p.m * p.g / (2.0 * p.l * theta.cos());
    ([r, 0.0, z], [0.0, r * omega, 0.0], omega, lambda)
}

fn check_conical(p: &Spherical, theta: f64, tr: &Trajectory<3>) {
    let (q0, _, omega, lambda) = conical(p, theta);
    let r = q0[0];
    for ((t, q), l) in tr.t.iter().zip(&tr.q).zip(&tr.lambda) {
        let exact = [r * (omega * t).cos(), r * (omega * t).sin(), q0[2]];
        for i in 0..3 {
            assert!(
                (q[i] - exact[i]).abs() < 1e-8,
                "θ = {theta}, t = {t}: q = {q:?} against {exact:?}"
            );
        }
        assert!(
            (l[0] - lambda).abs() < 1e-8 * lambda.abs(),
            "λ {l:?} against {lambda}"
        );
    }
}

/// Unconstrained, the bob would fall: |r| = 45 after 3 s from these states.
#[test]
fn the_pendulum_in_x_y_z_keeps_its_rod() {
    let p = Spherical {
        m: 0.5,
        g: 9.81,
        l: 1.2,
    };
    let theta = 0.6;
    let (q0, v0, _, _) = conical(&p, theta);
    let tr = Simulation::new(&p, q0, v0)
        .until(3.0)
        .sample_every(0.25)
        .run()
        .unwrap();
    check_conical(&p, theta, &tr);
    assert!(tr.invariants().constraints.unwrap().position < 1e-13);
}

/// Two masses on a line, the second ahead of the first; they collide when x₂ − x₁ reaches 0.
pub struct Pair {
    pub m1: f64,
    pub m2: f64,
    pub e: f64,
}

#[lagrangian]
impl Pair {
    fn lagrangian(&self, (_x1, v1): Coord, (_x2, v2): Coord) -> Scalar {
        0.5 * self.m1 * v1 * v1 + 0.5 * self.m2 * v2 * v2
    }
    fn contacts(&self, (x1, _): Coord, (x2, _): Coord) -> [Contact; 1] {
        [Contact::gap(x2 - x1).restitution(self.e).named("touch")]
    }
}

/// Positions at t of two masses from x₁ = 0, x₂ = d at speeds v₁ > v₂: they meet at
/// t_c = d / (v₁ − v₂) at x_c = v₁ t_c; after, the momentum is kept and the relative speed
/// reversed and scaled by e (Newton's law): v₁' = V − m₂ e (v₁ − v₂)/(m₁ + m₂),
/// v₂' = V + m₁ e (v₁ − v₂)/(m₁ + m₂), V = (m₁ v₁ + m₂ v₂)/(m₁ + m₂).
fn pair_closed_form(p: &Pair, d: f64, v1: f64, v2: f64, t: f64) -> [f64; 2] {
    let tc = d / (v1 - v2);
    if t <= tc {
        return [v1 * t, d + v2 * t];
    }
    let (m, xc) = (p.m1 + p.m2, v1 * tc);
    let vcm = (p.m1 * v1 + p.m2 * v2) / m;
    let rel = p.e * (v1 - v2);
    let (w1, w2) = (vcm - p.m2 * rel / m, vcm + p.m1 * rel / m);
    [xc + w1 * (t - tc), xc + w2 * (t - tc)]
}

/// Without the contact the masses would pass through each other (x₁ = 4, x₂ = −0.5 at t = 2).
#[test]
fn two_masses_collide() {
    let p = Pair {
        m1: 1.0,
        m2: 3.0,
        e: 0.5,
    };
    let (d, v1, v2) = (1.5, 2.0, -1.0);
    let tr = Simulation::new(&p, [0.0, d], [v1, v2])
        .until(2.0)
        .sample_every(0.25)
        .run()
        .unwrap();
    assert_eq!(tr.jumps.len(), 1);
    assert!((tr.jumps[0].t - 0.5).abs() < 1e-12);
    for (t, q) in tr.t.iter().zip(&tr.q) {
        let exact = pair_closed_form(&p, d, v1, v2, *t);
        assert!(
            (q[0] - exact[0]).abs() < 1e-10 && (q[1] - exact[1]).abs() < 1e-10,
            "t = {t}: {q:?} against {exact:?}"
        );
    }
    // An event of the user's runs next to the contact's own.
    let tr = Simulation::new(&p, [0.0, d], [v1, v2])
        .until(2.0)
        .event(Event::zero_crossing("x1 = 0.5", |_, q: &[f64; 2], _| {
            q[0] - 0.5
        }))
        .run()
        .unwrap();
    // x₁ passes 0.5 on its way in (t = 0.25) and on its way back after the impact.
    let (w1, _) = {
        let after = pair_closed_form(&p, d, v1, v2, 1.5);
        (after[0] - 1.0, after[1])
    };
    let back = 0.5 + 0.5 / -w1;
    let mine: Vec<f64> = tr
        .events
        .iter()
        .filter(|e| e.name == "x1 = 0.5")
        .map(|e| e.t)
        .collect();
    assert_eq!(tr.jumps.len(), 1);
    assert_eq!(mine.len(), 2, "{:?}", tr.events);
    assert!((mine[0] - 0.25).abs() < 1e-12 && (mine[1] - back).abs() < 1e-12);
}

/// Ensemble members run as `Simulation::new` runs them: each with its constraints or contacts.
#[test]
fn ensembles_run_what_their_systems_declare() {
    // Sleighs with three blade offsets.
    let offset = |i: usize| 0.2 + 0.2 * i as f64;
    let sleigh = |i: usize| Sleigh {
        m: 2.0,
        i: 0.3,
        a: offset(i),
    };
    let r = Ensemble::new(3, |i| {
        let (q0, v0) = sleigh_start(&sleigh(i), 0.2, 1.5);
        Member::new(sleigh(i), q0, v0).param("a", offset(i))
    })
    .configure(|sim| sim.until(4.0))
    .run();
    for (i, res) in r.results.iter().enumerate() {
        let tr = res.as_ref().unwrap();
        let (u, w) = sleigh_rates(tr.q.last().unwrap(), tr.qdot.last().unwrap());
        let (u_exact, w_exact) = sleigh_closed_form(&sleigh(i), 0.2, 1.5, 4.0);
        assert!(
            (u - u_exact).abs() < 1e-9 && (w - w_exact).abs() < 1e-9,
            "member {i}"
        );
    }
    // Conical pendulums at three angles.
    let angle = |i: usize| 0.3 + 0.3 * i as f64;
    let p = Spherical {
        m: 0.5,
        g: 9.81,
        l: 1.2,
    };
    let r = Ensemble::new(3, |i| {
        let (q0, v0, _, _) = conical(&p, angle(i));
        Member::new(
            Spherical {
                m: 0.5,
                g: 9.81,
                l: 1.2,
            },
            q0,
            v0,
        )
    })
    .configure(|sim| sim.until(3.0).sample_every(0.5))
    .run();
    for (i, res) in r.results.iter().enumerate() {
        check_conical(&p, angle(i), res.as_ref().unwrap());
    }
    // Colliding pairs with three mass ratios.
    let pair = |i: usize| Pair {
        m1: 1.0,
        m2: 0.5 + i as f64,
        e: 0.5,
    };
    let r = Ensemble::new(3, |i| Member::new(pair(i), [0.0, 1.5], [2.0, -1.0]))
        .configure(|sim| sim.until(2.0))
        .run();
    for (i, res) in r.results.iter().enumerate() {
        let tr = res.as_ref().unwrap();
        let exact = pair_closed_form(&pair(i), 1.5, 2.0, -1.0, 2.0);
        let q = tr.q.last().unwrap();
        assert!((q[0] - exact[0]).abs() < 1e-10 && (q[1] - exact[1]).abs() < 1e-10);
        assert_eq!(tr.jumps.len(), 1, "member {i}");
    }
}

/// What a run cannot take yet is refused, naming it, never dropped: the parameter
/// sensitivities of a run with contacts (whose Φ is taken: the swap of two equal masses' motions
/// in an elastic collision). Those of a constrained run are taken as the system declares its
/// constraints: the spherical pendulum's ∂(q, q̇)(1)/∂g against central differences of runs at
/// g ± 1e-4 g (their error ≈ 1e-8 relative; tolerance 1e-6).
#[test]
fn what_a_run_cannot_take_is_refused() {
    let p = Spherical {
        m: 0.5,
        g: 9.81,
        l: 1.2,
    };
    let (q0, v0, _, _) = conical(&p, 0.6);
    let tight = Method::Dop853 {
        rtol: 1e-12,
        atol: 1e-12,
    };
    let run = Simulation::new(&p, q0, v0)
        .method(tight)
        .until(1.0)
        .sensitivity()
        .parameter("g", p.g, |g| Spherical { m: 0.5, g, l: 1.2 })
        .run()
        .unwrap();
    let end = |g: f64| {
        let tr = Simulation::new(&Spherical { m: 0.5, g, l: 1.2 }, q0, v0)
            .method(tight)
            .until(1.0)
            .keep_samples(false)
            .run()
            .unwrap();
        let (q, v) = (*tr.q.last().unwrap(), *tr.qdot.last().unwrap());
        [q, v].concat()
    };
    let h = 1e-4 * p.g;
    let (up, down) = (end(p.g + h), end(p.g - h));
    let got = run.dparams.last().unwrap();
    for i in 0..6 {
        let want = (up[i] - down[i]) / (2.0 * h);
        assert!(
            (got[(i, 0)] - want).abs() < 1e-6 * want.abs().max(1.0),
            "{i}: {} vs {want}",
            got[(i, 0)]
        );
    }
    let pair = Pair {
        m1: 1.0,
        m2: 1.0,
        e: 1.0,
    };
    let err = Simulation::new(&pair, [0.0, 1.0], [1.0, 0.0])
        .until(1.0)
        .sensitivity()
        .parameter("e", 1.0, |e| Pair { e, ..pair })
        .run()
        .unwrap_err();
    assert!(err.to_string().contains("contacts"), "{err}");
    // Φ through the contact is taken (not dropped): equal masses, elastic, swap their motions
    // at the collision, so after it x₁(T) = x₂(0) + v₂(0) T and x₂(T) = x₁(0) + v₁(0) T, and
    // Φ(T) is that permutation.
    let run = Simulation::new(&pair, [0.0, 1.0], [1.0, 0.0])
        .until(1.5)
        .sensitivity()
        .run()
        .unwrap();
    assert_eq!(run.trajectory.jumps.len(), 1);
    let t = 1.5;
    let want = [
        [0.0, 1.0, 0.0, t],
        [1.0, 0.0, t, 0.0],
        [0.0, 0.0, 0.0, 1.0],
        [0.0, 0.0, 1.0, 0.0],
    ];
    let phi = run.final_phi();
    for (i, row) in want.iter().enumerate() {
        for (j, w) in row.iter().enumerate() {
            assert!(
                (phi[(i, j)] - w).abs() < 1e-10,
                "Φ[{i}, {j}] = {}",
                phi[(i, j)]
            );
        }
    }
    // A method that does not take constraints says so.
    let err = Simulation::new(&p, q0, v0)
        .method(Method::Taylor { tol: 1e-12 })
        .until(1.0)
        .run()
        .unwrap_err();
    assert!(
        matches!(err, SimulationError::InvalidOptions { .. }),
        "{err}"
    );
}
