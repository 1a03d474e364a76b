//! The Whipple bicycle of the benchmark of Meijaard, Papadopoulos, Ruina and Schwab (Proc. R.
//! Soc. A 463 (2007), "Linearized dynamics equations for the balance and steer of a bicycle: a
//! benchmark and review"), written from its nonlinear geometry: four rigid bodies (rear wheel,
//! rear frame with rider, front fork with handlebar, front wheel), both knife-edge wheels
//! rolling without slip, the front wheel touching the ground. Not from the paper's matrices:
//! the `bicycle` example and the tests linearize this and compare.
//!
//! Axes as in the paper: x forward, y to the right, z down, the origin at the rear contact in
//! the upright reference. Coordinates: the rear contact (x, y), the rear frame's yaw ψ, roll φ
//! (positive: leaning right) and pitch θ (R_B = R_z(ψ) R_x(φ) R_y(θ)), the steer angle δ about
//! the steer axis (tilted back by λ from the vertical, positive: steering right), and the
//! wheels' rotations θ_R, θ_F about their axles.

use lagrange::prelude::*;

/// A 3 × 3 inertia tensor.
pub type Matrix3 = SMatrix<f64, 3, 3>;

/// The Whipple bicycle (parameters of the benchmark's Table 1 in [`Bicycle::benchmark`]).
pub struct Bicycle {
    /// Wheelbase w.
    pub w: f64,
    /// Trail c.
    pub c: f64,
    /// Steer axis tilt λ (from the vertical).
    pub lambda: f64,
    /// Gravity.
    pub g: f64,
    /// Rear wheel radius, mass, and inertias about a diameter and the axle.
    pub r_r: f64,
    pub m_r: f64,
    pub i_rxx: f64,
    pub i_ryy: f64,
    /// Rear frame's centre of mass (x, z) in the reference, mass, inertia about it.
    pub x_b: f64,
    pub z_b: f64,
    pub m_b: f64,
    pub i_b: Matrix3,
    /// Front fork's centre of mass, mass, inertia.
    pub x_h: f64,
    pub z_h: f64,
    pub m_h: f64,
    pub i_h: Matrix3,
    /// Front wheel radius, mass, and inertias.
    pub r_f: f64,
    pub m_f: f64,
    pub i_fxx: f64,
    pub i_fyy: f64,
}

impl Bicycle {
    /// The benchmark bicycle of the paper's Table 1.
    ///
    /// ```
    /// use lagrange_examples::bicycle_system::Bicycle;
    /// let b = Bicycle::benchmark();
    /// assert_eq!((b.w, b.c, b.m_b), (1.02, 0.08, 85.0));
    /// ```
    pub fn benchmark() -> Self {
        Bicycle {
            w: 1.02,
            c: 0.08,
            lambda: std::f64::consts::PI / 10.0,
            g: 9.81,
            r_r: 0.3,
            m_r: 2.0,
            i_rxx: 0.0603,
            i_ryy: 0.12,
            x_b: 0.3,
            z_b: -0.9,
            m_b: 85.0,
            i_b: Matrix3::new(9.2, 0.0, 2.4, 0.0, 11.0, 0.0, 2.4, 0.0, 2.8),
            x_h: 0.9,
            z_h: -0.7,
            m_h: 4.0,
            i_h: Matrix3::new(
                0.05892, 0.0, -0.00756, 0.0, 0.06, 0.0, -0.00756, 0.0, 0.00708,
            ),
            r_f: 0.35,
            m_f: 3.0,
            i_fxx: 0.1405,
            i_fyy: 0.28,
        }
    }

    /// The upright reference at forward speed v: (q, q̇) with the wheels rolling.
    ///
    /// ```
    /// use lagrange_examples::bicycle_system::Bicycle;
    /// let (q, v) = Bicycle::benchmark().upright(3.0);
    /// assert_eq!((q, v[0], v[6]), ([0.0; 8], 3.0, -10.0));
    /// ```
    pub fn upright(&self, v: f64) -> ([f64; 8], [f64; 8]) {
        let mut qdot = [0.0; 8];
        qdot[0] = v;
        qdot[6] = -v / self.r_r;
        qdot[7] = -v / self.r_f;
        ([0.0; 8], qdot)
    }
}

/// The benchmark's published matrices (Meijaard et al. 2007, eqs. (A 20)–(A 24)): M, C₁, K₀,
/// K₂ of M q̈ + v C₁ q̇ + (g K₀ + v² K₂) q = f in q = (φ, δ), row by row.
pub mod published {
    /// M.
    pub const M: [[f64; 2]; 2] = [
        [80.81722, 2.31941332208709],
        [2.31941332208709, 0.29784188199686],
    ];
    /// C₁.
    pub const C1: [[f64; 2]; 2] = [
        [0.0, 33.86641391492494],
        [-0.85035641456978, 1.68540397397560],
    ];
    /// K₀.
    pub const K0: [[f64; 2]; 2] = [
        [-80.95, -2.59951685249872],
        [-2.59951685249872, -0.80329488458618],
    ];
    /// K₂.
    pub const K2: [[f64; 2]; 2] = [[0.0, 76.59734589573222], [0.0, 2.65431523794604]];
    /// The eigenvalues at v = 0 (the paper's Table 2): ±5.53094371765393, ±3.13164324790656.
    pub const STANDSTILL: [f64; 2] = [5.53094371765393, 3.13164324790656];
    /// The weave speed (a Hopf bifurcation) and the capsize speed, m/s.
    pub const WEAVE: f64 = 4.29238253634111;
    /// See [`WEAVE`].
    pub const CAPSIZE: f64 = 6.02426201538837;
}

impl Bicycle {
    /// The linearization about upright straight running at speed v, reduced to the lean φ and
    /// the steer δ: M, C, K of M q̈ + C q̇ + K q = 0 (the paper's M, v C₁, g K₀ + v² K₂).
    ///
    /// ```
    /// use lagrange_examples::bicycle_system::Bicycle;
    /// let lin = Bicycle::benchmark().lean_and_steer(0.0).unwrap();
    /// assert!((lin.m[(0, 0)] - 80.81722).abs() < 1e-9);
    /// ```
    pub fn lean_and_steer(&self, v: f64) -> Result<Linearization<2>, LinearizationError> {
        let (q, qdot) = self.upright(v);
        self.linearize_on_constraints(&q, &qdot, 0.0)?
            .reduce(["phi", "delta"])
    }

    /// The largest real part of the lean/steer eigenvalues at speed v (NaN where the
    /// linearization fails): negative inside the stable speed band.
    pub fn growth(&self, v: f64) -> f64 {
        self.lean_and_steer(v)
            .and_then(|l| l.eigenvalues())
            .map_or(f64::NAN, |e| {
                e.iter().map(|l| l.re).fold(f64::MIN, f64::max)
            })
    }

    /// The weave speed (the largest real part falls through zero) and the capsize speed (it
    /// rises through zero), by bisection to 1e-13 m/s in [2, 5] and [5, 8].
    ///
    /// ```
    /// use lagrange_examples::bicycle_system::Bicycle;
    /// let (weave, capsize) = Bicycle::benchmark().stable_band();
    /// assert!((weave - 4.2923825363).abs() < 1e-9 && (capsize - 6.0242620154).abs() < 1e-9);
    /// ```
    pub fn stable_band(&self) -> (f64, f64) {
        let root = |mut a: f64, mut b: f64| {
            let fa = self.growth(a);
            for _ in 0..200 {
                let m = 0.5 * (a + b);
                if b - a <= 1e-13 {
                    break;
                }
                if (self.growth(m) > 0.0) == (fa > 0.0) {
                    a = m;
                } else {
                    b = m;
                }
            }
            0.5 * (a + b)
        };
        (root(2.0, 5.0), root(5.0, 8.0))
    }
}

#[lagrangian(mode = "jets")]
impl Bicycle {
    /// The geometry the three functions below share, from the rear contact (x, y), yaw, roll,
    /// pitch and steer: the heading R_z(ψ)R_x(φ), the rear frame's and the fork's rotations, the
    /// rear wheel's centre and the steer axis' reference point on the ground.
    #[allow(clippy::type_complexity)]
    fn frames(
        &self,
        x: Scalar,
        y: Scalar,
        psi: Scalar,
        phi: Scalar,
        theta: Scalar,
        delta: Scalar,
    ) -> (
        Rotation<Scalar>,
        Rotation<Scalar>,
        Rotation<Scalar>,
        Vector3<Scalar>,
        Vector3<Scalar>,
    ) {
        let heading = Rotation::about_z(psi) * Rotation::about_x(phi);
        let rear = heading * Rotation::about_y(theta);
        let fork = rear
            * Rotation::about_y(self.lambda)
            * Rotation::about_z(delta)
            * Rotation::about_y(-self.lambda);
        // The rear wheel's centre above its contact, in the wheel's plane.
        let c_r = Vector3::new(x, y, 0.0) - heading * Vector3::new(0.0, 0.0, self.r_r);
        // The steer axis' point on the ground in the reference, carried by the rear frame.
        let s = c_r + rear * Vector3::new(self.w + self.c, 0.0, self.r_r);
        (heading, rear, fork, c_r, s)
    }

    #[allow(clippy::too_many_arguments)]
    fn lagrangian(
        &self,
        (x, _x_dot): Coord,
        (y, _y_dot): Coord,
        (psi, _psi_dot): Coord,
        (phi, _phi_dot): Coord,
        (theta, _theta_dot): Coord,
        (delta, _delta_dot): Coord,
        (theta_r, _theta_r_dot): Coord,
        (theta_f, _theta_f_dot): Coord,
    ) -> Scalar {
        let (_, rear, fork, c_r, s) = self.frames(x, y, psi, phi, theta, delta);
        let b = c_r + rear * Vector3::new(self.x_b, 0.0, self.z_b + self.r_r);
        let h = s + fork * Vector3::new(self.x_h - self.w - self.c, 0.0, self.z_h);
        let c_f = s + fork * Vector3::new(-self.c, 0.0, -self.r_f);
        let rear_wheel = rear * Rotation::about_y(theta_r);
        let front_wheel = fork * Rotation::about_y(theta_f);
        let (w_r, w_b) = (
            body_angular_velocity(&rear_wheel),
            body_angular_velocity(&rear),
        );
        let (w_h, w_f) = (
            body_angular_velocity(&fork),
            body_angular_velocity(&front_wheel),
        );
        let kinetic = 0.5 * self.m_r * velocity(c_r).norm_squared()
            + 0.5 * (self.i_rxx * (w_r.x * w_r.x + w_r.z * w_r.z) + self.i_ryy * w_r.y * w_r.y)
            + 0.5 * self.m_b * velocity(b).norm_squared()
            + 0.5 * w_b.dot(&(self.i_b * w_b))
            + 0.5 * self.m_h * velocity(h).norm_squared()
            + 0.5 * w_h.dot(&(self.i_h * w_h))
            + 0.5 * self.m_f * velocity(c_f).norm_squared()
            + 0.5 * (self.i_fxx * (w_f.x * w_f.x + w_f.z * w_f.z) + self.i_fyy * w_f.y * w_f.y);
        // z points down: the potential energy is −Σ m g z.
        let height = self.m_r * c_r.z + self.m_b * b.z + self.m_h * h.z + self.m_f * c_f.z;
        kinetic + self.g * height
    }

    /// The front wheel touches the ground: its lowest point, in its plane below its centre, is
    /// at z = 0.
    #[allow(clippy::too_many_arguments)]
    fn constraints(
        &self,
        (x, _): Coord,
        (y, _): Coord,
        (psi, _): Coord,
        (phi, _): Coord,
        (theta, _): Coord,
        (delta, _): Coord,
        (_, _): Coord,
        (_, _): Coord,
    ) -> [Scalar; 1] {
        let (_, _, fork, _, s) = self.frames(x, y, psi, phi, theta, delta);
        let c_f = s + fork * Vector3::new(-self.c, 0.0, -self.r_f);
        let axle = fork * Vector3::new(0.0, 1.0, 0.0);
        // |ẑ − (ẑ·n) n| = √(1 − n_z²): the contact is r_F along the unit of ẑ − (ẑ·n) n.
        let reach = self.r_f * (1.0 - axle.z * axle.z).sqrt();
        [c_f.z + reach]
    }

    /// Both wheels roll without slipping: the material point at each contact is at rest
    /// (its horizontal velocity; the vertical one follows from the contact).
    #[allow(clippy::too_many_arguments)]
    fn velocity_constraints(
        &self,
        (x, _): Coord,
        (y, _): Coord,
        (psi, _): Coord,
        (phi, _): Coord,
        (theta, _): Coord,
        (delta, _): Coord,
        (theta_r, _): Coord,
        (theta_f, _): Coord,
    ) -> [Scalar; 4] {
        let (heading, rear, fork, c_r, s) = self.frames(x, y, psi, phi, theta, delta);
        let down_r = heading * Vector3::new(0.0, 0.0, self.r_r);
        let c_f = s + fork * Vector3::new(-self.c, 0.0, -self.r_f);
        let axle = fork * Vector3::new(0.0, 1.0, 0.0);
        let nz = axle.z;
        let down_f = Vector3::new(-nz * axle.x, -nz * axle.y, 1.0 - nz * nz)
            * (self.r_f / (1.0 - nz * nz).sqrt());
        let slip_r =
            velocity(c_r) + angular_velocity(&(rear * Rotation::about_y(theta_r))).cross(&down_r);
        let slip_f =
            velocity(c_f) + angular_velocity(&(fork * Rotation::about_y(theta_f))).cross(&down_f);
        [slip_r.x, slip_r.y, slip_f.x, slip_f.y]
    }

    /// What it looks like (z down, as the paper's axes): the wheels (a mark on each rim shows
    /// it turn), the rear frame from the rear axle to the head and to the rider, the fork from
    /// the head to the front axle, the rider's mass as a ball, and the two contacts' paths.
    #[allow(clippy::too_many_arguments)]
    fn scene(
        &self,
        (x, _): Coord,
        (y, _): Coord,
        (psi, _): Coord,
        (phi, _): Coord,
        (theta, _): Coord,
        (delta, _): Coord,
        (theta_r, _): Coord,
        (theta_f, _): Coord,
    ) -> Scene {
        let (_, rear, fork, c_r, s) = self.frames(x, y, psi, phi, theta, delta);
        let c_f = s + fork * Vector3::new(-self.c, 0.0, -self.r_f);
        let rider = c_r + rear * Vector3::new(self.x_b, 0.0, self.z_b + self.r_r);
        // The steer axis, tilted back by λ, from its ground point up to the head.
        let axis = rear * Vector3::new(self.lambda.sin(), 0.0, self.lambda.cos());
        let head = s - axis * (1.4 * self.r_f / self.lambda.cos());
        // A wheel's plane has the axle (its frame's y) as normal: the disc's z is the axle.
        let side = Rotation::about_x(-std::f64::consts::FRAC_PI_2);
        let rim_r = c_r + rear * Rotation::about_y(theta_r) * Vector3::new(0.0, 0.0, self.r_r);
        let rim_f = c_f + fork * Rotation::about_y(theta_f) * Vector3::new(0.0, 0.0, self.r_f);
        let ground = |p: Vector3<f64>| Vector3::new(p.x, p.y, 0.0);
        Scene::new()
            .up(-Vector3::z())
            .disc("rear wheel", rear * side, c_r, self.r_r, 0.04, Rgb::BLACK)
            .disc("front wheel", fork * side, c_f, self.r_f, 0.04, Rgb::BLACK)
            .sphere("rear mark", rim_r, 0.05, Rgb::YELLOW)
            .sphere("front mark", rim_f, 0.05, Rgb::YELLOW)
            .rod("frame", c_r, head, 0.03, Rgb::STEEL)
            .rod("seat post", c_r, rider, 0.03, Rgb::STEEL)
            .rod("fork", head, c_f, 0.03, Rgb::GREY)
            .sphere("rider", rider, 0.25, Rgb::ORANGE)
            .trace("rear contact", ground(c_r), Rgb::RED)
            .trace("front contact", ground(c_f), Rgb::BLUE)
    }
}

impl Bicycle {
    /// A run to watch: from upright straight running at `v` m/s with a lean rate of 0.3 rad/s,
    /// `until` seconds, a sample every 10 ms (at 3 m/s it weaves and grows, at 5 m/s it
    /// decays).
    ///
    /// ```
    /// use lagrange_examples::bicycle_system::Bicycle;
    /// let tr = Bicycle::benchmark().watch(5.0, 0.1).unwrap();
    /// assert_eq!(tr.t.len(), 11);
    /// ```
    pub fn watch(&self, v: f64, until: f64) -> Result<Trajectory<8>, SimulationError> {
        self.watch_every(v, until, 0.01)
    }

    /// [`Bicycle::watch`] with a sample every `dt` seconds.
    ///
    /// ```
    /// use lagrange_examples::bicycle_system::Bicycle;
    /// let tr = Bicycle::benchmark().watch_every(5.0, 0.1, 0.05).unwrap();
    /// assert_eq!(tr.t.len(), 3);
    /// ```
    pub fn watch_every(
        &self,
        v: f64,
        until: f64,
        dt: f64,
    ) -> Result<Trajectory<8>, SimulationError> {
        let (q0, mut v0) = self.upright(v);
        v0[3] = 0.3;
        Simulation::new(self, q0, v0)
            .project_initial_state()
            .method(Method::Dop853 {
                rtol: 1e-9,
                atol: 1e-11,
            })
            .until(until)
            .sample_every(dt)
            .run()
    }
}
