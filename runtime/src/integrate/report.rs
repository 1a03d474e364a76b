//! How a run's summaries print: `Display` for [`Stats`], [`Drift`], [`Invariants`] (also with the
//! coordinates' names, [`Invariants::named`]) and [`ConstraintResidual`], one readable line or
//! block each, for people (`Debug` stays the fields).

use core::fmt;

use super::state::Stats;
use super::trajectory::{ConstraintResidual, Drift, Invariants};

impl fmt::Display for Stats {
    /// `412 steps (3 rejected), 4955 evaluations`, with the rejections by Newton, the Newton
    /// iterations, Jacobians and LU decompositions where there were any.
    ///
    /// ```
    /// let s = lagrange_runtime::Stats { steps: 412, rejected: 3, rhs_evals: 4955, ..Default::default() };
    /// assert_eq!(s.to_string(), "412 steps (3 rejected), 4955 evaluations");
    /// let r = lagrange_runtime::Stats { newton_iterations: 900, jacobians: 12, decompositions: 40, ..s };
    /// assert_eq!(r.to_string(), "412 steps (3 rejected), 4955 evaluations, 900 Newton iterations, 12 Jacobians, 40 LU decompositions");
    /// let n = lagrange_runtime::Stats { newton_failures: 2, ..r };
    /// assert!(n.to_string().starts_with("412 steps (3 rejected, 2 by Newton), 4955"));
    /// ```
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} steps ({} rejected", self.steps, self.rejected)?;
        if self.newton_failures > 0 {
            write!(f, ", {} by Newton", self.newton_failures)?;
        }
        write!(f, "), {} evaluations", self.rhs_evals)?;
        if self.newton_iterations > 0 {
            write!(f, ", {} Newton iterations", self.newton_iterations)?;
        }
        if self.jacobians > 0 || self.decompositions > 0 {
            write!(
                f,
                ", {} Jacobians, {} LU decompositions",
                self.jacobians, self.decompositions
            )?;
        }
        Ok(())
    }
}

impl fmt::Display for Drift {
    /// `6.31e-13 relative (1.26e-13 absolute, from 0.2)`.
    ///
    /// ```
    /// use lagrange_runtime::Drift;
    /// let d = Drift { initial: 0.2, max_abs: 1.26e-13, max_rel: 6.3e-13 };
    /// assert_eq!(d.to_string(), "6.30e-13 relative (1.26e-13 absolute, from 0.2)");
    /// ```
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:.2e} relative ({:.2e} absolute, from {})",
            self.max_rel, self.max_abs, self.initial
        )
    }
}

impl fmt::Display for ConstraintResidual {
    /// `|g| ≤ 1.0e-16, |ġ| ≤ 2.0e-16, largest projection 1.0e-11`.
    ///
    /// ```
    /// use lagrange_runtime::ConstraintResidual;
    /// let r = ConstraintResidual { position: 1e-16, velocity: 2e-16, projection: 1e-11 };
    /// assert_eq!(r.to_string(), "|g| ≤ 1.0e-16, |ġ| ≤ 2.0e-16, largest projection 1.0e-11");
    /// ```
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "|g| ≤ {:.1e}, |ġ| ≤ {:.1e}, largest projection {:.1e}",
            self.position, self.velocity, self.projection
        )
    }
}

/// [`Invariants`] with the coordinates' names (from [`Invariants::named`]).
#[derive(Clone, Copy, Debug)]
pub struct NamedInvariants<'a, const N: usize> {
    invariants: &'a Invariants<N>,
    names: Option<&'a [&'a str; N]>,
}

impl<const N: usize> Invariants<N> {
    /// The drifts printed with each momentum under its coordinate's name (`p_phi`), e.g. with
    /// [`Trajectory::coordinates`](crate::Trajectory::coordinates).
    ///
    /// ```
    /// use lagrange_runtime::{Drift, Invariants};
    /// let d = Drift { initial: 1.0, max_abs: 1e-12, max_rel: 1e-12 };
    /// let inv = Invariants::<2> { energy: Some(d), momenta: [None, Some(d)], energy_balance: None, constraints: None };
    /// let text = inv.named(&["theta", "phi"]).to_string();
    /// assert_eq!(text, "energy: 1.00e-12 relative (1.00e-12 absolute, from 1)\np_phi: 1.00e-12 relative (1.00e-12 absolute, from 1)");
    /// ```
    pub fn named<'a>(&'a self, names: &'a [&'a str; N]) -> NamedInvariants<'a, N> {
        NamedInvariants {
            invariants: self,
            names: Some(names),
        }
    }
}

impl<const N: usize> fmt::Display for NamedInvariants<'_, N> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let inv = self.invariants;
        let mut lines: Vec<String> = Vec::new();
        if let Some(d) = &inv.energy {
            lines.push(format!("energy: {d}"));
        }
        for (i, m) in inv.momenta.iter().enumerate() {
            if let Some(d) = m {
                let name = match self.names {
                    Some(names) => format!("p_{}", names[i]),
                    None => format!("p[{i}]"),
                };
                lines.push(format!("{name}: {d}"));
            }
        }
        if let Some(d) = &inv.energy_balance {
            lines.push(format!("energy balance h − h₀ − W: {d}"));
        }
        if let Some(c) = &inv.constraints {
            lines.push(format!("constraints: {c}"));
        }
        if lines.is_empty() {
            return f.write_str("no conserved quantity to check");
        }
        f.write_str(&lines.join("\n"))
    }
}

impl<const N: usize> fmt::Display for Invariants<N> {
    /// One line per conserved quantity (a momentum by its index, `p[2]`; with names:
    /// [`Invariants::named`]).
    ///
    /// ```
    /// use lagrange_runtime::{Drift, Invariants};
    /// let d = Drift { initial: 2.0, max_abs: 2e-9, max_rel: 1e-9 };
    /// let inv = Invariants::<1> { energy: None, momenta: [None], energy_balance: Some(d), constraints: None };
    /// assert_eq!(inv.to_string(), "energy balance h − h₀ − W: 1.00e-9 relative (2.00e-9 absolute, from 2)");
    /// ```
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        NamedInvariants {
            invariants: self,
            names: None,
        }
        .fmt(f)
    }
}
