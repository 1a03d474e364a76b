//! Rigid-body helpers: the inertia tensor of point masses, its shift to the centre of mass, and
//! the z-x-z Euler-angle chart (rotation matrix, body angular velocity, and a guard that turns a
//! run approaching the chart's singularity sin θ = 0 into a typed error).
//!
//! ```
//! use lagrange_runtime::rigid::{inertia_tensor, centre_of_mass, shift_from_centre_of_mass};
//! let body = [(1.0, [1.0, 0.0, 0.0]), (3.0, [0.0, 2.0, 0.0])];
//! let (m, r) = centre_of_mass(&body);
//! let about_cm = inertia_tensor(&body.map(|(mi, ri)| (mi, [ri[0] - r[0], ri[1] - r[1], ri[2] - r[2]])));
//! let shifted = shift_from_centre_of_mass(m, r, &about_cm);
//! assert!((shifted - inertia_tensor(&body)).abs().max() < 1e-14);
//! ```

use nalgebra::{Matrix3, Vector3};

use crate::error::DynamicsError;
use crate::integrate::{Event, Trajectory};

/// The inertia tensor I_ij = Σ_a m_a (r_a² δ_ij − r_ai r_aj) of point masses `(m_a, r_a)` about
/// the origin (eq. 76 of the reference text).
///
/// ```
/// use lagrange_runtime::rigid::inertia_tensor;
/// // Two unit masses at x = ±1: no inertia about x, 2 about y and z.
/// let i = inertia_tensor(&[(1.0, [1.0, 0.0, 0.0]), (1.0, [-1.0, 0.0, 0.0])]);
/// assert_eq!((i[(0, 0)], i[(1, 1)], i[(2, 2)], i[(0, 1)]), (0.0, 2.0, 2.0, 0.0));
/// ```
pub fn inertia_tensor(points: &[(f64, [f64; 3])]) -> Matrix3<f64> {
    points.iter().fold(Matrix3::zeros(), |acc, &(m, r)| {
        let r = Vector3::from(r);
        acc + (Matrix3::identity() * r.norm_squared() - r * r.transpose()) * m
    })
}

/// The total mass M and the centre of mass R = Σ m_a r_a / M of point masses (R is the origin
/// when M = 0).
///
/// ```
/// use lagrange_runtime::rigid::centre_of_mass;
/// let (m, r) = centre_of_mass(&[(1.0, [0.0, 0.0, 0.0]), (3.0, [4.0, 0.0, 0.0])]);
/// assert_eq!((m, r), (4.0, [3.0, 0.0, 0.0]));
/// ```
pub fn centre_of_mass(points: &[(f64, [f64; 3])]) -> (f64, [f64; 3]) {
    let m: f64 = points.iter().map(|p| p.0).sum();
    let s = points.iter().fold(Vector3::zeros(), |acc, &(mi, r)| {
        acc + Vector3::from(r) * mi
    });
    if m == 0.0 {
        (m, [0.0; 3])
    } else {
        (m, (s / m).into())
    }
}

/// The moment of inertia about the axis through `point` with direction `axis` (normalised
/// here): I_n = Σ_a m_a [ρ_a² − (n̂·ρ_a)²], ρ_a = r_a − point (eq. 69 of the reference text).
/// Returns 0 for a zero `axis`.
///
/// ```
/// use lagrange_runtime::rigid::moment_about_axis;
/// // A unit mass at (1, 1, 0) about the x axis: distance 1 from it.
/// let i = moment_about_axis(&[(1.0, [1.0, 1.0, 0.0])], [0.0; 3], [2.0, 0.0, 0.0]);
/// assert!((i - 1.0).abs() < 1e-15);
/// ```
pub fn moment_about_axis(points: &[(f64, [f64; 3])], point: [f64; 3], axis: [f64; 3]) -> f64 {
    let n = Vector3::from(axis);
    let norm = n.norm();
    if norm == 0.0 {
        return 0.0;
    }
    let n = n / norm;
    let p = Vector3::from(point);
    points
        .iter()
        .map(|&(m, r)| {
            let rho = Vector3::from(r) - p;
            m * (rho.norm_squared() - n.dot(&rho).powi(2))
        })
        .sum()
}

/// The inertia tensor about the origin from the one about the centre of mass (at `r_cm`, total
/// mass `m`): I_ij = M (R² δ_ij − R_i R_j) + I_ij^(cm), the corrected eq. 77 of the reference
/// text (the printed form lacks the δ_ij; see docs/ERRATA.md).
///
/// ```
/// use lagrange_runtime::rigid::shift_from_centre_of_mass;
/// use nalgebra::Matrix3;
/// // A point mass 2 at (0, 0, 3): about the origin it has 2·9 about x and y.
/// let i = shift_from_centre_of_mass(2.0, [0.0, 0.0, 3.0], &Matrix3::zeros());
/// assert_eq!((i[(0, 0)], i[(1, 1)], i[(2, 2)], i[(0, 2)]), (18.0, 18.0, 0.0, 0.0));
/// ```
pub fn shift_from_centre_of_mass(m: f64, r_cm: [f64; 3], i_cm: &Matrix3<f64>) -> Matrix3<f64> {
    let r = Vector3::from(r_cm);
    (Matrix3::identity() * r.norm_squared() - r * r.transpose()) * m + i_cm
}

/// The rotation matrix of z-x-z Euler angles, R = R_z(φ) R_x(θ) R_z(ψ): it maps body components
/// to lab components, so its columns are the body axes in the lab frame.
///
/// ```
/// use lagrange_runtime::rigid::rotation_zxz;
/// // θ tilts the body z axis away from the lab z axis, towards −y when φ = 0.
/// let r = rotation_zxz(0.0, 0.5, 0.0);
/// assert!((r[(2, 2)] - 0.5_f64.cos()).abs() < 1e-15 && (r[(1, 2)] + 0.5_f64.sin()).abs() < 1e-15);
/// ```
pub fn rotation_zxz(phi: f64, theta: f64, psi: f64) -> Matrix3<f64> {
    let rz = |a: f64| {
        let (s, c) = a.sin_cos();
        Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
    };
    let (s, c) = theta.sin_cos();
    let rx = Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c);
    rz(phi) * rx * rz(psi)
}

/// Body-frame angular velocity ϖ of the z-x-z Euler angles from their rates:
/// ϖ1 = φ̇ sin θ sin ψ + θ̇ cos ψ, ϖ2 = φ̇ sin θ cos ψ − θ̇ sin ψ, ϖ3 = φ̇ cos θ + ψ̇
/// (φ does not enter). Angles and rates are ordered (φ, θ, ψ).
///
/// ```
/// use lagrange_runtime::rigid::body_angular_velocity_zxz;
/// // Spinning about the body axis only: ϖ = (0, 0, ψ̇ + φ̇ cos θ).
/// let w = body_angular_velocity_zxz([0.0, 0.3, 0.2], [1.0, 0.0, 2.0]);
/// assert!((w[2] - (2.0 + 0.3_f64.cos())).abs() < 1e-15);
/// ```
pub fn body_angular_velocity_zxz(angles: [f64; 3], rates: [f64; 3]) -> [f64; 3] {
    let [_, theta, psi] = angles;
    let [phi_dot, theta_dot, psi_dot] = rates;
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = psi.sin_cos();
    [
        phi_dot * st * sp + theta_dot * cp,
        phi_dot * st * cp - theta_dot * sp,
        phi_dot * ct + psi_dot,
    ]
}

/// The z-x-z Euler-angle rates (φ̇, θ̇, ψ̇) giving the body angular velocity ϖ at angles
/// (φ, θ, ψ): the inverse of [`body_angular_velocity_zxz`]. Fails with
/// [`DynamicsError::SingularMassMatrix`] where the chart is singular (|sin θ| below `1e-12`).
///
/// ```
/// use lagrange_runtime::rigid::{body_angular_velocity_zxz, euler_rates_zxz};
/// let angles = [0.1, 1.0, -0.4];
/// let rates = euler_rates_zxz(angles, [0.3, -1.2, 2.0]).unwrap();
/// let w = body_angular_velocity_zxz(angles, rates);
/// assert!((w[0] - 0.3).abs() < 1e-14 && (w[1] + 1.2).abs() < 1e-14 && (w[2] - 2.0).abs() < 1e-14);
/// assert!(euler_rates_zxz([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]).is_err());
/// ```
pub fn euler_rates_zxz(angles: [f64; 3], w: [f64; 3]) -> Result<[f64; 3], DynamicsError> {
    let [_, theta, psi] = angles;
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = psi.sin_cos();
    if st.abs() < 1e-12 || !st.is_finite() {
        return Err(chart_error(0.0, &angles, &[], st, 1e-12));
    }
    let phi_dot = (w[0] * sp + w[1] * cp) / st;
    Ok([phi_dot, w[0] * cp - w[1] * sp, w[2] - phi_dot * ct])
}

fn chart_error(t: f64, q: &[f64], qdot: &[f64], sin_theta: f64, min: f64) -> DynamicsError {
    DynamicsError::SingularMassMatrix {
        t,
        q: q.to_vec(),
        qdot: qdot.to_vec(),
        message: format!(
            "the z-x-z Euler-angle chart is (nearly) singular here: sin θ = {:.3e} ≤ {min:.1e} \
             (θ is expected in (0, π)); at sin θ = 0, φ and ψ turn about the same axis and the mass matrix of the Euler angles loses rank (its \
             determinant ∝ sin²θ). The body is fine; the coordinates are not. Try: orient the lab \
             axes (or pick which body axis is the Euler z axis) so that this body axis never points \
             along the lab z axis during the run, e.g. for a free body put the lab z axis along the \
             angular momentum and choose as Euler z axis a body axis that does not align with it.",
            sin_theta
        ),
    }
}

/// A guard against the z-x-z chart's singularity: a terminal [`Event`] when sin θ falls to
/// `min_sin`, and [`EulerChartGuard::check`] that turns a run it stopped into
/// [`DynamicsError::SingularMassMatrix`] with the time, the state and what to do.
///
/// θ is taken in its usual range (0, π), where sin θ > 0 (an orientation with θ in (−π, 0) is the
/// same as (φ + π, −θ, ψ + π)). The event function sin θ − `min_sin` is smooth, so a run that
/// would pass straight through θ = 0 or π within one step is still caught.
///
/// ```
/// use lagrange_runtime::rigid::EulerChartGuard;
/// let guard = EulerChartGuard { theta_index: 1, min_sin: 1e-3 };
/// let event = guard.event::<3>();
/// assert!(event.is_terminal());
/// assert!(event.value(0.0, &[0.0, 0.5, 0.0], &[0.0; 3]) > 0.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EulerChartGuard {
    /// Index of θ among the coordinates.
    pub theta_index: usize,
    /// The sin θ at which the run is stopped.
    pub min_sin: f64,
}

impl EulerChartGuard {
    /// The name of the guard's event.
    ///
    /// ```
    /// assert_eq!(lagrange_runtime::rigid::EulerChartGuard::EVENT_NAME, "euler chart singularity");
    /// ```
    pub const EVENT_NAME: &'static str = "euler chart singularity";

    /// The terminal event sin θ − `min_sin` = 0 (falling), to add to a
    /// [`Simulation`](crate::Simulation). An out-of-range `theta_index` never fires.
    ///
    /// ```
    /// use lagrange_runtime::rigid::EulerChartGuard;
    /// let e = EulerChartGuard { theta_index: 0, min_sin: 0.01 }.event::<1>();
    /// assert!(e.value(0.0, &[0.0], &[0.0]) < 0.0);
    /// ```
    pub fn event<const N: usize>(self) -> Event<'static, N> {
        Event::zero_crossing(Self::EVENT_NAME, move |_t, q: &[f64; N], _v| {
            q.get(self.theta_index)
                .map_or(1.0, |th| th.sin() - self.min_sin)
        })
        .falling()
        .terminal()
    }

    /// `Err(SingularMassMatrix)` (time and state, with advice) if the guard's event stopped
    /// `traj` or it started with sin θ ≤ `min_sin`, else `Ok(())`.
    ///
    /// ```
    /// use lagrange_runtime::{Lagrangian, Scalar, Simulation, Method, rigid::EulerChartGuard};
    /// // θ̈ = 0 with θ(0) = 0.5, θ̇ = −1: the guard fires at sin θ = 0.1.
    /// struct Free;
    /// impl Lagrangian<1> for Free {
    ///     const COORDINATES: [&'static str; 1] = ["theta"];
    ///     const CYCLIC: [bool; 1] = [true];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
    /// }
    /// let guard = EulerChartGuard { theta_index: 0, min_sin: 0.1 };
    /// let traj = Simulation::new(&Free, [0.5], [-1.0]).method(Method::Dop853 { rtol: 1e-10, atol: 1e-12 })
    ///     .until(2.0).event(guard.event()).run().unwrap();
    /// let err = guard.check(&traj).unwrap_err();
    /// assert!((err.t() - (0.5 - 0.1_f64.asin())).abs() < 1e-9);
    /// ```
    pub fn check<const N: usize>(&self, traj: &Trajectory<N>) -> Result<(), DynamicsError> {
        if let (Some(t), Some(q), Some(v)) = (traj.t.first(), traj.q.first(), traj.qdot.first()) {
            let s = q.get(self.theta_index).map_or(1.0, |th| th.sin());
            if s <= self.min_sin {
                return Err(chart_error(*t, q, v, s, self.min_sin));
            }
        }
        if traj.terminated_by.as_deref() != Some(Self::EVENT_NAME) {
            return Ok(());
        }
        match traj
            .events
            .iter()
            .rev()
            .find(|e| e.name == Self::EVENT_NAME)
        {
            Some(hit) => {
                let s = hit.q.get(self.theta_index).map_or(0.0, |th| th.sin());
                Err(chart_error(hit.t, &hit.q, &hit.qdot, s, self.min_sin))
            }
            None => {
                let (t, q, v) = match (traj.t.last(), traj.q.last(), traj.qdot.last()) {
                    (Some(t), Some(q), Some(v)) => (*t, q.to_vec(), v.to_vec()),
                    _ => (f64::NAN, Vec::new(), Vec::new()),
                };
                Err(chart_error(t, &q, &v, 0.0, self.min_sin))
            }
        }
    }
}
