//! The passive compass-gait walker of the `walker` example and the walker tests (Goswami,
//! Thuilot & Espiau, INRIA report 2996, 1996): two straight legs of length l = a + b with a
//! point mass m each (a from the foot, b from the hip) and a point mass m_H at the hip, walking
//! down a slope γ. Written as a user writes it: L of the stance phase (the stance foot a fixed
//! pivot), and the heel strike as a resetting event whose reset comes from the conservation of
//! the momenta the impulse at the landing foot does no work on.
//!
//! Coordinates in the slope's frame (x downhill, y along the slope's normal): θ₁ the stance
//! leg's angle and θ₂ the swing leg's, each the direction from the leg's foot to the hip,
//! e(θ) = (sin θ, cos θ), measured from the slope's normal, positive downhill.
//!
//! With m → 0 (a = 0, b = l: the leg masses at the feet) this is the *simplest walking model*
//! of Garcia, Chatterjee, Ruina & Coleman (J. Biomech. Eng. 120, 1998): its θ and φ are −θ₁
//! and θ₂ − θ₁ here.

use lagrange::prelude::*;
use lagrange::sensitivity::{OrbitError, PeriodicOrbit, Shooting};

/// A compass-gait walker on a slope (see the [module documentation](self)).
pub struct CompassGait {
    /// Hip mass m_H.
    pub m_hip: f64,
    /// Each leg's mass m.
    pub m: f64,
    /// The leg mass's distance from the foot.
    pub a: f64,
    /// The leg mass's distance from the hip.
    pub b: f64,
    /// Gravity.
    pub g: f64,
    /// The slope γ (rad).
    pub slope: f64,
}

#[lagrangian]
impl CompassGait {
    fn lagrangian(&self, (th1, th1_dot): Coord, (th2, th2_dot): Coord) -> Scalar {
        let (mh, m, a, b, g) = (self.m_hip, self.m, self.a, self.b, self.g);
        let l = a + b;
        // T: the stance leg turns about its foot, the swing leg hangs from the moving hip.
        0.5 * (m * a * a + (mh + m) * l * l) * th1_dot * th1_dot
            + 0.5 * m * b * b * th2_dot * th2_dot
            - m * l * b * th1_dot * th2_dot * (th1 - th2).cos()
            // V in the slope's frame, gravity g (sin γ, −cos γ).
            - g * (m * a + (mh + m) * l) * (th1 + self.slope).cos()
            + g * m * b * (th2 + self.slope).cos()
    }

    /// What it looks like, gravity down (the slope's frame turned by γ): the legs, the hip and
    /// the leg masses, a stretch of the slope, the hip's path (in the stance foot's frame: the
    /// walker is drawn as seen from the foot it stands on).
    fn scene(&self, (th1, _): Coord, (th2, _): Coord) -> Scene {
        let l = self.a + self.b;
        let e = |th: f64| Vector3::new(th.sin(), th.cos(), 0.0);
        let hip = e(th1) * l;
        let swing_foot = hip - e(th2) * l;
        let up = Vector3::new(-self.slope.sin(), self.slope.cos(), 0.0);
        Scene::new()
            .up(up)
            .cuboid(
                "slope",
                Rotation::identity(),
                Vector3::new(0.0, -0.02 * l, 0.0),
                Vector3::new(3.0 * l, 0.04 * l, 0.8 * l),
                Rgb::GREY,
            )
            .rod("stance leg", Vector3::zeros(), hip, 0.02 * l, Rgb::STEEL)
            .rod("swing leg", hip, swing_foot, 0.02 * l, Rgb::ORANGE)
            .sphere("hip", hip, 0.06 * l, Rgb::RED)
            .sphere("stance mass", e(th1) * self.a, 0.04 * l, Rgb::STEEL)
            .sphere("swing mass", hip - e(th2) * self.b, 0.04 * l, Rgb::ORANGE)
            .trace("hip's path", hip, Rgb::RED)
    }
}

impl CompassGait {
    /// How far past the slope's normal (rad) the swing leg must be for its foot's landing to
    /// count as a heel strike ([`heel_strike_event`](Self::heel_strike_event)): the passages
    /// of the foot through the ground nearer the normal are the compass gait's scuffing.
    pub const SCUFF: f64 = 0.1;

    /// Goswami, Thuilot & Espiau's walker on a slope of `degrees`: m_H = 10, m = 5,
    /// a = b = 0.5, g = 9.8 (the parameters of their report and of the literature's passive
    /// gait at 3°).
    ///
    /// ```
    /// use lagrange_examples::walker_system::CompassGait;
    /// let w = CompassGait::goswami(3.0);
    /// assert_eq!((w.leg(), w.m_hip / w.m), (1.0, 2.0));
    /// ```
    pub fn goswami(degrees: f64) -> Self {
        CompassGait {
            m_hip: 10.0,
            m: 5.0,
            a: 0.5,
            b: 0.5,
            g: 9.8,
            slope: degrees.to_radians(),
        }
    }

    /// Garcia et al.'s simplest walker on a slope γ (rad): the feet's masses 1e-20 of the
    /// hip's (their O(β) corrections below round-off), unit hip mass, g and l.
    ///
    /// ```
    /// use lagrange_examples::walker_system::CompassGait;
    /// let w = CompassGait::simplest(0.009);
    /// assert_eq!((w.a, w.b, w.leg()), (0.0, 1.0, 1.0));
    /// ```
    pub fn simplest(slope: f64) -> Self {
        CompassGait {
            m_hip: 1.0,
            m: 1e-20,
            a: 0.0,
            b: 1.0,
            g: 1.0,
            slope,
        }
    }

    /// The leg length l = a + b.
    pub fn leg(&self) -> f64 {
        self.a + self.b
    }

    /// The heel strike: (q⁺, q̇⁺) from the state just before the swing foot lands.
    ///
    /// The legs trade roles (θ₁⁺ = θ₂⁻, θ₂⁺ = θ₁⁻: the positions do not jump) and the impulse
    /// at the landing foot, the new pivot, does no work on any virtual motion the new
    /// coordinates describe; the trailing foot leaves the ground without an impulse. So each
    /// momentum conjugate to the new coordinates, p_k = Σᵢ mᵢ vᵢ·∂rᵢ/∂θₖ⁺ (the masses'
    /// velocities vᵢ, their positions rᵢ from the new pivot), is the same just before and just
    /// after, and M(q⁺) q̇⁺ = p⁻ gives the velocities: the conservation of the angular momentum
    /// of the whole walker about the landing foot and of the trailing leg about the hip.
    /// The mass matrix is the system's own ([`Lagrangian::mass_matrix`]).
    ///
    /// ```
    /// use lagrange_examples::walker_system::CompassGait;
    /// // The simplest walker's limit (m → 0): θ̇₁⁺ = cos 2θ₁⁻ θ̇₁⁻ (Garcia et al. 1998, eq. 5).
    /// let w = CompassGait { m_hip: 1.0, m: 1e-20, a: 0.0, b: 1.0, g: 1.0, slope: 0.009 };
    /// let (q, v) = w.heel_strike(&[0.2, -0.2], &[0.2, -0.3]).unwrap();
    /// assert_eq!(q, [-0.2, 0.2]);
    /// assert!((v[0] - 0.4_f64.cos() * 0.2).abs() < 1e-15);
    /// ```
    pub fn heel_strike(
        &self,
        q: &[f64; 2],
        v: &[f64; 2],
    ) -> Result<([f64; 2], [f64; 2]), DynamicsError> {
        let (a, b, l, m, mh) = (self.a, self.b, self.leg(), self.m, self.m_hip);
        // d e(θ)/dθ.
        let de = |th: f64| [th.cos(), -th.sin()];
        let dot = |x: [f64; 2], y: [f64; 2]| x[0] * y[0] + x[1] * y[1];
        let scale = |s: f64, x: [f64; 2]| [s * x[0], s * x[1]];
        let sub = |x: [f64; 2], y: [f64; 2]| [x[0] - y[0], x[1] - y[1]];
        // The masses' velocities just before, from the old pivot.
        let v_stance_mass = scale(a * v[0], de(q[0]));
        let v_hip = scale(l * v[0], de(q[0]));
        let v_swing_mass = sub(v_hip, scale(b * v[1], de(q[1])));
        let q_plus = [q[1], q[0]];
        // From the new pivot: the old swing leg's mass at a e(θ₁⁺), the hip at l e(θ₁⁺), the
        // old stance leg's mass at l e(θ₁⁺) − b e(θ₂⁺).
        let (d1, d2) = (de(q_plus[0]), de(q_plus[1]));
        let p = [
            m * a * dot(v_swing_mass, d1)
                + mh * l * dot(v_hip, d1)
                + m * l * dot(v_stance_mass, d1),
            -m * b * dot(v_stance_mass, d2),
        ];
        let mass = self.mass_matrix(&q_plus, &[0.0; 2], 0.0);
        let upper = [[mass[(0, 0)], mass[(0, 1)]], [mass[(1, 0)], mass[(1, 1)]]];
        let v_plus = lagrange::solve_mass_matrix(&upper, &p, Self::COORDINATES, &q_plus, v, 0.0)?;
        Ok((q_plus, v_plus))
    }

    /// The heel strike as an event: the swing foot lands in front where the legs are
    /// symmetric about the slope's normal, θ₁ + θ₂ = 0 rising (θ₂ < 0). The compass gait's
    /// straight swing leg passes through the ground twice on the way (the scuffing every
    /// compass-gait model lets pass): behind the stance leg before mid-stance, and on a short
    /// step in front of it too, where θ₁ + θ₂ crosses 0 as well (rising just after each
    /// strike, falling as the foot comes out in front). So a strike counts only once the swing
    /// leg is [`SCUFF`](Self::SCUFF) past the normal: the event's function is
    /// min(θ₁ + θ₂, −θ₂ − SCUFF), rising through 0; it is ≤ −2α just after a strike (far from
    /// a crossing, whatever the round-off of the reset).
    ///
    /// ```
    /// use lagrange_examples::walker_system::CompassGait;
    /// let w = CompassGait { m_hip: 10.0, m: 5.0, a: 0.5, b: 0.5, g: 9.81, slope: 0.05 };
    /// let e = w.heel_strike_event();
    /// assert!(e.is_reset() && e.value(0.0, &[0.2, -0.2], &[0.0; 2]) == 0.0);
    /// assert!(e.value(0.0, &[-0.2, 0.2], &[0.0; 2]) < -0.2); // just after a strike
    /// assert!(e.value(0.0, &[0.03, 0.02], &[0.0; 2]) < 0.0); // scuffing in front
    /// ```
    pub fn heel_strike_event(&self) -> Event<'_, 2> {
        Event::zero_crossing("heel strike", |_t, q: &[f64; 2], _v| {
            (q[0] + q[1]).min(-q[1] - Self::SCUFF)
        })
        .rising()
        .reset_fallible(move |_t, q, v| {
            let (q, v) = self.heel_strike(q, v)?;
            Ok([q, v])
        })
    }

    /// Mid-stance as an event: the stance leg passes the slope's normal (θ₁ = 0 rising): the
    /// Poincaré section the gait is shot on.
    ///
    /// ```
    /// use lagrange_examples::walker_system::CompassGait;
    /// let w = CompassGait { m_hip: 10.0, m: 5.0, a: 0.5, b: 0.5, g: 9.81, slope: 0.05 };
    /// assert_eq!(w.mid_stance_event().value(0.0, &[0.1, -0.3], &[0.0; 2]), 0.1);
    /// ```
    pub fn mid_stance_event(&self) -> Event<'static, 2> {
        Event::zero_crossing("mid-stance", |_t, q: &[f64; 2], _v| q[0]).rising()
    }

    /// The state (q, q̇) just after a heel strike written in the coordinates of Garcia et al.
    /// and Goswami et al. (the stance leg's angle from the slope's normal, its rate, the angle
    /// between the legs and its rate, with their signs): (θ, θ̇, φ, φ̇) = (−θ₁, −θ̇₁, θ₂ − θ₁,
    /// θ̇₂ − θ̇₁).
    ///
    /// ```
    /// use lagrange_examples::walker_system::CompassGait;
    /// let w = CompassGait { m_hip: 1.0, m: 1e-20, a: 0.0, b: 1.0, g: 1.0, slope: 0.009 };
    /// assert_eq!(w.garcia_state(&[-0.2, 0.2], &[0.2, 0.1]), [0.2, -0.2, 0.4, -0.1]);
    /// ```
    pub fn garcia_state(&self, q: &[f64; 2], v: &[f64; 2]) -> [f64; 4] {
        [-q[0], -v[0], q[1] - q[0], v[1] - v[0]]
    }

    /// The inverse of [`garcia_state`](Self::garcia_state).
    ///
    /// ```
    /// use lagrange_examples::walker_system::CompassGait;
    /// let w = CompassGait { m_hip: 1.0, m: 1e-20, a: 0.0, b: 1.0, g: 1.0, slope: 0.009 };
    /// assert_eq!(w.from_garcia_state(&[0.2, -0.2, 0.4, -0.1]), ([-0.2, 0.2], [0.2, 0.1]));
    /// ```
    pub fn from_garcia_state(&self, x: &[f64; 4]) -> ([f64; 2], [f64; 2]) {
        ([-x[0], x[2] - x[0]], [-x[1], x[3] - x[1]])
    }

    /// The first state on mid-stance ([`mid_stance_event`](Self::mid_stance_event)) the walker
    /// reaches from (q, q̇), through any heel strikes on the way (within 50 step times of
    /// √(l/g)).
    pub fn to_mid_stance(
        &self,
        q: [f64; 2],
        v: [f64; 2],
        method: Method,
    ) -> Result<([f64; 2], [f64; 2]), SimulationError> {
        let run = Simulation::new(self, q, v)
            .method(method)
            .event(self.heel_strike_event())
            .event(self.mid_stance_event().terminal())
            .until(50.0 * (self.leg() / self.g).sqrt())
            .keep_samples(false)
            .run()?;
        match run.events.iter().rev().find(|e| e.name == "mid-stance") {
            Some(hit) => Ok((hit.q, hit.qdot)),
            None => Err(SimulationError::InvalidOptions {
                message: format!(
                    "the walker did not reach mid-stance from q = {q:?}, q̇ = {v:?} (it fell or \
                     stopped): start nearer a gait"
                ),
            }),
        }
    }

    /// The state just after the next heel strike from (q, q̇).
    pub fn after_strike(
        &self,
        q: [f64; 2],
        v: [f64; 2],
        method: Method,
    ) -> Result<([f64; 2], [f64; 2]), Box<dyn std::error::Error>> {
        let run = Simulation::new(self, q, v)
            .method(method)
            .event(self.heel_strike_event().terminal())
            .until(50.0 * (self.leg() / self.g).sqrt())
            .keep_samples(false)
            .run()?;
        match run.events.last() {
            Some(hit) => Ok(self.heel_strike(&hit.q, &hit.qdot)?),
            None => {
                Err(format!("no heel strike from q = {q:?}, q̇ = {v:?}: start nearer a gait").into())
            }
        }
    }

    /// The period-one gait through a mid-stance state near (q, q̇) (from
    /// [`to_mid_stance`](Self::to_mid_stance)): the fixed point of the step-to-step map on the
    /// mid-stance section, shot through the heel strike, with the map's multipliers (the
    /// orbit's `period` is the step time). `step_time` bounds each shot (twice it).
    pub fn gait(
        &self,
        q: [f64; 2],
        v: [f64; 2],
        step_time: f64,
        method: Method,
    ) -> Result<PeriodicOrbit<2>, OrbitError> {
        Shooting::autonomous(self, q, v, step_time)
            .method(method)
            .event(|| self.heel_strike_event())
            .section(|| self.mid_stance_event())
            .find()
    }
}
