//! The Taylor method over SIMD lanes: W members of an ensemble have their Taylor series computed
//! together, one member per lane of [`Lanes`] (the system's generated
//! [`Lagrangian::series_in`]: the recurrences of every node, order by order, as one pass
//! of vector code); each member then takes its own step from its series with its own scalar
//! [`Taylor`] stepper and driver (the Jorba–Zou step size, the sum, samples, events, dense output,
//! errors). Taylor steps are never rejected, so a lane's step is the scalar run's step whenever its
//! series is (bit for bit where the lanes compute the scalar operations), and a member that ends
//! frees its lane for the next member at once.
//!
//! A lane the lanes code leaves out (its M₀ has no LDLᵀ: indefinite or singular) or whose series
//! is not finite computes its series with the scalar code, which pivots or reports exactly what a
//! single run would; so does every lane of a system without lanes code.

use crate::error::DynamicsError;
use crate::lagrangian::Lagrangian;
use crate::lanes::{Lanes, Mask};
use crate::taylor::SeriesBuf;

use crate::integrate::method::Method;
use crate::integrate::simulation::Simulation;
use crate::integrate::state::{Fault, Y, YOf};
use crate::integrate::stepper::Stepper;
use crate::integrate::taylor::Taylor;

use super::members::{enter, fill, lanes_of, retire, End, Out, Slot};

/// A Taylor member in a lane (nothing kept besides its run).
type TaylorSlot<'p, 'a, L, const N: usize> = Slot<'p, 'a, Taylor<'p, L, N>, (), N>;

/// Whether the run goes on (`Ok(true)`: it needs the series at its node), has reached its end
/// (`Ok(false)`) or has used up its step budget.
fn pending<L: Lagrangian<N>, const N: usize>(
    s: &mut TaylorSlot<'_, '_, L, N>,
) -> Result<bool, Fault> {
    let r = &s.run;
    if r.stepper.t() >= r.opts.until {
        return Ok(false);
    }
    r.driver.check_budget(&r.opts)?;
    Ok(true)
}

/// One step from the series at the node (taken from the lanes, or computed here), then what
/// follows it; `Ok(true)` when a terminal event ended the run.
fn step<L: Lagrangian<N>, const N: usize>(s: &mut TaylorSlot<'_, '_, L, N>) -> Result<bool, Fault> {
    let r = &mut s.run;
    let until = r.opts.until;
    r.stepper.advance(until, r.driver.stats())?;
    r.driver
        .after_step(&mut r.stepper, &r.opts, &mut r.progress)
}

/// Runs the Taylor members of `queue` with W per vector, calling `out(position, result)` as
/// each ends; other members (another method, constraints) run the scalar driver.
#[inline(always)]
pub(super) fn run<
    'p,
    'a: 'p,
    L: Lagrangian<N> + 'a,
    const N: usize,
    const W: usize,
    const F: bool,
>(
    queue: impl Iterator<Item = (usize, &'p mut Simulation<'a, L, N>)>,
    out: &mut Out<'_, N>,
) {
    let mut queue = queue;
    let mut slots: [Option<TaylorSlot<'p, 'a, L, N>>; W] = core::array::from_fn(|_| None);
    let mut params: Vec<Lanes<W, F>> = Vec::new();
    let mut series: Vec<YOf<Lanes<W, F>, N>> = Vec::new();
    let mut buf = SeriesBuf::<Lanes<W, F>>::new();
    loop {
        let refreshed = fill(&mut slots, &mut queue, out, start, pending);
        let Some(lane) = lanes_of(&slots) else {
            return;
        };
        if refreshed {
            params.clear();
        }
        let members: [&L; W] = core::array::from_fn(|l| lane[l].run.stepper.sys());
        let orders = lane.map(|s| s.run.stepper.order());
        let (order, min_order) = orders
            .iter()
            .fold((0, usize::MAX), |(hi, lo), &p| (hi.max(p), lo.min(p)));
        series.resize(order + 1, [[Lanes::ZERO; N]; 2]);
        let mut t = Lanes::ZERO;
        for (l, s) in lane.iter().enumerate() {
            let (tl, yl) = s.run.stepper.node_state();
            t.0[l] = tl;
            for c in 0..2 {
                for i in 0..N {
                    series[0][c][i].0[l] = yl[c][i];
                }
            }
        }
        let done =
            lane_series::<L, N, W, F>(&members, &mut params, t, &mut series, &mut buf)
                .and_then(Result::ok);
        // 0 · x is 0 for finite x and NaN otherwise: a lane's sum is 0 only where its series
        // is finite (the orders past the lowest member's apart: a member does not read them).
        let mut finite = [Lanes::<W, F>::ZERO; 2];
        for (k, row) in series.iter().enumerate().skip(1) {
            for x in row.iter().flatten() {
                finite[usize::from(k > min_order)] += *x * 0.0;
            }
        }
        // Each lane whose series the vector code gave, at the order every busy lane has, plans its
        // step from the largest |coefficient| of orders 0, p − 1 and p (its own scalar step
        // size); the sums at those steps are then one pass of vector code (`taylor::horner`, the
        // scalar sum's body in every lane). The others take their series and step
        // on their own.
        let p = min_order;
        // Whether lane l's series is the vector code's and finite to its member's order.
        let given = |l: usize| {
            finite[0].0[l] == 0.0
                && (orders[l] == min_order || finite[1].0[l] == 0.0)
                && done.is_some_and(|m| m.0[l])
        };
        let mut plans: [Option<(f64, f64)>; W] = [None; W];
        let mut tau = Lanes::<W, F>::ZERO;
        for l in 0..W {
            let Some(s) = slots[l].as_ref() else { continue };
            if !(given(l) && order == p) {
                continue;
            }
            let norm = |k: usize| {
                series[k]
                    .iter()
                    .flatten()
                    .fold(0.0_f64, |m, x| m.max(x.0[l].abs()))
            };
            let stepper = &s.run.stepper;
            plans[l] = stepper.plan_from_norms([norm(0), norm(p - 1), norm(p)], s.run.opts.until);
            if let Some((h, _)) = plans[l] {
                tau.0[l] = h;
            }
        }
        // An `if`, not `bool::then` with a closure: the closure was not inlined, so the sum ran
        // as baseline SSE2 code outside the engine's AVX2 function (7.7 % of an ensemble).
        let y1 = if plans.iter().any(Option::is_some) {
            Some(crate::integrate::taylor::horner(&series[..=p], tau))
        } else {
            None
        };
        for l in 0..W {
            let Some(s) = slots[l].as_mut() else { continue };
            let r = &mut s.run;
            let landed = match (plans[l], &y1) {
                (Some((_, t1)), Some(y)) => {
                    let y1: Y<N> = core::array::from_fn(|c| core::array::from_fn(|i| y[c][i].0[l]));
                    let ok = y1.iter().flatten().all(|x| x.is_finite());
                    if ok {
                        let dense = r.driver.needs_interpolant(&r.opts).then_some((&series[..], l));
                        r.stepper.land(t1, y1, dense, r.driver.stats());
                    }
                    ok
                }
                _ => false,
            };
            let stepped = if landed {
                r.driver
                    .after_step(&mut r.stepper, &r.opts, &mut r.progress)
            } else {
                if given(l) {
                    r.stepper.take_series(&series, l, r.driver.stats());
                }
                step(s)
            };
            match stepped {
                Ok(false) => {}
                Ok(true) => retire(&mut slots[l], End::Stopped, out),
                Err(f) => retire(&mut slots[l], End::Failed(f), out),
            }
        }
    }
}

/// Starts a Taylor member (see [`enter`]).
fn start<'p, 'a, L: Lagrangian<N>, const N: usize>(
    pos: usize,
    sim: &'p mut Simulation<'a, L, N>,
    out: &mut Out<'_, N>,
) -> Option<TaylorSlot<'p, 'a, L, N>> {
    let run = enter(
        pos,
        sim,
        out,
        |method| match method {
            Method::Taylor { tol } => Some(tol),
            _ => None,
        },
        |sys, tol, t0, y0, hmax, _stats| Ok(Taylor::new(sys, t0, y0, tol, hmax)),
    )?;
    Some(Slot { pos, run, own: () })
}

/// Above this many coordinates the lanes' series runs out of the engine's function
/// ([`lane_series`]).
const SERIES_INLINE_MAX_N: usize = 3;

/// The lanes' series ([`Lagrangian::series_in`]): inlined into the engine for a system of at most
/// [`SERIES_INLINE_MAX_N`] coordinates (the heavy top's 64-member Taylor ensemble takes 1.15 %
/// more instructions with the call), else out of the engine's function and compiled for its
/// features: AVX2, and FMA for the fused lanes (`F`). Inlined (the series is `#[inline(always)]`),
/// an 8-link chain's series made each of the two engine functions 590 KB of code that LLVM took
/// 150 s to optimize (5.5 min of one test's build), a 4-coordinate system's with high powers 38 s
/// each; on its own the series builds in seconds. One call per step, where the series of four or
/// more coordinates is the larger part of the work.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn lane_series<L: Lagrangian<N>, const N: usize, const W: usize, const F: bool>(
    members: &[&L; W],
    params: &mut Vec<Lanes<W, F>>,
    t: Lanes<W, F>,
    out: &mut [YOf<Lanes<W, F>, N>],
    buf: &mut SeriesBuf<Lanes<W, F>>,
) -> Option<Result<Mask<W>, DynamicsError>> {
    if const { N <= SERIES_INLINE_MAX_N } {
        return L::series_in(members, params, t, out, buf);
    }
    // SAFETY: on x86-64 the lanes engines run only inside `run_lanes_avx2` and
    // `run_lanes_avx2_fma` (`lanes::run_lanes`), which are called only where the CPU has AVX2,
    // and FMA for the fused engine (F = true).
    #[allow(unsafe_code)]
    let series = unsafe {
        if F {
            series_avx2_fma(members, params, t, out, buf)
        } else {
            series_avx2(members, params, t, out, buf)
        }
    };
    series
}

/// Functions that run [`Lagrangian::series_in`] with the attributes given (the target features
/// they are compiled for).
macro_rules! series_fns {
    ($($(#[$attr:meta])* $name:ident;)*) => {$(
        $(#[$attr])*
        fn $name<L: Lagrangian<N>, const N: usize, const W: usize, const F: bool>(
            members: &[&L; W],
            params: &mut Vec<Lanes<W, F>>,
            t: Lanes<W, F>,
            out: &mut [YOf<Lanes<W, F>, N>],
            buf: &mut SeriesBuf<Lanes<W, F>>,
        ) -> Option<Result<Mask<W>, DynamicsError>> {
            L::series_in(members, params, t, out, buf)
        }
    )*};
}

series_fns! {
    /// The lanes' series where the engines are not compiled for a feature set of their own.
    #[cfg(not(target_arch = "x86_64"))]
    #[inline(always)]
    lane_series;
    /// [`Lagrangian::series_in`] compiled for AVX2 (the exact lanes).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[inline(never)]
    series_avx2;
    /// [`Lagrangian::series_in`] compiled for AVX2 and FMA (the fused lanes).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    #[inline(never)]
    series_avx2_fma;
}
