//! Unilateral contacts g(q, t) ≥ 0 with a restitution law: the [`Unilateral`] trait, the
//! [`Contact`] a system declares for each gap, and the contact rows from the jets.
//!
//! A contact is open while its gap g is positive; where g reaches zero with ġ < 0 the bodies
//! collide, and the impact map (derived from M and the gradients, see
//! [`impact`](crate::impact)) gives the velocities after it: M Δq̇ = Gᵀ Λ with Newton's law
//! ġ⁺ = −e ġ⁻ on the rows that take an impulse. A contact that comes to rest (e = 0, or a Zeno
//! accumulation of bounces) is closed: it acts as a holonomic constraint g = 0 with a
//! multiplier λ ≥ 0, until λ reaches zero (lift-off). A sticking contact also holds the rate of
//! a tangential coordinate s(q, t) of the contact point at zero while closed (a pivot: no
//! friction limit). [`Simulation::contacts`](crate::Simulation::contacts) runs such a system.
//!
//! ```
//! use lagrange_runtime::{Contact, Lagrangian, Scalar, Unilateral};
//! /// A ball above a floor at y = 0, restitution 0.8.
//! struct Ball;
//! impl Lagrangian<2> for Ball {
//!     const COORDINATES: [&'static str; 2] = ["x", "y"];
//!     const CYCLIC: [bool; 2] = [true, false];
//!     const AUTONOMOUS: bool = true;
//!     fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
//!         (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[1] * 9.81
//!     }
//! }
//! impl Unilateral<2, 1> for Ball {
//!     fn contacts<S: Scalar>(&self, q: &[S; 2], _t: S) -> [Contact<S>; 1] {
//!         [Contact::gap(q[1]).restitution(0.8).named("floor")]
//!     }
//! }
//! let rows = Ball.contact_rows(&[0.0, 0.5], &[1.0, -2.0], 0.0);
//! assert_eq!((rows.gap[0], rows.normal[0], rows.normal_rate[0]), (0.5, [0.0, 1.0], -2.0));
//! assert_eq!((rows.restitution[0], rows.names[0], rows.sticking[0]), (0.8, "floor", false));
//! ```

use crate::eom::ConstraintRows;
use crate::jet::ConstraintJet;
use crate::lagrangian::Lagrangian;
use crate::scalar::Scalar;

/// One unilateral contact: its gap g(q, t) ≥ 0, its restitution coefficient, and optionally a
/// tangential coordinate s(q, t) of the contact point held still while the contact is closed
/// (a sticking contact).
///
/// ```
/// use lagrange_runtime::Contact;
/// let c = Contact::gap(0.25).restitution(0.5).sticking(1.0).named("corner");
/// assert_eq!((c.gap_value(), c.restitution_coefficient(), c.tangent(), c.name()), (0.25, 0.5, Some(1.0), Some("corner")));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact<S> {
    gap: S,
    tangent: Option<S>,
    restitution: f64,
    name: Option<&'static str>,
}

impl<S: Copy> Contact<S> {
    /// A frictionless, perfectly plastic (e = 0) contact with gap g: open while g > 0.
    ///
    /// ```
    /// use lagrange_runtime::Contact;
    /// assert_eq!(Contact::gap(2.0).restitution_coefficient(), 0.0);
    /// ```
    pub fn gap(g: S) -> Self {
        Contact {
            gap: g,
            tangent: None,
            restitution: 0.0,
            name: None,
        }
    }

    /// Newton's coefficient of restitution e ∈ [0, 1]: ġ⁺ = −e ġ⁻ at an impact.
    ///
    /// ```
    /// use lagrange_runtime::Contact;
    /// assert_eq!(Contact::gap(2.0).restitution(0.8).restitution_coefficient(), 0.8);
    /// ```
    pub fn restitution(mut self, e: f64) -> Self {
        self.restitution = e;
        self
    }

    /// Makes the contact sticking: `s` is a tangential coordinate of the contact point (its
    /// position along the surface); an impact also stops ṡ, and while the contact is closed ṡ
    /// stays zero (the point pivots, no friction limit).
    ///
    /// ```
    /// use lagrange_runtime::Contact;
    /// assert_eq!(Contact::gap(0.0).sticking(3.0).tangent(), Some(3.0));
    /// ```
    pub fn sticking(mut self, s: S) -> Self {
        self.tangent = Some(s);
        self
    }

    /// Names the contact (the run's event for it carries the name; else `contact j`).
    ///
    /// ```
    /// use lagrange_runtime::Contact;
    /// assert_eq!(Contact::gap(0.0).named("floor").name(), Some("floor"));
    /// ```
    pub fn named(mut self, name: &'static str) -> Self {
        self.name = Some(name);
        self
    }

    /// The gap g.
    ///
    /// ```
    /// use lagrange_runtime::Contact;
    /// assert_eq!(Contact::gap(2.0).gap_value(), 2.0);
    /// ```
    pub fn gap_value(&self) -> S {
        self.gap
    }

    /// The tangential coordinate of a sticking contact.
    ///
    /// ```
    /// use lagrange_runtime::Contact;
    /// assert_eq!(Contact::gap(2.0).tangent(), None);
    /// ```
    pub fn tangent(&self) -> Option<S> {
        self.tangent
    }

    /// The restitution coefficient e.
    ///
    /// ```
    /// use lagrange_runtime::Contact;
    /// assert_eq!(Contact::gap(1.0).restitution(0.3).restitution_coefficient(), 0.3);
    /// ```
    pub fn restitution_coefficient(&self) -> f64 {
        self.restitution
    }

    /// The name given by [`named`](Contact::named).
    ///
    /// ```
    /// use lagrange_runtime::Contact;
    /// assert_eq!(Contact::gap(1.0).name(), None);
    /// ```
    pub fn name(&self) -> Option<&'static str> {
        self.name
    }
}

/// The rows of a system's `K` contacts at (q, q̇, t): each gap with its gradient, its rate and
/// its curvature along the motion, and the same of the tangential coordinate of a sticking one.
///
/// ```
/// use lagrange_runtime::contact::ContactRows;
/// let rows = ContactRows::<2, 1>::default();
/// assert_eq!(rows.gap, [0.0]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactRows<const N: usize, const K: usize> {
    /// g(q, t).
    pub gap: [f64; K],
    /// ∂g/∂q.
    pub normal: [[f64; N]; K],
    /// ġ = (∂g/∂q) q̇ + ∂g/∂t.
    pub normal_rate: [f64; K],
    /// g̈ at q̈ = 0.
    pub normal_curvature: [f64; K],
    /// Whether the contact is sticking (has a tangential row).
    pub sticking: [bool; K],
    /// ∂s/∂q of a sticking contact (zero otherwise).
    pub tangent: [[f64; N]; K],
    /// ṡ.
    pub tangent_rate: [f64; K],
    /// s̈ at q̈ = 0.
    pub tangent_curvature: [f64; K],
    /// The restitution coefficients.
    pub restitution: [f64; K],
    /// The contacts' names.
    pub names: [&'static str; K],
}

impl<const N: usize, const K: usize> Default for ContactRows<N, K> {
    fn default() -> Self {
        ContactRows {
            gap: [0.0; K],
            normal: [[0.0; N]; K],
            normal_rate: [0.0; K],
            normal_curvature: [0.0; K],
            sticking: [false; K],
            tangent: [[0.0; N]; K],
            tangent_rate: [0.0; K],
            tangent_curvature: [0.0; K],
            restitution: [0.0; K],
            names: [""; K],
        }
    }
}

/// A [`Lagrangian`] system with `K` unilateral contacts g(q, t) ≥ 0 (see the
/// [module documentation](crate::contact)). Implement [`contacts`](Unilateral::contacts)
/// generically over [`Scalar`], or write `fn contacts` in a `#[lagrangian]` impl.
pub trait Unilateral<const N: usize, const K: usize>: Lagrangian<N> {
    /// `true` when no contact depends on time (then closed contacts do no work). The default,
    /// `false`, is always correct.
    const SCLERONOMIC: bool = false;

    /// The contacts at (q, t).
    fn contacts<S: Scalar>(&self, q: &[S; N], t: S) -> [Contact<S>; K];

    /// The equality constraints that hold throughout a run of this system alongside its
    /// contacts: its holonomic rows g(q, t) = 0, then its velocity rows A q̇ + b = 0, at
    /// (q, q̇, t). None by default; `#[lagrangian]` writes it for a system with `fn contacts`
    /// and `fn constraints` or `fn velocity_constraints`, and a hand-written impl of both
    /// traits writes the one line below. A contacts run then keeps them at every step, in the
    /// accelerations, at every impact (the impulse has their rows in it: M Δq̇ = Gᵀ Λ + Aᵀ μ,
    /// the constraints holding after the jump) and in the projection.
    ///
    /// ```
    /// use lagrange_runtime::contact::EqualityRows;
    /// use lagrange_runtime::{Contact, Holonomic, Lagrangian, Scalar, Unilateral};
    /// /// A pendulum in x, y (its rod a constraint) that may strike a wall at x = −0.5.
    /// struct Pendulum;
    /// impl Lagrangian<2> for Pendulum {
    ///     const COORDINATES: [&'static str; 2] = ["x", "y"];
    ///     const CYCLIC: [bool; 2] = [true, false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
    ///         (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[1] * 9.81
    ///     }
    /// }
    /// impl Holonomic<2, 1> for Pendulum {
    ///     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] { [q[0] * q[0] + q[1] * q[1] - 1.0] }
    /// }
    /// impl Unilateral<2, 1> for Pendulum {
    ///     fn contacts<S: Scalar>(&self, q: &[S; 2], _t: S) -> [Contact<S>; 1] { [Contact::gap(q[0] + 0.5)] }
    ///     fn equality_rows(&self, q: &[f64; 2], qdot: &[f64; 2], t: f64) -> EqualityRows<2> {
    ///         EqualityRows::of(&self.constraint_rows(q, qdot, t), 0)
    ///     }
    /// }
    /// let rows = Pendulum.equality_rows(&[0.0, -1.0], &[1.0, 0.0], 0.0);
    /// assert_eq!((rows.len(), rows.jacobian[0], rows.curvature[0]), (1, [0.0, -2.0], 2.0));
    /// ```
    fn equality_rows(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> EqualityRows<N> {
        let _ = (q, qdot, t);
        EqualityRows::default()
    }

    /// The contact rows at (q, q̇, t), from one evaluation of
    /// [`contacts`](Unilateral::contacts) in the [`ConstraintJet`].
    ///
    /// ```
    /// use lagrange_runtime::{Contact, Lagrangian, Scalar, Unilateral};
    /// /// A disc of radius 1 rolling on y = 0 through the contact point's tangent x − θ.
    /// struct Disc;
    /// impl Lagrangian<3> for Disc {
    ///     const COORDINATES: [&'static str; 3] = ["x", "y", "theta"];
    ///     const CYCLIC: [bool; 3] = [true, false, true];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 3], v: &[S; 3], _t: S) -> S {
    ///         (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * 0.5 - q[1]
    ///     }
    /// }
    /// impl Unilateral<3, 1> for Disc {
    ///     fn contacts<S: Scalar>(&self, q: &[S; 3], _t: S) -> [Contact<S>; 1] {
    ///         [Contact::gap(q[1] - 1.0).sticking(q[0] + q[2])]
    ///     }
    /// }
    /// let rows = Disc.contact_rows(&[0.0, 1.0, 0.0], &[2.0, 0.0, -2.0], 0.0);
    /// assert_eq!((rows.sticking[0], rows.tangent[0], rows.tangent_rate[0]), (true, [1.0, 0.0, 1.0], 0.0));
    /// ```
    fn contact_rows(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> ContactRows<N, K> {
        let (qj, tj) = ConstraintJet::seed(q, qdot, t);
        let c = self.contacts(&qj, tj);
        let mut rows = ContactRows::default();
        for (j, c) in c.iter().enumerate() {
            rows.gap[j] = c.gap.value();
            rows.normal[j] = c.gap.grad_q();
            rows.normal_rate[j] = c.gap.rate();
            rows.normal_curvature[j] = c.gap.curvature();
            rows.restitution[j] = c.restitution;
            rows.names[j] = c.name.unwrap_or("");
            if let Some(s) = c.tangent {
                rows.sticking[j] = true;
                rows.tangent[j] = s.grad_q();
                rows.tangent_rate[j] = s.rate();
                rows.tangent_curvature[j] = s.curvature();
            }
        }
        rows
    }
}

/// The equality constraints of a system with contacts ([`Unilateral::equality_rows`]): each
/// row's value g (0 for a velocity row), gradient (∂g/∂q, or A for a velocity row), rate
/// (ġ, or A q̇ + b) and curvature (its second derivative along the motion at q̈ = 0), the
/// holonomic rows first and the last [`velocity_rows`](EqualityRows::velocity_rows) of them
/// velocity constraints.
///
/// ```
/// use lagrange_runtime::contact::EqualityRows;
/// use lagrange_runtime::eom::ConstraintRows;
/// let rows = ConstraintRows { value: [0.5, 0.0], jacobian: [[1.0], [2.0]], rate: [3.0, 4.0], curvature: [5.0, 6.0] };
/// let eq = EqualityRows::of(&rows, 1);
/// assert_eq!((eq.len(), eq.velocity_rows, eq.value[0], eq.rate[1]), (2, 1, 0.5, 4.0));
/// assert!(EqualityRows::<1>::default().is_empty());
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EqualityRows<const N: usize> {
    /// g(q, t) per row (0 for the velocity rows).
    pub value: Vec<f64>,
    /// ∂g/∂q (A for a velocity row).
    pub jacobian: Vec<[f64; N]>,
    /// ġ (A q̇ + b for a velocity row).
    pub rate: Vec<f64>,
    /// The row's second derivative (first, for a velocity row) along the motion at q̈ = 0.
    pub curvature: Vec<f64>,
    /// How many of the rows, the last ones, are velocity constraints.
    pub velocity_rows: usize,
}

impl<const N: usize> EqualityRows<N> {
    /// The rows of a [`Holonomic`](crate::Holonomic) system's
    /// [`constraint_rows`](crate::Holonomic::constraint_rows), the last `velocity_rows` of them
    /// velocity constraints.
    ///
    /// ```
    /// use lagrange_runtime::contact::EqualityRows;
    /// use lagrange_runtime::eom::ConstraintRows;
    /// let rows = ConstraintRows { value: [0.5], jacobian: [[1.0, 0.0]], rate: [3.0], curvature: [5.0] };
    /// assert_eq!(EqualityRows::of(&rows, 0).jacobian, vec![[1.0, 0.0]]);
    /// ```
    pub fn of<const K: usize>(rows: &ConstraintRows<N, K>, velocity_rows: usize) -> Self {
        EqualityRows {
            value: rows.value.to_vec(),
            jacobian: rows.jacobian.to_vec(),
            rate: rows.rate.to_vec(),
            curvature: rows.curvature.to_vec(),
            velocity_rows: velocity_rows.min(K),
        }
    }

    /// The number of rows.
    ///
    /// ```
    /// # use lagrange_runtime::contact::EqualityRows;
    /// assert_eq!(EqualityRows::<3>::default().len(), 0);
    /// ```
    pub fn len(&self) -> usize {
        self.value.len()
    }

    /// Whether there are no rows.
    ///
    /// ```
    /// # use lagrange_runtime::contact::EqualityRows;
    /// assert!(EqualityRows::<3>::default().is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.value.is_empty()
    }
}
