//! Redundant constraints: rows of G that depend on the others (everywhere, or along the motion)
//! are run, not refused — the multipliers are the least-norm ones (the one constraint force
//! Gᵀλ, split with the smallest |λ|), the projection the least-squares correction of least norm;
//! constraints that are dependent *and* contradict each other are refused with
//! `DependentConstraints` naming them. DOP853, Radau5 and RATTLE each run a parallelogram
//! linkage with a third crank against its minimal model.

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
