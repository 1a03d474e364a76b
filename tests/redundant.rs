//! Redundant constraints: rows of G that depend on the others (everywhere, or along the motion)
//! are run, not refused — the multipliers are the least-norm ones (the one constraint force
//! Gᵀλ, split with the smallest |λ|), the projection the least-squares correction of least norm;
//! constraints that are dependent *and* contradict each other are refused with
//! `DependentConstraints` naming them. DOP853, Radau5 and RATTLE each run a parallelogram
//! linkage with a third crank against its minimal model, and Bricard's mechanism (rows of rank
//! four on five) over its 10 s against its energy, its loop closure and its symmetry.

use lagrange::prelude::*;

/// A parallelogram linkage with a third crank: a coupler bar (mass m, inertia i about its
/// reference pin, position (x, y), angle φ) hung from three parallel cranks of length r whose
/// ground pivots are at (0, 0), (b, 0) and (2b, 0), each crank's tip pinned to the coupler at
/// (b_k, 0) in its frame. Three constraints on three coordinates (Grübler: no freedom), yet it
/// moves with one: the third crank repeats what the other two impose (G has rank 2 along the
/// whole motion). Gravity along −y.
pub struct ThirdCrank {
    pub m: f64,
    pub i: f64,
    pub r: f64,
    pub b: f64,
    pub g: f64,
}

#[lagrangian]
impl ThirdCrank {
    fn lagrangian(&self, (_x, x_dot): Coord, (y, y_dot): Coord, (_phi, phi_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) + 0.5 * self.i * phi_dot * phi_dot
            - self.m * self.g * y
    }
    fn constraints(&self, (x, _): Coord, (y, _): Coord, (phi, _): Coord) -> [Scalar; 3] {
        let crank = |k: f64| {
            let (px, py) = (x + k * self.b * phi.cos(), y + k * self.b * phi.sin());
            (px - k * self.b).powi(2) + py.powi(2) - self.r * self.r
        };
        [crank(0.0), crank(1.0), crank(2.0)]
    }
}

/// Its motion in its one coordinate, derived apart: the coupler keeps φ = 0 and translates
/// along a circle of radius r (its reference pin on the first crank's tip), so it is a simple
/// pendulum of length r: L = ½ m r² θ̇² + m g r cos θ.
pub struct CouplerAngle {
    pub m: f64,
    pub r: f64,
    pub g: f64,
}

#[lagrangian]
impl CouplerAngle {
    fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
        0.5 * self.m * self.r * self.r * theta_dot * theta_dot
            + self.m * self.g * self.r * theta.cos()
    }
}

/// The redundant linkage runs with DOP853 and Radau5 (the explicit methods and Radau5 share the
/// constrained accelerations and the projection) with the motion of its minimal model to 1e-9,
/// on its constraints, with the least-norm multipliers: the third crank's pull shared so that
/// λ ⟂ null(Gᵀ), here λ₀ − 2λ₁ + λ₂ = 0 (G's rows (2x, 2y, 2y·b·k) are linear in k).
#[test]
fn a_parallelogram_with_a_third_crank_moves_as_its_minimal_model() {
    let p = ThirdCrank {
        m: 2.0,
        i: 0.4,
        r: 0.8,
        b: 1.0,
        g: 9.81,
    };
    let theta0: f64 = 0.7;
    let q0 = [p.r * theta0.sin(), -p.r * theta0.cos(), 0.0];
    let until = 3.0;
    let minimal = CouplerAngle {
        m: p.m,
        r: p.r,
        g: p.g,
    };
    let reference = Simulation::new(&minimal, [theta0], [0.0])
        .method(Method::Dop853 {
            rtol: 1e-13,
            atol: 1e-13,
        })
        .until(until)
        .sample_every(0.25)
        .run()
        .unwrap();
    for method in [
        Method::Dop853 {
            rtol: 1e-12,
            atol: 1e-12,
        },
        Method::Radau5 {
            rtol: 1e-12,
            atol: 1e-12,
        },
    ] {
        let tr = Simulation::new(&p, q0, [0.0; 3])
            .method(method)
            .until(until)
            .sample_every(0.25)
            .run()
            .unwrap_or_else(|e| panic!("{method:?}: {e}"));
        assert_eq!(tr.t.len(), reference.t.len());
        let mut worst = 0.0_f64;
        for (k, q) in tr.q.iter().enumerate() {
            let theta = q[0].atan2(-q[1]);
            worst = worst.max((theta - reference.q[k][0]).abs()).max(q[2].abs());
            let l = &tr.lambda[k];
            assert!(
                (l[0] - 2.0 * l[1] + l[2]).abs() <= 1e-9 * l[1].abs().max(1.0),
                "{method:?} t = {}: λ = {l:?} is not the least-norm one",
                tr.t[k]
            );
        }
        let c = tr.invariants().constraints.unwrap();
        eprintln!(
            "third crank, {method:?}: {} steps, worst θ difference {worst:.2e}, residuals \
             {:.1e} / {:.1e}",
            tr.stats.steps, c.position, c.velocity
        );
        assert!(worst <= 1e-9, "{method:?}: {worst:e}");
        assert!(c.position <= 1e-13 && c.velocity <= 1e-12, "{c:?}");
    }
}

/// The same parallelogram with two cranks only: no redundant row.
pub struct TwoCranks {
    pub m: f64,
    pub i: f64,
    pub r: f64,
    pub b: f64,
    pub g: f64,
}

#[lagrangian]
impl TwoCranks {
    fn lagrangian(&self, (_x, x_dot): Coord, (y, y_dot): Coord, (_phi, phi_dot): Coord) -> Scalar {
        0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) + 0.5 * self.i * phi_dot * phi_dot
            - self.m * self.g * y
    }
    fn constraints(&self, (x, _): Coord, (y, _): Coord, (phi, _): Coord) -> [Scalar; 2] {
        let crank = |k: f64| {
            let (px, py) = (x + k * self.b * phi.cos(), y + k * self.b * phi.sin());
            (px - k * self.b).powi(2) + py.powi(2) - self.r * self.r
        };
        [crank(0.0), crank(1.0)]
    }
}

/// RATTLE (the variational method's constrained step) runs the redundant linkage: its nodes are
/// those of the two-crank linkage (the same constraint manifold, the same span of constraint
/// forces: the same discrete equations) to round-off, and its Richardson extrapolation over dt
/// and dt/2 (the method is symmetric: its error is even in dt) is the minimal model's motion to
/// 1e-9.
#[test]
fn rattle_runs_the_third_crank_as_the_two_crank_linkage() {
    let (m, i, r, b, g) = (2.0, 0.4, 0.8, 1.0, 9.81);
    let third = ThirdCrank { m, i, r, b, g };
    let two = TwoCranks { m, i, r, b, g };
    let theta0: f64 = 0.7;
    let q0 = [r * theta0.sin(), -r * theta0.cos(), 0.0];
    let until = 3.0;
    let end = |tr: Trajectory<3>| {
        let q = *tr.q.last().unwrap();
        assert!(q[2].abs() < 1e-12, "φ = {}", q[2]);
        q[0].atan2(-q[1])
    };
    let run3 = |dt: f64| {
        Simulation::new(&third, q0, [0.0; 3])
            .method(Method::VariationalMidpoint { dt })
            .until(until)
            .keep_samples(false)
            .run()
            .unwrap()
    };
    let coarse = end(run3(1e-3));
    let fine = end(run3(5e-4));
    let two_crank = end(Simulation::new(&two, q0, [0.0; 3])
        .method(Method::VariationalMidpoint { dt: 1e-3 })
        .until(until)
        .keep_samples(false)
        .run()
        .unwrap());
    let exact = Simulation::new(&CouplerAngle { m, r, g }, [theta0], [0.0])
        .method(Method::Dop853 {
            rtol: 1e-13,
            atol: 1e-13,
        })
        .until(until)
        .keep_samples(false)
        .run()
        .unwrap()
        .q
        .last()
        .unwrap()[0];
    let extrapolated = (4.0 * fine - coarse) / 3.0;
    eprintln!(
        "third crank, RATTLE: θ(3) dt 1e-3 {coarse:.12}, 5e-4 {fine:.12}, extrapolated \
         {extrapolated:.12}, two cranks {two_crank:.12}, minimal model {exact:.12}"
    );
    assert!(
        (coarse - two_crank).abs() < 1e-11,
        "{coarse} against {two_crank}"
    );
    assert!(
        (extrapolated - exact).abs() < 1e-9,
        "{extrapolated} against {exact}"
    );
    // The extrapolation is what closes the gap: dt = 1e-3 alone is order dt² away.
    assert!((coarse - exact).abs() > 1e-8);
}

/// Bricard's mechanism: five rods (length 1, mass 1, square section 0.1) and six hinges, the
/// sixth rod the ground, each hinge's axis at right angles to the rods it joins and to the
/// hinge before it (the orthogonal Bricard linkage, the IFToMM benchmark library's A04: rods
/// of 1 m and 1 kg, section 0.1 m, gravity along −y, 10 s). Its coordinates are the five hinge
/// angles of the open chain from the ground hinge at the origin; its constraints close the loop
/// at the sixth hinge: the chain's end on the ground hinge's point (3 rows) and the last rod's
/// hinge axis along the ground's (2 rows). Five constraints on five coordinates — Grübler's
/// count gives no freedom — yet it moves with one: G has rank 4 along the whole motion.
///
/// The reference configuration (all angles 0) puts the rods on edges of the unit cube: hinges
/// at (0,0,0), (1,0,0), (1,1,0), (1,1,1), (0,1,1), (0,0,1) with axes −y, z, x, −y, z, x (the
/// library's page did not give its coordinates; this one is ours). Released from rest there,
/// gravity moves it along its one freedom.
pub struct Bricard {
    pub m: f64,
    pub side: f64,
    pub g: f64,
}

#[lagrangian(mode = "jets")]
impl Bricard {
    /// The five rods' rotations (body axes along the reference's) and their far hinges.
    #[allow(clippy::type_complexity)]
    fn chain(
        &self,
        a: Scalar,
        b: Scalar,
        c: Scalar,
        d: Scalar,
        e: Scalar,
    ) -> ([Rotation<Scalar>; 5], [Vector3<Scalar>; 5]) {
        let r1 = Rotation::about_y(-a);
        let r2 = r1 * Rotation::about_z(b);
        let r3 = r2 * Rotation::about_x(c);
        let r4 = r3 * Rotation::about_y(-d);
        let r5 = r4 * Rotation::about_z(e);
        let j1 = r1 * Vector3::new(1.0, 0.0, 0.0);
        let j2 = j1 + r2 * Vector3::new(0.0, 1.0, 0.0);
        let j3 = j2 + r3 * Vector3::new(0.0, 0.0, 1.0);
        let j4 = j3 + r4 * Vector3::new(-1.0, 0.0, 0.0);
        let j5 = j4 + r5 * Vector3::new(0.0, -1.0, 0.0);
        ([r1, r2, r3, r4, r5], [j1, j2, j3, j4, j5])
    }

    fn lagrangian(
        &self,
        (a, _a_dot): Coord,
        (b, _b_dot): Coord,
        (c, _c_dot): Coord,
        (d, _d_dot): Coord,
        (e, _e_dot): Coord,
    ) -> Scalar {
        let (r, j) = self.chain(a, b, c, d, e);
        // Each rod's half-length in its body axes, and its inertia: m (1 + s²)/12 across the
        // rod, m s²/6 about it.
        let half = [
            Vector3::new(0.5, 0.0, 0.0),
            Vector3::new(0.0, 0.5, 0.0),
            Vector3::new(0.0, 0.0, 0.5),
            Vector3::new(-0.5, 0.0, 0.0),
            Vector3::new(0.0, -0.5, 0.0),
        ];
        let along = [0, 1, 2, 0, 1];
        let across = self.m * (1.0 + self.side * self.side) / 12.0;
        let about = self.m * self.side * self.side / 6.0;
        let mut lag = 0.0 * a;
        for k in 0..5 {
            let centre = if k == 0 {
                r[0] * half[0]
            } else {
                j[k - 1] + r[k] * half[k]
            };
            let w = body_angular_velocity(&r[k]);
            let mut spin = 0.0 * a;
            for i in 0..3 {
                let inertia = if i == along[k] { about } else { across };
                spin = spin + 0.5 * inertia * w[i] * w[i];
            }
            lag = lag + 0.5 * self.m * velocity(centre).norm_squared() + spin
                - self.m * self.g * centre.y;
        }
        lag
    }

    fn constraints(
        &self,
        (a, _): Coord,
        (b, _): Coord,
        (c, _): Coord,
        (d, _): Coord,
        (e, _): Coord,
    ) -> [Scalar; 5] {
        let (r, j) = self.chain(a, b, c, d, e);
        let axis = r[4] * Vector3::new(1.0, 0.0, 0.0);
        [j[4].x, j[4].y, j[4].z - 1.0, axis.y, axis.z]
    }
}

/// Bricard's mechanism over its 10 s with DOP853, Radau5 and RATTLE: the energy kept (it is
/// conservative), the loop closed at every sample, and the motion on its one-freedom curve —
/// the linkage's symmetry keeps hinges 1, 3, 5 at one angle and 2, 4 at another (a kinematic
/// fact of this configuration curve, found by continuation before this test was written) —
/// and the three methods on one motion.
#[test]
fn bricards_mechanism_moves_with_its_one_freedom() {
    let sys = Bricard {
        m: 1.0,
        side: 0.1,
        g: 9.81,
    };
    let until = 10.0;
    let mut ends = Vec::new();
    for (method, energy_tol) in [
        (
            Method::Dop853 {
                rtol: 1e-13,
                atol: 1e-13,
            },
            1e-8,
        ),
        (
            Method::Radau5 {
                rtol: 1e-12,
                atol: 1e-12,
            },
            1e-7,
        ),
        (Method::VariationalMidpoint { dt: 2e-3 }, 4e-3),
    ] {
        let tr = Simulation::new(&sys, [0.0; 5], [0.0; 5])
            .method(method)
            .until(until)
            .sample_every(0.5)
            .run()
            .unwrap_or_else(|e| panic!("{method:?}: {e}"));
        let inv = tr.invariants();
        let c = inv.constraints.unwrap();
        let drift = inv.energy.expect("conservative").max_abs;
        let mut symmetry = 0.0_f64;
        let mut range = 0.0_f64;
        for q in &tr.q {
            symmetry = symmetry
                .max((q[0] - q[2]).abs())
                .max((q[0] - q[4]).abs())
                .max((q[1] - q[3]).abs());
            range = range.max(q[0].abs());
        }
        eprintln!(
            "Bricard, {method:?}: {} steps, energy drift {:.1e}, residuals {:.1e} / {:.1e}, \
             symmetry {symmetry:.1e}, largest hinge angle {range:.3}",
            tr.stats.steps, drift, c.position, c.velocity
        );
        assert!(range > 0.3, "{method:?}: it moved only {range}");
        assert!(drift <= energy_tol, "{method:?}: {drift:e}");
        assert!(
            c.position <= 1e-12 && c.velocity <= 1e-11,
            "{method:?}: {c:?}"
        );
        assert!(symmetry <= 1e-9, "{method:?}: {symmetry:e}");
        ends.push(*tr.q.last().unwrap());
    }
    // DOP853 and Radau5 at their tolerances; RATTLE (order 2, dt 1e-3) to its error.
    let gap = |a: &[f64; 5], b: &[f64; 5]| (0..5).fold(0.0_f64, |m, i| m.max((a[i] - b[i]).abs()));
    assert!(
        gap(&ends[0], &ends[1]) <= 1e-7,
        "{:e}",
        gap(&ends[0], &ends[1])
    );
    eprintln!(
        "end-state gaps {:.1e} {:.1e}",
        gap(&ends[0], &ends[1]),
        gap(&ends[0], &ends[2])
    );
    assert!(
        gap(&ends[0], &ends[2]) <= 1e-3,
        "{:e}",
        gap(&ends[0], &ends[2])
    );
}
