//! Runs with unilateral contacts ([`Simulation::contacts`]): the contact view the integrators
//! step (its accelerations those of the closed contacts acting as constraints), one event per
//! contact (its gap while open, its normal multiplier while closed), and the transitions at
//! those events: impacts through the derived impact map ([`crate::impact`]), lift-off, and the
//! resting contact a Zeno accumulation of bounces resolves to.

use std::cell::Cell;
use std::rc::Rc;

use nalgebra::SMatrix;

use crate::contact::{ContactRows, Unilateral};
use crate::eom::Pieces;
use crate::error::{DynamicsError, DynamicsResult, Short};
use crate::impact::{self, Candidate, Equality};
use crate::lagrangian::Lagrangian;
use crate::linalg::lu_solve_dyn;
use crate::scalar::Scalar;

use super::error::SimulationError;
use super::events::{Event, Jump, Side};
use super::manifold::{Manifold, Rows, least_norm_dyn};
use super::newton::inf_norm;
use super::sensitivity::central;
use super::simulation::{Simulation, Sys};
use super::state::{Fault, Y};

/// At most this many Newton iterations when projecting positions onto the closed contacts.
const MAX_PROJECTION: usize = 10;

/// Which contacts are closed, and where each closed sticking contact's tangential coordinate is
/// held: shared by the view, its events and the run's projection.
#[derive(Debug)]
struct ContactState<const K: usize> {
    closed: Cell<[bool; K]>,
    anchor: Cell<[f64; K]>,
    /// The last transition the run took: the modes on either side of it (what a sensitivity
    /// run's saltation matrix evaluates the flow, the event and the reset with).
    last: Cell<Option<Transition<K>>>,
    /// Set while a saltation matrix differentiates the reset from the mode before the jump: a
    /// transition is then evaluated and undone, not recorded.
    dry: Cell<bool>,
}

/// Which contacts are closed and where the sticking ones are anchored.
type Mode<const K: usize> = ([bool; K], [f64; K]);

/// A transition of the contacts' mode: before, after, and whether it was the completion of a
/// Zeno accumulation (no saltation matrix: infinitely many impacts).
#[derive(Clone, Copy, Debug)]
struct Transition<const K: usize> {
    before: Mode<K>,
    after: Mode<K>,
    zeno: bool,
}

/// A system with unilateral contacts seen as the [`Lagrangian`] the integrators step: its
/// accelerations are those with the closed contacts as constraints (M q̈ = f + Gᵀλ over their
/// rows), everything else is the system's own. What [`Simulation::contacts`] runs.
///
/// ```
/// use lagrange_runtime::{integrate::ContactView, Contact, Lagrangian, Scalar, Unilateral};
/// struct Ball;
/// impl Lagrangian<1> for Ball {
///     const COORDINATES: [&'static str; 1] = ["y"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 - q[0] * 9.81 }
/// }
/// impl Unilateral<1, 1> for Ball {
///     fn contacts<S: Scalar>(&self, q: &[S; 1], _t: S) -> [Contact<S>; 1] { [Contact::gap(q[0])] }
/// }
/// // On the floor at rest, the contact starts closed: no acceleration, λ = m g.
/// let view = ContactView::new(&Ball, &[0.0], &[0.0], 0.0).unwrap();
/// assert_eq!(view.closed(), [true]);
/// assert_eq!(view.accelerations(&[0.0], &[0.0], 0.0).unwrap(), [0.0]);
/// assert_eq!(view.normal_forces(&[0.0], &[0.0], 0.0).unwrap(), [9.81]);
/// ```
pub struct ContactView<'a, U: ?Sized, const N: usize, const K: usize> {
    sys: &'a U,
    state: Rc<ContactState<K>>,
    /// How many equality constraints hold alongside the contacts
    /// ([`Unilateral::equality_rows`]), and how many of them (the last) are velocity rows.
    equalities: (usize, usize),
}

impl<U: ?Sized, const N: usize, const K: usize> Clone for ContactView<'_, U, N, K> {
    fn clone(&self) -> Self {
        ContactView {
            sys: self.sys,
            state: Rc::clone(&self.state),
            equalities: self.equalities,
        }
    }
}

impl<U: ?Sized, const N: usize, const K: usize> core::fmt::Debug for ContactView<'_, U, N, K> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("ContactView")
            .field("closed", &self.state.closed.get())
            .finish_non_exhaustive()
    }
}

/// One row of a closed contact or of an equality constraint: its gradient, value (the gap,
/// the tangential coordinate minus its anchor, or g), rate and curvature, its λ slot (2j
/// normal, 2j + 1 tangential, 2K + i for equality i), and whether it is a velocity constraint
/// (no position part).
struct Row<const N: usize> {
    grad: [f64; N],
    value: f64,
    rate: f64,
    curvature: f64,
    slot: usize,
    velocity: bool,
}

impl<'a, U: Unilateral<N, K> + ?Sized, const N: usize, const K: usize> ContactView<'a, U, N, K> {
    /// The view of `sys` starting at (q0, q̇0, t0): a contact is closed where its gap and its
    /// rate vanish (to 1e-9 of their scales) and the closed contacts press (λ ≥ 0); the state
    /// must not penetrate (a gap below −1e-9 of its scale is an error that names the contact).
    ///
    /// ```
    /// # use lagrange_runtime::{integrate::ContactView, Contact, Lagrangian, Scalar, Unilateral};
    /// # struct Ball;
    /// # impl Lagrangian<1> for Ball {
    /// #     const COORDINATES: [&'static str; 1] = ["y"];
    /// #     const CYCLIC: [bool; 1] = [false];
    /// #     const AUTONOMOUS: bool = true;
    /// #     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 - q[0] * 9.81 }
    /// # }
    /// # impl Unilateral<1, 1> for Ball {
    /// #     fn contacts<S: Scalar>(&self, q: &[S; 1], _t: S) -> [Contact<S>; 1] { [Contact::gap(q[0])] }
    /// # }
    /// assert!(ContactView::new(&Ball, &[-0.5], &[0.0], 0.0).unwrap_err().contains("penetrates"));
    /// assert_eq!(ContactView::new(&Ball, &[1.0], &[0.0], 0.0).unwrap().closed(), [false]);
    /// ```
    pub fn new(sys: &'a U, q0: &[f64; N], qdot0: &[f64; N], t0: f64) -> Result<Self, String> {
        let view = Self::of(sys, q0, qdot0, t0);
        view.start(q0, qdot0, t0, false, None)
            .map_err(|e| e.to_string())?;
        Ok(view)
    }

    /// The view of `sys` with every contact open, its equality rows counted at (q0, q̇0, t0).
    fn of(sys: &'a U, q0: &[f64; N], qdot0: &[f64; N], t0: f64) -> Self {
        let eq = sys.equality_rows(q0, qdot0, t0);
        ContactView {
            sys,
            state: Rc::new(ContactState {
                closed: Cell::new([false; K]),
                anchor: Cell::new([0.0; K]),
                last: Cell::new(None),
                dry: Cell::new(false),
            }),
            equalities: (eq.len(), eq.velocity_rows),
        }
    }

    /// Sets the view up for a run that starts at (q0, q̇0, t0), at the run's own start time
    /// (a moving gap is read there): the contacts whose gap and rate vanish close, and the state
    /// is put exactly on them (a gap within 1e-9 of its scale is a contact, not an error); a
    /// contact that touches and approaches (gap 0, ġ < 0) is an impact at t0, whose jump is
    /// returned with the state after it. Errors name the contact (not finite, penetrating).
    /// A system with equality constraints must start on them (checked as for a constrained
    /// run), or is put on them first where `project` (`Simulation::project_initial_state`).
    /// The contacts of `hold` start closed whatever their gap and rate (a shooting's iterate:
    /// the state is put on them).
    pub(crate) fn start(
        &self,
        q0: &[f64; N],
        qdot0: &[f64; N],
        t0: f64,
        project: bool,
        hold: Option<&[bool]>,
    ) -> Result<(Y<N>, Option<Jump<N>>), SimulationError> {
        let held = |j: usize| hold.is_some_and(|h| h.get(j) == Some(&true));
        self.state.closed.set([false; K]);
        self.state.anchor.set([0.0; K]);
        self.state.last.set(None);
        self.state.dry.set(false);
        let mut y = [*q0, *qdot0];
        if self.equalities.0 > 0 {
            // Every contact is open here: the view's rows are the equalities alone.
            super::simulation::start_on(self, t0, &mut y, project)?;
        }
        let invalid = |message: String| SimulationError::InvalidOptions { message };
        let on = y;
        let (q0, qdot0) = (&on[0], &on[1]);
        let rows = self.sys.contact_rows(q0, qdot0, t0);
        let mut closed = [false; K];
        let mut approaching = None;
        for j in 0..K {
            let (gs, vs) = scales(&rows, j, q0, qdot0);
            if !(rows.gap[j].is_finite() && rows.normal_rate[j].is_finite()) {
                return Err(invalid(format!(
                    "contact {} is not finite at the start t0 = {t0} (gap {}, rate {})",
                    self.name(&rows, j),
                    rows.gap[j],
                    rows.normal_rate[j]
                )));
            }
            if rows.gap[j] < -1e-9 * gs && !held(j) {
                return Err(invalid(format!(
                    "contact {} penetrates at the start: its gap is {} at t0 = {t0}, q0 = {}; \
                     start with every gap g ≥ 0",
                    self.name(&rows, j),
                    Short(rows.gap[j]),
                    Short(&q0[..])
                )));
            }
            if let Some(message) = bad_restitution(rows.restitution[j]) {
                return Err(invalid(format!(
                    "contact {}: {message} (at the start t0 = {t0})",
                    self.name(&rows, j)
                )));
            }
            // Touching: a gap within the round-off of computing it (the terms of g that cancel),
            // or a small penetration (accepted above, put on the surface below). A positive gap
            // above round-off is a drop, however small (a ball 5e-10 above the floor falls for
            // 1e-5 s before its first impact; measured against the gradient's scale it was
            // taken for touching, which made the answer depend on the units and on where the
            // origin is).
            let touching = rows.gap[j] <= gap_roundoff(&rows, j, q0);
            closed[j] = held(j) || (touching && rows.normal_rate[j].abs() <= 1e-9 * vs);
            if !held(j) && touching && rows.normal_rate[j] < -1e-9 * vs && approaching.is_none() {
                approaching = Some(j);
            }
        }
        self.close(closed, &rows);
        self.anchor_at(q0, t0);
        self.release(q0, qdot0, t0)
            .map_err(|e| invalid(e.to_string()))?;
        let mut jump = None;
        if let Some(j) = approaching {
            // An impact at t0: every contact touching and approaching takes its impulse (the
            // transition takes them all), as if the run had arrived here.
            let after = self
                .transition(j, false, t0, q0, qdot0)
                .map_err(|e| invalid(e.to_string()))?;
            let (e0, e1) = (
                self.sys.energy(q0, qdot0, t0),
                self.sys.energy(&after[0], &after[1], t0),
            );
            jump = Some(Jump {
                event: self.name(&rows, j),
                t: t0,
                before: (*q0, *qdot0),
                after: (after[0], after[1]),
                energy_change: e1 - e0,
            });
            y = after;
        }
        // On the closed contacts exactly: a gap of 1e-12 taken for a contact is one.
        self.project(t0, &mut y).map_err(|f| {
            invalid(format!(
                "the initial state could not be put on the contacts that touch at t0 = {t0} \
                 ({f:?}): start with the touching contacts' gaps at 0"
            ))
        })?;
        Ok((y, jump))
    }

    /// Which contacts are closed now.
    pub fn closed(&self) -> [bool; K] {
        self.state.closed.get()
    }

    /// The system itself.
    pub fn system(&self) -> &'a U {
        self.sys
    }

    /// The normal forces λ_j of the closed contacts at a state (zero for the open ones).
    pub fn normal_forces(
        &self,
        q: &[f64; N],
        qdot: &[f64; N],
        t: f64,
    ) -> Result<[f64; K], DynamicsError> {
        let (_, lambda) = self.solve(q, qdot, t)?;
        Ok(core::array::from_fn(|j| lambda[2 * j]))
    }

    /// A contact's name for messages and events.
    fn name(&self, rows: &ContactRows<N, K>, j: usize) -> String {
        if rows.names[j].is_empty() {
            format!("contact {j}")
        } else {
            rows.names[j].to_string()
        }
    }

    /// Sets the closed contacts, anchoring each newly closed sticking one where it is.
    fn close(&self, closed: [bool; K], rows: &ContactRows<N, K>) {
        let was = self.state.closed.get();
        let mut anchor = self.state.anchor.get();
        for j in 0..K {
            if closed[j] && !was[j] && rows.sticking[j] {
                anchor[j] = f64::NAN;
            }
        }
        self.state.anchor.set(anchor);
        self.state.closed.set(closed);
    }

    /// Anchors every closed sticking contact not yet anchored at its tangential coordinate at q.
    fn anchor_at(&self, q: &[f64; N], t: f64) {
        let mut anchor = self.state.anchor.get();
        if anchor.iter().all(|a| !a.is_nan()) {
            return;
        }
        let values = self.sys.contacts(q, t);
        for j in 0..K {
            if anchor[j].is_nan() {
                anchor[j] = values[j].tangent().unwrap_or(0.0);
            }
        }
        self.state.anchor.set(anchor);
    }

    /// The rows of the closed contacts at (q, q̇, t).
    /// The equality constraints' rows come first (slots 2K + i), so that a contact row that
    /// repeats them is the one `independent` leaves out.
    fn active_rows(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> Vec<Row<N>> {
        let closed = self.state.closed.get();
        let anchor = self.state.anchor.get();
        let mut out = Vec::new();
        let (e, ev) = self.equalities;
        if e > 0 {
            let eq = self.sys.equality_rows(q, qdot, t);
            for i in 0..eq.len().min(e) {
                out.push(Row {
                    grad: eq.jacobian[i],
                    value: eq.value[i],
                    rate: eq.rate[i],
                    curvature: eq.curvature[i],
                    slot: 2 * K + i,
                    velocity: i >= e - ev,
                });
            }
        }
        if !closed.iter().any(|&c| c) {
            return out;
        }
        let rows = self.sys.contact_rows(q, qdot, t);
        for j in 0..K {
            if !closed[j] {
                continue;
            }
            out.push(Row {
                grad: rows.normal[j],
                value: rows.gap[j],
                rate: rows.normal_rate[j],
                curvature: rows.normal_curvature[j],
                slot: 2 * j,
                velocity: false,
            });
            if rows.sticking[j] {
                // The tangent's value against its anchor (the anchor is the value at closure).
                let a = if anchor[j].is_nan() { 0.0 } else { anchor[j] };
                let s = self.sys.contacts(q, t)[j].tangent().unwrap_or(0.0);
                out.push(Row {
                    grad: rows.tangent[j],
                    value: s - a,
                    rate: rows.tangent_rate[j],
                    curvature: rows.tangent_curvature[j],
                    slot: 2 * j + 1,
                    velocity: false,
                });
            }
        }
        out
    }

    /// q̈ and the multipliers (2K slots, zero for open contacts) with the closed contacts as
    /// constraints: [M −Gᵀ; G 0] (q̈, λ) = (f, −c), each row of G scaled to unit largest entry.
    fn solve(
        &self,
        q: &[f64; N],
        qdot: &[f64; N],
        t: f64,
    ) -> Result<([f64; N], Vec<f64>), DynamicsError> {
        let rows = independent(self.active_rows(q, qdot, t));
        let mut lambda = vec![0.0; 2 * K + self.equalities.0];
        if rows.is_empty() {
            return Ok((self.sys.accelerations(q, qdot, t)?, lambda));
        }
        let pieces: Pieces<N> = self.sys.pieces(q, qdot, t);
        let f = pieces.rhs();
        let ms = (0..N)
            .map(|i| pieces.mass_entry(i, i).abs())
            .fold(f64::MIN_POSITIVE, f64::max);
        let r = rows.len();
        let n = N + r;
        let mut a = vec![0.0; n * n];
        let mut x = vec![0.0; n];
        let mut s = vec![1.0; r];
        for i in 0..N {
            for c in 0..N {
                a[i * n + c] = pieces.mass_entry(i, c) / ms;
            }
            x[i] = f[i] / ms;
        }
        for (m, row) in rows.iter().enumerate() {
            let big = row.grad.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            s[m] = if big > 0.0 { 1.0 / big } else { 1.0 };
            for i in 0..N {
                a[i * n + N + m] = -row.grad[i] * s[m];
                a[(N + m) * n + i] = row.grad[i] * s[m];
            }
            x[N + m] = -row.curvature * s[m];
        }
        let state = || (t, q.to_vec(), qdot.to_vec());
        lu_solve_dyn(&mut a, &mut x, 1.0).map_err(|_| {
            let (t, q, qdot) = state();
            let names = self.sys.contact_rows(&q_arr(&q), &q_arr(&qdot), t).names;
            let mut closed: Vec<String> = (0..K)
                .filter(|&j| self.closed()[j])
                .map(|j| {
                    if names[j].is_empty() {
                        format!("contact {j}")
                    } else {
                        names[j].to_string()
                    }
                })
                .collect();
            if self.equalities.0 > 0 {
                closed.push(format!(
                    "and the {} equality constraint(s)",
                    self.equalities.0
                ));
            }
            DynamicsError::DependentConstraints {
                t,
                q,
                qdot,
                message: format!(
                    "the closed contacts [{}] leave a direction without inertia (a coordinate \
                     that neither the mass matrix nor the contacts' rows hold): the accelerations \
                     are not determined; give that coordinate inertia, or end the run before the \
                     contacts close",
                    closed.join(", ")
                ),
            }
        })?;
        if !x.iter().all(|v| v.is_finite()) {
            let (t, q, qdot) = state();
            return Err(DynamicsError::NonFinite {
                t,
                q,
                qdot,
                message: "the accelerations with the closed contacts are not finite".into(),
            });
        }
        for (m, row) in rows.iter().enumerate() {
            lambda[row.slot] = x[N + m] * ms * s[m];
        }
        Ok((core::array::from_fn(|i| x[i]), lambda))
    }

    /// Opens closed contacts that pull (λ < 0) at (q, q̇, t), the most negative first, until
    /// every closed one presses.
    fn release(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> Result<(), DynamicsError> {
        for _ in 0..K {
            let (_, lambda) = self.solve(q, qdot, t)?;
            let scale = lambda.iter().fold(0.0_f64, |m, l| m.max(l.abs()));
            let closed = self.closed();
            let worst = (0..K)
                .filter(|&j| closed[j] && lambda[2 * j] < -1e-12 * scale)
                .min_by(|&a, &b| lambda[2 * a].total_cmp(&lambda[2 * b]));
            let Some(j) = worst else {
                return Ok(());
            };
            let mut c = closed;
            c[j] = false;
            self.state.closed.set(c);
        }
        Ok(())
    }

    /// The transition at contact `j`'s event at (t, q, q̇): an impact where `j` is open (with
    /// restitution 0 when `plastic`, the Zeno resolution), a lift-off where it is closed.
    /// Returns the state after it, on the closed contacts.
    /// The mode: which contacts are closed, where the sticking ones are anchored.
    fn mode(&self) -> Mode<K> {
        (self.state.closed.get(), self.state.anchor.get())
    }

    fn set_mode(&self, (closed, anchor): Mode<K>) {
        self.state.closed.set(closed);
        self.state.anchor.set(anchor);
    }

    /// [`transition`](Self::transition) as the run takes it (recorded as the last), or, while a
    /// saltation matrix differentiates the reset, evaluated and undone.
    fn transit(
        &self,
        j: usize,
        plastic: bool,
        t: f64,
        q: &[f64; N],
        qdot: &[f64; N],
    ) -> Result<Y<N>, DynamicsError> {
        let before = self.mode();
        let out = self.transition(j, plastic, t, q, qdot);
        if self.state.dry.get() {
            self.set_mode(before);
        } else {
            self.state.last.set(Some(Transition {
                before,
                after: self.mode(),
                zeno: plastic,
            }));
        }
        out
    }

    /// Puts the mode on `side` of the last transition (see [`Event::side`]).
    fn side(&self, side: Side) -> Result<(), String> {
        let Some(last) = self.state.last.get() else {
            return Ok(());
        };
        if last.zeno {
            return Err(
                "the contact closed at the accumulation of its impacts (a Zeno run): the flow \
                 through infinitely many impacts has no derivative there; end the sensitivity \
                 run before the impacts accumulate"
                    .into(),
            );
        }
        match side {
            Side::Before => {
                self.set_mode(last.before);
                self.state.dry.set(true);
            }
            Side::After => {
                self.set_mode(last.after);
                self.state.dry.set(false);
            }
        }
        Ok(())
    }

    fn transition(
        &self,
        j: usize,
        plastic: bool,
        t: f64,
        q: &[f64; N],
        qdot: &[f64; N],
    ) -> Result<Y<N>, DynamicsError> {
        let closed = self.closed();
        let mut y = [*q, *qdot];
        if closed[j] && !plastic {
            // Lift-off: λ_j reached zero.
            let mut c = closed;
            c[j] = false;
            self.state.closed.set(c);
            self.release(q, qdot, t)?;
            return Ok(y);
        }
        let rows = self.sys.contact_rows(q, qdot, t);
        // The candidates: this contact, the closed ones, and the open ones at zero gap
        // approaching or resting.
        let mut idx = Vec::new();
        for i in 0..K {
            let (gs, vs) = scales(&rows, i, q, qdot);
            let touching = rows.gap[i].abs() <= 1e-9 * gs && rows.normal_rate[i] <= 1e-9 * vs;
            if i == j || closed[i] || touching {
                idx.push(i);
            }
        }
        if plastic {
            // The Zeno completion: where the impacts accumulate the motion normal to every
            // touching contact has died out; all of them close, and the velocities lose their
            // components against them (the plastic impact of all at once, least kinetic energy
            // change: [M −Gᵀ; G 0] (q̇⁺, Λ) = (M q̇⁻, −∂g/∂t) over their independent rows). A
            // contact that then pulls opens at once (`release`).
            let mut next = closed;
            for &i in &idx {
                next[i] = true;
            }
            self.close(next, &rows);
            self.anchor_at(q, t);
            y[1] = self.plastic(q, qdot, t)?;
            self.release(&y[0], &y[1], t)?;
            self.project(t, &mut y).map_err(|f| DynamicsError::Impact {
                t,
                q: q.to_vec(),
                qdot: qdot.to_vec(),
                message: format!(
                    "after the impacts accumulated, the state could not be put on the closed \
                     contacts ({f:?})"
                ),
            })?;
            return Ok(y);
        }
        for &i in &idx {
            if let Some(message) = bad_restitution(rows.restitution[i]) {
                return Err(DynamicsError::Impact {
                    t,
                    q: q.to_vec(),
                    qdot: qdot.to_vec(),
                    message: format!("contact {}: {message}", self.name(&rows, i)),
                });
            }
        }
        let cands: Vec<Candidate<N>> = idx
            .iter()
            .map(|&i| Candidate {
                normal: rows.normal[i],
                rate: rows.normal_rate[i],
                restitution: if plastic && i == j {
                    0.0
                } else {
                    rows.restitution[i]
                },
                tangent: rows.sticking[i].then_some((rows.tangent[i], rows.tangent_rate[i])),
            })
            .collect();
        let m: SMatrix<f64, N, N> = self.sys.mass_matrix(q, qdot, t);
        let mass: [[f64; N]; N] = core::array::from_fn(|i| core::array::from_fn(|k| m[(i, k)]));
        // The equality constraints hold through the impact (their independent rows).
        let equalities: Vec<Equality<N>> = independent(self.active_rows(q, qdot, t))
            .into_iter()
            .filter(|r| r.slot >= 2 * K)
            .map(|r| Equality {
                row: r.grad,
                rate: r.rate,
            })
            .collect();
        let out = impact::resolve_constrained(&mass, qdot, &cands, &equalities).map_err(|f| {
            DynamicsError::Impact {
                t,
                q: q.to_vec(),
                qdot: qdot.to_vec(),
                message: format!(
                    "the impact of {} (with {} contact(s) touching) has no solution ({f:?}): the \
                 impact law M Δq̇ = Gᵀ Λ, ġ⁺ = −e ġ⁻ on the rows that take an impulse and \
                 ġ⁺ ≥ −e ġ⁻ on the others cannot be met; check that the contacts' gradients \
                 are independent where they touch together (and of the equality constraints)",
                    self.name(&rows, j),
                    idx.len()
                ),
            }
        })?;
        y[1] = out.qdot;
        // Contacts left at rest on their surface (ġ⁺ ≈ 0) close; the ones still moving apart
        // (a bounce, a separation) are open.
        let mut next = [false; K];
        for (c, &i) in cands.iter().zip(&idx) {
            let vs = scales(&rows, i, q, qdot).1.max(c.rate.abs());
            let after: f64 = c.rate
                + (0..N)
                    .map(|k| c.normal[k] * (out.qdot[k] - qdot[k]))
                    .sum::<f64>();
            next[i] = after.abs() <= 1e-9 * vs;
        }
        self.close(next, &rows);
        self.anchor_at(q, t);
        self.release(&y[0], &y[1], t)?;
        self.project(t, &mut y).map_err(|f| DynamicsError::Impact {
            t,
            q: q.to_vec(),
            qdot: qdot.to_vec(),
            message: format!(
                "after the impact the state could not be put on the closed contacts ({f:?})"
            ),
        })?;
        Ok(y)
    }

    /// The velocities after a plastic impact on every closed contact at (q, q̇⁻, t): the
    /// least-kinetic-energy change that makes each closed row's rate zero (independent rows).
    fn plastic(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> Result<[f64; N], DynamicsError> {
        let rows = independent(self.active_rows(q, qdot, t));
        if rows.is_empty() {
            return Ok(*qdot);
        }
        let m: SMatrix<f64, N, N> = self.sys.mass_matrix(q, qdot, t);
        let ms = (0..N)
            .map(|i| m[(i, i)].abs())
            .fold(f64::MIN_POSITIVE, f64::max);
        let r = rows.len();
        let n = N + r;
        let mut a = vec![0.0; n * n];
        let mut x = vec![0.0; n];
        for i in 0..N {
            for k in 0..N {
                a[i * n + k] = m[(i, k)] / ms;
            }
            x[i] = (0..N).map(|k| m[(i, k)] * qdot[k]).sum::<f64>() / ms;
        }
        for (c, row) in rows.iter().enumerate() {
            let big = row
                .grad
                .iter()
                .fold(0.0_f64, |m, x| m.max(x.abs()))
                .max(f64::MIN_POSITIVE);
            for i in 0..N {
                a[i * n + N + c] = -row.grad[i] / big;
                a[(N + c) * n + i] = row.grad[i] / big;
            }
            // G q̇⁺ + ∂g/∂t = 0, with ∂g/∂t = rate − G q̇⁻.
            let gv: f64 = (0..N).map(|i| row.grad[i] * qdot[i]).sum();
            x[N + c] = -(row.rate - gv) / big;
        }
        lu_solve_dyn(&mut a, &mut x, 1.0).map_err(|_| DynamicsError::Impact {
            t,
            q: q.to_vec(),
            qdot: qdot.to_vec(),
            message: "the plastic impact on every touching contact has no solution (a \
                      direction without inertia)"
                .into(),
        })?;
        Ok(core::array::from_fn(|i| x[i]))
    }

    /// The run's events, one per contact: its gap while open, its normal force while closed,
    /// both falling through zero; the transition resets the state.
    fn events(&self, q0: &[f64; N], t0: f64) -> Vec<Event<'a, N>>
    where
        U: Sized,
    {
        let names = self.sys.contacts(q0, t0);
        (0..K)
            .map(|j| {
                let name = names[j]
                    .name()
                    .map_or_else(|| format!("contact {j}"), str::to_string);
                let (v, r, z, m) = (self.clone(), self.clone(), self.clone(), self.clone());
                Event::zero_crossing(name, move |t, q, qdot| {
                    if v.closed()[j] {
                        v.solve(q, qdot, t).map_or(f64::NAN, |(_, l)| l[2 * j])
                    } else {
                        v.sys.contacts(q, t)[j].gap_value()
                    }
                })
                .falling()
                .reset_fallible(move |t, q, qdot| r.transit(j, false, t, q, qdot))
                .rest_at_accumulation(move |t, q, qdot| z.transit(j, true, t, q, qdot))
                .with_sides(move |side| m.side(side))
            })
            .collect()
    }
}

/// Why a restitution coefficient is refused, if it is: Newton's law ġ⁺ = −e ġ⁻ takes
/// 0 ≤ e ≤ 1 (e < 0 would send the body on into the surface, e > 1 make energy).
fn bad_restitution(e: f64) -> Option<String> {
    (!(0.0..=1.0).contains(&e)).then(|| {
        format!(
            "its restitution e = {e} is outside [0, 1]: an impact leaves at ġ⁺ = −e ġ⁻, so e < 0 \
             would go on into the surface and e > 1 would make energy; give 0 (plastic) to 1 \
             (elastic) with `.restitution(e)`"
        )
    })
}

/// A slice of length N as an array (for messages).
fn q_arr<const N: usize>(v: &[f64]) -> [f64; N] {
    core::array::from_fn(|i| v.get(i).copied().unwrap_or(f64::NAN))
}

/// The round-off of contact j's gap at q: 64 ε (Σ|∂g/∂q_i q_i| + |g|), the size of the terms
/// that cancel in g (a gap y − 10⁶ at y ≈ 10⁶ carries about 10⁻¹⁰ of it, one at q = 0 none).
fn gap_roundoff<const N: usize, const K: usize>(
    rows: &ContactRows<N, K>,
    j: usize,
    q: &[f64; N],
) -> f64 {
    let n = &rows.normal[j];
    let terms: f64 = (0..N).map(|i| (n[i] * q[i]).abs()).sum::<f64>() + rows.gap[j].abs();
    64.0 * f64::EPSILON * terms
}

/// The scales contact j's gap and rate are measured against: Σ|∂g/∂q_i q_i| and
/// Σ|∂g/∂q_i q̇_i| + |∂g/∂t|, each plus the gradient's largest entry (a floor for a contact at
/// q = 0 or at rest).
fn scales<const N: usize, const K: usize>(
    rows: &ContactRows<N, K>,
    j: usize,
    q: &[f64; N],
    qdot: &[f64; N],
) -> (f64, f64) {
    let n = &rows.normal[j];
    let size: f64 = n.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let gs: f64 = (0..N).map(|i| (n[i] * q[i]).abs()).sum::<f64>() + size;
    let gv: f64 = (0..N).map(|i| n[i] * qdot[i]).sum::<f64>();
    let vs: f64 = (0..N).map(|i| (n[i] * qdot[i]).abs()).sum::<f64>()
        + (rows.normal_rate[j] - gv).abs()
        + size;
    (gs, vs)
}

impl<U: Unilateral<N, K> + ?Sized, const N: usize, const K: usize> Manifold<N>
    for ContactView<'_, U, N, K>
{
    fn count(&self) -> usize {
        2 * K + self.equalities.0
    }
    fn velocity_rows(&self) -> usize {
        self.equalities.1
    }
    fn rows(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> Rows<N> {
        let n = self.count();
        let mut out = Rows {
            value: vec![0.0; n],
            jacobian: vec![[0.0; N]; n],
            rate: vec![0.0; n],
        };
        for r in self.active_rows(q, qdot, t) {
            out.value[r.slot] = r.value;
            out.jacobian[r.slot] = r.grad;
            out.rate[r.slot] = r.rate;
        }
        out
    }
    fn multipliers(&self, t: f64, y: &Y<N>) -> Result<Vec<f64>, Fault> {
        Ok(self.solve(&y[0], &y[1], t)?.1)
    }
    fn project(&self, t: f64, y: &mut Y<N>) -> Result<f64, Fault> {
        let zero = [0.0; N];
        let mut moved = 0.0_f64;
        // Positions onto the rows that have a position part (not the velocity constraints).
        let positional = |q: &[f64; N]| {
            let mut rows = self.active_rows(q, &zero, t);
            rows.retain(|r| !r.velocity);
            independent(rows)
        };
        let mut rows = positional(&y[0]);
        if rows.is_empty() && self.equalities.1 == 0 {
            return Ok(0.0);
        }
        for _ in 0..MAX_PROJECTION {
            if rows.iter().all(|r| r.value == 0.0) {
                break;
            }
            let r: Vec<f64> = rows.iter().map(|r| r.value).collect();
            let dq = least_norm(&rows, &r)?;
            for i in 0..N {
                y[0][i] -= dq[i];
                moved = moved.max(dq[i].abs());
            }
            if !y[0].iter().all(|x| x.is_finite()) {
                return Err(Fault::NonFinite);
            }
            rows = positional(&y[0]);
            if inf_norm(&dq) <= 4.0 * f64::EPSILON * inf_norm(&y[0]) {
                break;
            }
        }
        // Velocities: the nearest q̇ with G q̇ + ∂g/∂t = 0.
        let vrows = independent(self.active_rows(&y[0], &y[1], t));
        let r: Vec<f64> = vrows.iter().map(|r| r.rate).collect();
        let dv = least_norm(&vrows, &r)?;
        for i in 0..N {
            y[1][i] -= dv[i];
        }
        Ok(moved)
    }
    fn residual(&self, t: f64, y: &Y<N>) -> (f64, f64) {
        self.active_rows(&y[0], &y[1], t)
            .iter()
            .fold((0.0_f64, 0.0_f64), |(p, v), r| {
                (p.max(r.value.abs()), v.max(r.rate.abs()))
            })
    }
}

/// The rows whose gradients are independent, in order: a row that repeats a combination of the
/// ones before it (to 1e-9 of its length) is left out. A body resting on more contact rows than
/// it has freedoms (a block on both sticking corners: the two corners' tangential rows are the
/// same row) keeps a determined motion; the forces of the rows left out are taken as zero (the
/// split of a statically indeterminate support is not determined by rigid bodies).
fn independent<const N: usize>(rows: Vec<Row<N>>) -> Vec<Row<N>> {
    // One row (or none) needs no test: a vanishing gradient is the solve's to report.
    if rows.len() <= 1 {
        return rows;
    }
    let mut basis: Vec<[f64; N]> = Vec::new();
    let mut kept = Vec::with_capacity(rows.len());
    for row in rows {
        let norm = row.grad.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm == 0.0 || !norm.is_finite() {
            kept.push(row);
            continue;
        }
        let mut v: [f64; N] = core::array::from_fn(|i| row.grad[i] / norm);
        for b in &basis {
            let d: f64 = (0..N).map(|i| v[i] * b[i]).sum();
            for i in 0..N {
                v[i] -= d * b[i];
            }
        }
        let rest = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if rest <= 1e-9 {
            continue;
        }
        basis.push(core::array::from_fn(|i| v[i] / rest));
        kept.push(row);
    }
    kept
}

/// The least-norm Δ = Gᵀ(GGᵀ)⁻¹ r of G Δ = r over `rows`.
fn least_norm<const N: usize>(rows: &[Row<N>], r: &[f64]) -> Result<[f64; N], Fault> {
    let g: Vec<[f64; N]> = rows.iter().map(|r| r.grad).collect();
    least_norm_dyn(
        &g,
        r,
        "projecting onto the closed contacts: their gradients are dependent here",
    )
}

impl<U: Unilateral<N, K> + ?Sized, const N: usize, const K: usize> Lagrangian<N>
    for ContactView<'_, U, N, K>
{
    crate::constraints::forward_to_system!();
    const COORDINATES: [&'static str; N] = U::COORDINATES;
    // A contact may touch any coordinate: none is cyclic, no momentum is conserved.
    const CYCLIC: [bool; N] = [false; N];
    const AUTONOMOUS: bool = U::AUTONOMOUS;
    const MOMENTUM_CONSERVED: [bool; N] = [false; N];
    // Between impacts, closed contacts that do not move in time do no work.
    const ENERGY_CONSERVED: bool = U::ENERGY_CONSERVED && U::SCLERONOMIC;

    /// The system's power plus that of the closed contacts' forces, λ·(G q̇) (non-zero only for
    /// contacts that move in time); NaN where the accelerations fail.
    fn power(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> f64 {
        let mut p = self.sys.power(q, qdot, t);
        if !U::SCLERONOMIC {
            let Ok((_, lambda)) = self.solve(q, qdot, t) else {
                return f64::NAN;
            };
            for r in self.active_rows(q, qdot, t) {
                let gv: f64 = (0..N).map(|i| r.grad[i] * qdot[i]).sum();
                p += lambda[r.slot] * gv;
            }
        }
        p
    }
    fn accelerations(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> DynamicsResult<[f64; N]> {
        // With every contact open and no equality constraints: the system's own accelerations,
        // nothing allocated.
        if self.equalities.0 == 0 && !self.state.closed.get().iter().any(|&c| c) {
            return self.sys.accelerations(q, qdot, t);
        }
        self.solve(q, qdot, t).map(|(a, _)| a)
    }

    /// The Jacobian of the view's accelerations where they are not the system's own (closed
    /// contacts or equality constraints act): fourth-order central differences in each of q
    /// and q̇ (steps ε^(1/5) of each variable's size: about 1e-13 relative for the smooth
    /// constrained accelerations); `None` (the system's own, exact) with every contact open
    /// and no equality constraints.
    fn first_order_jacobian(
        &self,
        q: &[f64; N],
        qdot: &[f64; N],
        t: f64,
    ) -> Option<DynamicsResult<nalgebra::DMatrix<f64>>> {
        if self.equalities.0 == 0 && !self.state.closed.get().iter().any(|&c| c) {
            return None;
        }
        Some(self.difference_jacobian(q, qdot, t))
    }
}

impl<U: Unilateral<N, K> + ?Sized, const N: usize, const K: usize> ContactView<'_, U, N, K> {
    /// See `first_order_jacobian`.
    fn difference_jacobian(
        &self,
        q: &[f64; N],
        qdot: &[f64; N],
        t: f64,
    ) -> DynamicsResult<nalgebra::DMatrix<f64>> {
        let mut jac = nalgebra::DMatrix::zeros(2 * N, 2 * N);
        for i in 0..N {
            jac[(i, N + i)] = 1.0;
        }
        for col in 0..2 * N {
            let x = if col < N { q[col] } else { qdot[col - N] };
            let h = f64::EPSILON.powf(0.2) * x.abs().max(1.0);
            let at = |d: f64| {
                let (mut qp, mut vp) = (*q, *qdot);
                if col < N {
                    qp[col] = x + d;
                } else {
                    vp[col - N] = x + d;
                }
                self.solve(&qp, &vp, t).map(|(a, _)| a)
            };
            let (p1, m1, p2, m2) = (at(h)?, at(-h)?, at(2.0 * h)?, at(-2.0 * h)?);
            for i in 0..N {
                jac[(N + i, col)] = central(h, [p1[i], m1[i], p2[i], m2[i]]);
            }
        }
        if jac.iter().all(|x| x.is_finite()) {
            Ok(jac)
        } else {
            Err(DynamicsError::NonFinite {
                t,
                q: q.to_vec(),
                qdot: qdot.to_vec(),
                message: "the Jacobian of the accelerations with the closed contacts is not \
                          finite here (the contacts' rows are singular)"
                    .into(),
            })
        }
    }
}

impl<'a, U, const N: usize, const K: usize> Simulation<'a, ContactView<'a, U, N, K>, N>
where
    U: Unilateral<N, K>,
{
    /// A run of a system with unilateral contacts from (q0, q̇0): the same builder as
    /// [`Simulation::new`], with the explicit methods (DOP853, Dormand–Prince, RK4) or Radau5. It is the
    /// run `Simulation::new` gives a system that declares its contacts
    /// ([`Lagrangian::declared`]: every `#[lagrangian]` impl with `fn contacts`); this
    /// constructor names K for a hand-written `impl Unilateral<N, K>` that does not.
    ///
    /// Each contact is an event: while open, its gap falling through zero is an impact, and the
    /// state jumps by the impact map derived from M and the contacts' gradients
    /// ([`crate::impact`]: Newton's law ġ⁺ = −e ġ⁻ on the rows that take an impulse, several
    /// simultaneous contacts solved exactly); a contact that comes to rest closes and acts as a
    /// constraint with a multiplier λ ≥ 0 ([`Trajectory::lambda`](crate::Trajectory::lambda):
    /// contact j's normal force in column 2j, a sticking contact's tangential force in 2j + 1),
    /// until λ falls to zero (lift-off). Impacts that accumulate (a Zeno run: a ball bouncing
    /// ever lower) are resolved: the contact closes plastically at the last one and the run goes
    /// on in resting contact, reported in [`Trajectory::zeno`](crate::Trajectory::zeno). The
    /// jumps are in [`Trajectory::jumps`](crate::Trajectory::jumps) and the work column carries
    /// the energy they remove.
    ///
    /// A system with constraints beside its contacts ([`Unilateral::equality_rows`]: every
    /// `#[lagrangian]` impl with `fn constraints` or `fn velocity_constraints` next to
    /// `fn contacts`) keeps them throughout: in the accelerations, in the projection and through
    /// every impact (M Δq̇ = Gᵀ Λ + Aᵀ μ, the constraints' rates zero after it); their
    /// multipliers follow the contacts' (column 2K + i for constraint i), and the start must be
    /// on them (or `project_initial_state`), as for a constrained run.
    ///
    /// A contact is closed at the start where its gap and rate are zero and it presses; a state
    /// that penetrates a contact is refused ([`SimulationError::InvalidOptions`](crate::SimulationError::InvalidOptions)).
    ///
    /// ```
    /// use lagrange_runtime::{Contact, Lagrangian, Scalar, Simulation, Unilateral};
    /// struct Ball;
    /// impl Lagrangian<1> for Ball {
    ///     const COORDINATES: [&'static str; 1] = ["y"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 - q[0] * 9.81 }
    /// }
    /// impl Unilateral<1, 1> for Ball {
    ///     const SCLERONOMIC: bool = true;
    ///     fn contacts<S: Scalar>(&self, q: &[S; 1], _t: S) -> [Contact<S>; 1] {
    ///         [Contact::gap(q[0]).restitution(0.5).named("floor")]
    ///     }
    /// }
    /// let tr = Simulation::contacts(&Ball, [1.0], [0.0]).until(3.0).run().unwrap();
    /// let t1 = (2.0 / 9.81_f64).sqrt();
    /// assert!((tr.jumps[0].t - t1).abs() < 1e-10);
    /// let z = tr.zeno.as_ref().unwrap(); // resting from t∞ = t₁ (1 + e)/(1 − e) = 3 t₁ on
    /// assert!((z.t_accumulation - 3.0 * t1).abs() < 1e-9 && z.resting);
    /// assert!((tr.lambda.last().unwrap()[0] - 9.81).abs() < 1e-9); // λ = m g
    /// ```
    pub fn contacts(system: &'a U, q0: [f64; N], qdot0: [f64; N]) -> Self {
        let view = ContactView::of(system, &q0, &qdot0, 0.0);
        let events = view.events(&q0, 0.0);
        let mut sim = Self::with(Sys::Owned(Box::new(view.clone())), q0, qdot0);
        // The view is set up when the run starts, at its start time and initial state.
        let start = view.clone();
        sim.o.contact_start = Some(Box::new(move |q, v, t, project, hold| {
            start.start(q, v, t, project, hold)
        }));
        sim.o.manifold = Some(Box::new(view));
        sim.o.events = events;
        sim
    }
}
