//! Typed errors of the dynamics: what happened, where (t, q, q̇), and what to try.

use core::fmt;

/// The result of evaluating the dynamics: a value, or the [`DynamicsError`] that stopped it.
///
/// ```
/// use lagrange_runtime::{DynamicsError, DynamicsResult};
/// let e = DynamicsError::NonFinite { t: 0.5, q: vec![0.0], qdot: vec![f64::NAN], message: "q̇ is NaN".into() };
/// let r: DynamicsResult<[f64; 1]> = Err(e);
/// assert_eq!(r.map_err(|e| e.to_string().contains("t = 0.5")), Err(true));
/// ```
pub type DynamicsResult<T> = Result<T, DynamicsError>;

/// Why the equations of motion could not be solved at a state.
///
/// Every variant carries the time and the state at which it happened, and its message says what
/// to try.
///
/// ```
/// use lagrange_runtime::DynamicsError;
/// let e = DynamicsError::NonFinite { t: 1.0, q: vec![0.0], qdot: vec![f64::NAN], message: "q̇ is NaN".into() };
/// assert!(e.to_string().contains("t = 1"));
/// ```
#[derive(Clone, PartialEq)]
#[non_exhaustive]
pub enum DynamicsError {
    /// The mass matrix ∂²L/∂q̇∂q̇ is singular (or numerically so) at this state.
    SingularMassMatrix {
        /// Time.
        t: f64,
        /// Coordinates.
        q: Vec<f64>,
        /// Velocities.
        qdot: Vec<f64>,
        /// What was found, the likely cause, and what to try.
        message: String,
    },
    /// The state, the Lagrangian's derivatives or the accelerations are not finite.
    NonFinite {
        /// Time.
        t: f64,
        /// Coordinates.
        q: Vec<f64>,
        /// Velocities.
        qdot: Vec<f64>,
        /// What was not finite and what to try.
        message: String,
    },
    /// The holonomic constraints are dependent (their Jacobian G = ∂g/∂q has dependent rows) at
    /// this state: one of them says nothing the others do not, so the multipliers are not
    /// determined.
    DependentConstraints {
        /// Time.
        t: f64,
        /// Coordinates.
        q: Vec<f64>,
        /// Velocities.
        qdot: Vec<f64>,
        /// Which constraints, and what to try.
        message: String,
    },
    /// An impact of unilateral contacts has no solution at this state (see
    /// [`impact`](crate::impact)), or its outcome could not be put on the closed contacts.
    Impact {
        /// Time.
        t: f64,
        /// Coordinates.
        q: Vec<f64>,
        /// Velocities before the impact.
        qdot: Vec<f64>,
        /// Which contacts, and what to try.
        message: String,
    },
    /// `linearize` was asked of a system with holonomic constraints declared by
    /// `#[lagrangian]`: the linearization of the unconstrained L would describe motions the
    /// constraints forbid (spurious modes), so it is refused.
    Constrained {
        /// Time.
        t: f64,
        /// Coordinates.
        q: Vec<f64>,
        /// Velocities.
        qdot: Vec<f64>,
        /// What to do instead.
        message: String,
    },
}

impl DynamicsError {
    /// The time at which the error happened.
    ///
    /// ```
    /// use lagrange_runtime::DynamicsError;
    /// let e = DynamicsError::NonFinite { t: 2.0, q: vec![], qdot: vec![], message: String::new() };
    /// assert_eq!(e.t(), 2.0);
    /// ```
    pub fn t(&self) -> f64 {
        match self {
            DynamicsError::SingularMassMatrix { t, .. }
            | DynamicsError::NonFinite { t, .. }
            | DynamicsError::DependentConstraints { t, .. }
            | DynamicsError::Impact { t, .. }
            | DynamicsError::Constrained { t, .. } => *t,
        }
    }
}

impl fmt::Display for DynamicsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (kind, t, q, qdot, message) = match self {
            DynamicsError::SingularMassMatrix {
                t,
                q,
                qdot,
                message,
            } => ("singular mass matrix", t, q, qdot, message),
            DynamicsError::NonFinite {
                t,
                q,
                qdot,
                message,
            } => ("non-finite dynamics", t, q, qdot, message),
            DynamicsError::DependentConstraints {
                t,
                q,
                qdot,
                message,
            } => ("dependent constraints", t, q, qdot, message),
            DynamicsError::Constrained {
                t,
                q,
                qdot,
                message,
            } => ("a constrained system", t, q, qdot, message),
            DynamicsError::Impact {
                t,
                q,
                qdot,
                message,
            } => ("an impact without a solution", t, q, qdot, message),
        };
        write!(
            f,
            "{kind} at t = {t}, q = {q}, q̇ = {qdot}: {message}",
            t = Short(*t),
            q = Short(&q[..]),
            qdot = Short(&qdot[..])
        )
    }
}

impl std::error::Error for DynamicsError {}

/// A number, or a list of numbers, printed for people: 12 significant digits, then the shortest
/// form (`0.009`, not `0.009000000000000001`).
///
/// ```
/// use lagrange_runtime::error::Short;
/// assert_eq!(Short(0.001 * 9.0).to_string(), "0.009");
/// assert_eq!(Short(&[1.0, 1e-20 + 1e-36][..]).to_string(), "[1, 1e-20]");
/// ```
pub struct Short<T>(pub T);

impl fmt::Display for Short<f64> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        if !x.is_finite() || x == 0.0 {
            return write!(f, "{x}");
        }
        let rounded: f64 = format!("{x:.11e}").parse().unwrap_or(x);
        let a = rounded.abs();
        if (1e-5..1e15).contains(&a) {
            write!(f, "{rounded}")
        } else {
            write!(f, "{rounded:e}")
        }
    }
}

impl fmt::Display for Short<&[f64]> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[")?;
        for (i, x) in self.0.iter().enumerate() {
            if i > 0 {
                write!(f, ", ")?;
            }
            write!(f, "{}", Short(*x))?;
        }
        write!(f, "]")
    }
}

impl core::fmt::Debug for DynamicsError {
    /// The sentence of `Display` (what happened, where, what to try), without the escapes a
    /// derived `Debug` puts on every combining dot of q̇: what `fn main() -> Result<..>` prints.
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        core::fmt::Display::fmt(self, f)
    }
}
