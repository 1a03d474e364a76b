//! The one factory of the explicit methods: the stepper of any explicit [`Method`] over any
//! [`Problem`] (a plain run, a sensitivity run).

use super::dop853::Dop853;
use super::dopri5::Dopri5;
use super::explicit::ExplicitRk;
use super::method::Method;
use super::problem::Problem;
use super::rk4::Rk4;
use super::state::{Fault, Stats};
use super::stepper::Stepper;

/// The explicit tableaux a [`Method`] names.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Tab {
    Rk4,
    Dopri5,
    Dop853,
}

/// An explicit method as the factory takes it: its tableau, tolerances (adaptive) and step
/// (fixed).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Explicit {
    tab: Tab,
    tol: (f64, f64),
    dt: f64,
}

impl Explicit {
    /// The explicit method `method` names, if it is one.
    pub(crate) fn of(method: Method) -> Option<Self> {
        let (tab, tol, dt) = match method {
            Method::Rk4 { dt } => (Tab::Rk4, (0.0, 0.0), dt),
            Method::DormandPrince { rtol, atol } => (Tab::Dopri5, (rtol, atol), 0.0),
            Method::Dop853 { rtol, atol } => (Tab::Dop853, (rtol, atol), 0.0),
            _ => return None,
        };
        Some(Explicit { tab, tol, dt })
    }

    /// The stepper of this method over the problem `p` from (t, x), up to `until`: the one
    /// factory of the explicit methods, for plain runs and sensitivity runs alike (a new
    /// explicit method is a tableau file and one line here).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn stepper<'s, P: Problem<N> + 's, const N: usize>(
        self,
        p: P,
        t: f64,
        x: P::State,
        until: f64,
        hmax: f64,
        stats: &mut Stats,
    ) -> Result<Box<dyn Stepper<N> + 's>, Fault> {
        let (tol, dt) = (self.tol, self.dt);
        Ok(match self.tab {
            Tab::Rk4 => Box::new(ExplicitRk::<P, Rk4, N>::new(
                p, t, x, tol, dt, until, hmax, stats,
            )?),
            Tab::Dopri5 => Box::new(ExplicitRk::<P, Dopri5, N>::new(
                p, t, x, tol, dt, until, hmax, stats,
            )?),
            Tab::Dop853 => Box::new(ExplicitRk::<P, Dop853, N>::new(
                p, t, x, tol, dt, until, hmax, stats,
            )?),
        })
    }
}
