//! The [`Lagrangian`] trait: L(q, q̇, t) and what is derived from it with the jets.

use nalgebra::SMatrix;

use crate::eom::{self, Pieces};
use crate::error::{DynamicsError, DynamicsResult};
use crate::jet::{ElJet, HessianJet};
use crate::linalg::all_finite;
use crate::real::Real;
use crate::scalar::Scalar;

/// A mechanical system given by its Lagrangian L(q, q̇, t) in `N` generalized coordinates.
///
/// Implement [`Lagrangian::lagrangian`] generically over [`Scalar`] (or let `#[lagrangian]` write
/// the impl); the equations of motion, the mass matrix, the momenta and the energy are derived
/// from it with forward-mode jets.
///
/// ```
/// use lagrange_runtime::{Lagrangian, Scalar};
/// /// A harmonic oscillator, L = m q̇²/2 − k q²/2.
/// struct Oscillator { m: f64, k: f64 }
/// impl Lagrangian<1> for Oscillator {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], qdot: &[S; 1], _t: S) -> S {
///         qdot[0] * qdot[0] * (self.m / 2.0) - q[0] * q[0] * (self.k / 2.0)
///     }
/// }
/// let osc = Oscillator { m: 2.0, k: 8.0 };
/// assert_eq!(osc.accelerations(&[1.0], &[0.0], 0.0).unwrap(), [-4.0]);
/// assert_eq!(osc.energy(&[1.0], &[1.0], 0.0), 5.0);
/// ```
pub trait Lagrangian<const N: usize> {
    /// Coordinate names, in declaration order.
    const COORDINATES: [&'static str; N];
    /// `true` for a coordinate absent from L: its momentum is conserved, and q̈ does not depend on
    /// it (the explicit integrators rely on that; `Simulation::run` checks it at the initial state).
    const CYCLIC: [bool; N];
    /// `true` when L has no explicit time dependence (∂L/∂t = 0).
    const AUTONOMOUS: bool;
    /// `true` for a coordinate whose momentum p = ∂L/∂q̇ is conserved: cyclic, and no
    /// generalized force or dissipation acts on it. The default, `CYCLIC`, is right for a system
    /// without forces; an impl that supplies [`generalized_forces`](Self::generalized_forces) or
    /// [`dissipation`](Self::dissipation) by hand must say which momenta they leave alone
    /// (`#[lagrangian]` works it out).
    const MOMENTUM_CONSERVED: [bool; N] = Self::CYCLIC;
    /// `true` when the energy (Jacobi integral) h = q̇·p − L is conserved: L autonomous, no
    /// dissipation, no generalized forces. The default, `AUTONOMOUS`, is right for a system
    /// without forces (see [`MOMENTUM_CONSERVED`](Self::MOMENTUM_CONSERVED)).
    const ENERGY_CONSERVED: bool = Self::AUTONOMOUS;

    /// L(q, q̇, t), generic over the number type.
    fn lagrangian<S: Scalar>(&self, q: &[S; N], qdot: &[S; N], t: S) -> S;

    /// The Rayleigh dissipation function D(q, q̇, t) ≥ 0 (default 0): −∂D/∂q̇ joins the
    /// generalized forces, so d/dt ∂L/∂q̇ − ∂L/∂q = Q − ∂D/∂q̇.
    ///
    /// ```
    /// use lagrange_runtime::{Lagrangian, Scalar};
    /// /// A damped oscillator, m ẍ + b ẋ + k x = 0 with m = k = 1, b = 0.5.
    /// struct Damped;
    /// impl Lagrangian<1> for Damped {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     const ENERGY_CONSERVED: bool = false;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] - q[0] * q[0]) * 0.5 }
    ///     fn dissipation<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.25 }
    /// }
    /// assert_eq!(Damped.accelerations(&[1.0], &[2.0], 0.0).unwrap(), [-1.0 - 0.5 * 2.0]);
    /// ```
    #[inline(always)]
    fn dissipation<S: Scalar>(&self, _q: &[S; N], _qdot: &[S; N], _t: S) -> S {
        S::constant(0.0)
    }

    /// The generalized forces Q(q, q̇, t), one per coordinate (default 0): the forces L does not
    /// describe (a drive, a motor torque, drag), d/dt ∂L/∂q̇ − ∂L/∂q = Q − ∂D/∂q̇.
    ///
    /// ```
    /// use lagrange_runtime::{Lagrangian, Scalar};
    /// /// A free particle pushed by a constant force 3.
    /// struct Pushed;
    /// impl Lagrangian<1> for Pushed {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [true];
    ///     const AUTONOMOUS: bool = true;
    ///     const MOMENTUM_CONSERVED: [bool; 1] = [false];
    ///     const ENERGY_CONSERVED: bool = false;
    ///     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 1.0 }
    ///     fn generalized_forces<S: Scalar>(&self, _q: &[S; 1], _v: &[S; 1], _t: S) -> [S; 1] { [S::constant(3.0)] }
    /// }
    /// assert_eq!(Pushed.accelerations(&[0.0], &[0.0], 0.0).unwrap(), [1.5]);
    /// ```
    #[inline(always)]
    fn generalized_forces<S: Scalar>(&self, _q: &[S; N], _qdot: &[S; N], _t: S) -> [S; N] {
        [S::constant(0.0); N]
    }

    /// The power dh/dt along the motion: the rate at which the generalized forces, the
    /// dissipation and the explicit time dependence of L change the energy,
    /// (Q − ∂D/∂q̇)·q̇ − ∂L/∂t. Its integral over a run is the work the trajectory records, so
    /// that h(t) − h(t0) − W(t) measures the integrator's error when h is not conserved.
    ///
    /// ```
    /// use lagrange_runtime::{Lagrangian, Scalar};
    /// struct Damped;
    /// impl Lagrangian<1> for Damped {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     const ENERGY_CONSERVED: bool = false;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] - q[0] * q[0]) * 0.5 }
    ///     fn dissipation<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.25 }
    /// }
    /// assert_eq!(Damped.power(&[1.0], &[2.0], 0.0), -0.5 * 2.0 * 2.0); // −b ẋ² = −2D
    /// ```
    fn power(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> f64 {
        jet_power(self, q, qdot, t)
    }

    /// The pieces of the equations of motion at (q, q̇, t): the mass matrix M = ∂²L/∂q̇∂q̇ and the
    /// Lagrangian part of the right-hand side, f_L = ∂L/∂q − (∂²L/∂q̇∂q) q̇ − ∂²L/∂q̇∂t (see
    /// [`eom`], where they are assembled and solved).
    ///
    /// The default derives them from L with the jets ([`jet_pieces`]: one evaluation in the
    /// [`ElJet`], by columns above [`EL_BY_COLUMNS_ABOVE`](crate::jet::EL_BY_COLUMNS_ABOVE)
    /// coordinates); `#[lagrangian]` in symbolic mode emits
    /// straight-line code; a hand-written impl may supply them directly.
    ///
    /// ```
    /// use lagrange_runtime::{Lagrangian, Scalar};
    /// struct Osc;
    /// impl Lagrangian<1> for Osc {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] - q[0] * q[0]) * 0.5 }
    /// }
    /// let p = Osc.pieces(&[2.0], &[0.0], 0.0);
    /// assert_eq!((p.mass, p.lagrangian_force), ([[1.0]], [-2.0]));
    /// ```
    #[inline(always)]
    fn pieces(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> Pieces<N> {
        jet_pieces(self, q, qdot, t)
    }

    /// The accelerations q̈ from M q̈ = ∂L/∂q − (∂²L/∂q̇∂q) q̇ − ∂²L/∂q̇∂t: the
    /// [`pieces`](Self::pieces) assembled and solved by [`eom::solve`].
    ///
    /// Fails with [`DynamicsError::SingularMassMatrix`] where M = ∂²L/∂q̇∂q̇ is singular and with
    /// [`DynamicsError::NonFinite`] where the state or the derivatives are not finite.
    fn accelerations(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> DynamicsResult<[f64; N]> {
        crate::scalar::take_unseen_rate();
        let pieces = self.pieces(q, qdot, t);
        if crate::scalar::take_unseen_rate() {
            return Err(DynamicsError::NonFinite {
                t,
                q: q.to_vec(),
                qdot: qdot.to_vec(),
                message: "the body reads `velocity(…)` of a number that carries no rate: a \
                          helper function outside the #[lagrangian] impl calls `velocity`, which \
                          the macro cannot see, so L was evaluated in jets without rates and the \
                          rate is NaN (a `min` or `max` may have hidden it). Call `velocity` in \
                          the impl's own body (the macro then evaluates it with rates), or pass \
                          the helper the rate it needs as an argument"
                    .into(),
            });
        }
        eom::solve(&pieces, Self::COORDINATES, q, qdot, t)
    }

    /// The mass matrix M = ∂²L/∂q̇∂q̇ (from [`pieces`](Self::pieces)).
    fn mass_matrix(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> SMatrix<f64, N, N> {
        let p = self.pieces(q, qdot, t);
        SMatrix::from_fn(|i, k| p.mass_entry(i, k))
    }

    /// The generalized momenta p = ∂L/∂q̇.
    fn momenta(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> [f64; N] {
        // An inline const: each system instantiates only the path its N takes.
        if const { N > crate::jet::EL_BY_COLUMNS_ABOVE } {
            value_and_momenta_by_column(self, q, qdot, t).1
        } else {
            el_jet(self, q, qdot, t).grad_qdot()
        }
    }

    /// The energy h = q̇·p − L and the momenta p together (what an integrator records at every
    /// step): one jet pass where [`energy`](Self::energy) and [`momenta`](Self::momenta) take
    /// two. `#[lagrangian]` generates it (fused straight-line code in symbolic mode); a
    /// hand-written impl that overrides `energy` and `momenta` should override this too.
    ///
    /// ```
    /// use lagrange_runtime::{Lagrangian, Scalar};
    /// struct Osc;
    /// impl Lagrangian<1> for Osc {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] - q[0] * q[0]) * 0.5 }
    /// }
    /// assert_eq!(Osc.energy_and_momenta(&[1.0], &[2.0], 0.0), (2.5, [2.0]));
    /// ```
    fn energy_and_momenta(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> (f64, [f64; N]) {
        jet_energy_and_momenta(self, q, qdot, t)
    }

    /// What `#[lagrangian]` compiled for this system beyond the methods above: whether its
    /// q̈ runs W ensemble members per vector, and the construct that keeps the Taylor method
    /// away. [`Compiled::NONE`] (the default) for jets mode and hand-written impls.
    ///
    /// ```
    /// use lagrange_runtime::{lagrangian::Compiled, Lagrangian, Scalar};
    /// struct Osc;
    /// impl Lagrangian<1> for Osc {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] - q[0] * q[0]) * 0.5 }
    /// }
    /// assert_eq!(Osc::COMPILED, Compiled::NONE);
    /// assert!(!Osc::COMPILED.lanes && Osc::COMPILED.not_analytic.is_none());
    /// ```
    const COMPILED: Compiled = Compiled::NONE;

    /// The compiled kernels' parameters slot by slot, each named by the field of `self` it
    /// holds (`"g"` for `self.g`, `"r.x"` for a `Vector3` field's component) or `""` where the
    /// slot is not a field (a constant, parameter-only code, a condition): the fields a
    /// sensitivity run can differentiate by exactly, by seeding their slots in tangents
    /// ([`Sensitivity::field`](crate::Sensitivity::field)). Empty without compiled kernels (a
    /// hand-written impl, the jets mode); `#[lagrangian]` fills it in the symbolic mode.
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar};
    /// struct Spring { k: f64 }
    /// impl Lagrangian<1> for Spring {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
    ///         (v[0] * v[0] - q[0] * q[0] * self.k) * 0.5
    ///     }
    /// }
    /// assert!(Spring::KERNEL_FIELDS.is_empty()); // hand-written: no compiled kernel
    /// ```
    const KERNEL_FIELDS: &'static [&'static str] = &[];

    /// Whether the system declares unilateral contacts (`fn contacts` under `#[lagrangian]`, which
    /// sets it): a run that would step the motion as if there were none (an analysis that does
    /// not take contacts yet, or a hand-written impl whose [`declared`](Self::declared) does not
    /// name them) is then refused instead, and an [`Ensemble`](crate::Ensemble) runs its members
    /// one at a time. A hand-written `impl Unilateral` should set it too.
    ///
    /// ```
    /// use lagrange_runtime::{Lagrangian, Scalar};
    /// struct Osc;
    /// impl Lagrangian<1> for Osc {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] - q[0] * q[0]) * 0.5 }
    /// }
    /// assert!(!Osc::DECLARES_CONTACTS);
    /// ```
    const DECLARES_CONTACTS: bool = false;

    /// q̈ by the compiled kernel over any [`Real`] width: lane l for `members[l]` at (q, q̇, t)
    /// of lane l, with the lanes whose pivot tests passed and whose values are finite (a lane
    /// not in the mask is unspecified: ask [`accelerations`](Self::accelerations) of its member,
    /// which pivots or explains). `params` is the kernel's copy of the members' parameters:
    /// empty, the kernel fills it; the caller empties it when a lane's member changes. `None`:
    /// no compiled kernel (the default; `#[lagrangian]` generates it in symbolic mode where
    /// [`Compiled::lanes`] holds). Every lane equals `accelerations` of its member bit for bit
    /// where the arithmetic is the scalar code's, to round-off where the vector sin and cos enter
    /// and in the fused lanes (`Lanes<W, true>`, whose `madd` rounds once).
    ///
    /// ```
    /// # use lagrange_runtime::{Lagrangian, Scalar, lanes::Lanes};
    /// struct Spring { k: f64 }
    /// impl Lagrangian<1> for Spring {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
    ///         (v[0] * v[0] - q[0] * q[0] * self.k) * 0.5
    ///     }
    /// }
    /// let z = Lanes::<2>([0.0; 2]);
    /// let none = Spring::accelerations_in(&[&Spring { k: 1.0 }, &Spring { k: 4.0 }], &mut Vec::new(), &[z], &[z], z);
    /// assert!(none.is_none()); // hand-written: no compiled kernel
    /// ```
    #[doc(hidden)]
    #[inline]
    fn accelerations_in<R: Real>(
        members: &[&Self],
        params: &mut Vec<R>,
        q: &[R; N],
        qdot: &[R; N],
        t: R,
    ) -> Option<([R; N], R::Mask)>
    where
        Self: Sized,
    {
        let _ = (members, params, q, qdot, t);
        None
    }

    /// The Taylor coefficients of the motion through (q, q̇) = `out[0]` at time t, up to order
    /// `out.len() − 1`, by the compiled kernel over any [`Real`] width (`members` and `params`
    /// as for [`accelerations_in`](Self::accelerations_in)): on return `out[k] = [q_k, q̇_k]`
    /// with q(t + τ) = Σ q_k τ^k, in the lanes of the mask (a lane left out, its M₀ not positive
    /// definite, has an unspecified series: ask the width-1 kernel of its member, which pivots
    /// or explains). For the Taylor method ([`Method::Taylor`](crate::Method::Taylor)); `buf` is
    /// scratch space the caller keeps between calls. `None` where the system does not provide
    /// them: the default. The symbolic mode of `#[lagrangian]` generates them (the Taylor
    /// recurrences of every node of the expression graph, see [`taylor`](crate::taylor)).
    ///
    /// ```
    /// use lagrange_runtime::{taylor::SeriesBuf, Lagrangian, Scalar};
    /// struct Osc;
    /// impl Lagrangian<1> for Osc {
    ///     const COORDINATES: [&'static str; 1] = ["x"];
    ///     const CYCLIC: [bool; 1] = [false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] - q[0] * q[0]) * 0.5 }
    /// }
    /// let mut out = [[[1.0], [0.0]], [[0.0], [0.0]]];
    /// let series = Osc::series_in(&[&Osc], &mut Vec::new(), 0.0, &mut out, &mut SeriesBuf::new());
    /// assert!(series.is_none()); // hand-written
    /// ```
    #[doc(hidden)]
    #[inline]
    fn series_in<R: crate::eom::SeriesReal>(
        members: &[&Self],
        params: &mut Vec<R>,
        t: R,
        out: &mut [[[R; N]; 2]],
        buf: &mut crate::taylor::SeriesBuf<R>,
    ) -> Option<Result<R::Mask, DynamicsError>>
    where
        Self: Sized,
    {
        let _ = (members, params, t, out, buf);
        None
    }

    /// J = ∂(q̇, q̈)/∂(q, q̇) of a view of a system whose accelerations are not its L's own (a
    /// constrained run's: [`Constrained`](crate::constraints::Constrained) gives the Jacobian of
    /// its constrained accelerations), for Radau5's Newton matrix and the stiffness diagnosis.
    /// `None` for a system whose J is that of its L (the default: the run takes it from the
    /// compiled kernel or the jets).
    ///
    /// ```
    /// use lagrange_runtime::{constraints::Constrained, Holonomic, Lagrangian, Scalar};
    /// /// A pendulum in x, y: the rod x² + y² = 4, g = 9.81.
    /// struct P;
    /// impl Lagrangian<2> for P {
    ///     const COORDINATES: [&'static str; 2] = ["x", "y"];
    ///     const CYCLIC: [bool; 2] = [true, false];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
    ///         (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[1] * 9.81
    ///     }
    /// }
    /// impl Holonomic<2, 1> for P {
    ///     const SCLERONOMIC: bool = true;
    ///     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] {
    ///         [q[0] * q[0] + q[1] * q[1] - 4.0]
    ///     }
    /// }
    /// assert!(P.first_order_jacobian(&[0.0, -2.0], &[0.0, 0.0], 0.0).is_none());
    /// let j = Constrained::new(&P).first_order_jacobian(&[0.0, -2.0], &[0.0, 0.0], 0.0);
    /// let j = j.unwrap().unwrap();
    /// assert!((j[(2, 0)] + 9.81 / 2.0).abs() < 1e-12); // δẍ = −(g/l) δx at the bottom
    /// ```
    #[doc(hidden)]
    fn first_order_jacobian(
        &self,
        q: &[f64; N],
        qdot: &[f64; N],
        t: f64,
    ) -> Option<DynamicsResult<nalgebra::DMatrix<f64>>> {
        let _ = (q, qdot, t);
        None
    }

    /// Hands `v` the run of this system as it declares itself: as it is
    /// ([`Declared::plain`], the default), with its `K` holonomic and velocity constraints
    /// ([`Declared::constrained`]) or with its `K` contacts ([`Declared::contacts`]). This is how
    /// [`Simulation::new`](crate::Simulation::new) and the members of an
    /// [`Ensemble`](crate::Ensemble) take everything the system declares: the number of
    /// constraints is a type parameter that only the system's impl knows. `#[lagrangian]`
    /// writes it for a system with `fn constraints`, `fn velocity_constraints` or
    /// `fn contacts`; a hand-written `impl Holonomic` or `impl Unilateral` writes the one line
    /// (as below), else runs it with `Simulation::constrained` or `Simulation::contacts`.
    ///
    /// ```
    /// use lagrange_runtime::lagrangian::Declared;
    /// use lagrange_runtime::{Holonomic, Lagrangian, Scalar, Simulation, Unilateral};
    /// /// A particle on the unit circle, written in x, y.
    /// struct Ring;
    /// impl Lagrangian<2> for Ring {
    ///     const COORDINATES: [&'static str; 2] = ["x", "y"];
    ///     const CYCLIC: [bool; 2] = [true, true];
    ///     const AUTONOMOUS: bool = true;
    ///     fn lagrangian<S: Scalar>(&self, _q: &[S; 2], v: &[S; 2], _t: S) -> S { (v[0] * v[0] + v[1] * v[1]) * 0.5 }
    ///     fn declared<'s, V: Declared<'s, Self, 2>>(&'s self, v: V) -> V::Output {
    ///         v.constrained::<1>(self)
    ///     }
    /// }
    /// impl Holonomic<2, 1> for Ring {
    ///     fn constraints<S: Scalar>(&self, q: &[S; 2], _t: S) -> [S; 1] { [q[0] * q[0] + q[1] * q[1] - 1.0] }
    /// }
    /// let tr = Simulation::new(&Ring, [1.0, 0.0], [0.0, 1.0]).until(10.0).run().unwrap();
    /// let [x, y] = *tr.q.last().unwrap();
    /// assert!((x - 10.0_f64.cos()).abs() < 1e-8 && (y - 10.0_f64.sin()).abs() < 1e-8);
    /// // M q̈ = Gᵀλ with G = (2x, 2y) and q̈ = −q: the ring pulls with λ = −1/2.
    /// assert!((tr.lambda.last().unwrap()[0] + 0.5).abs() < 1e-8);
    /// ```
    #[inline(always)]
    fn declared<'s, V: Declared<'s, Self, N>>(&'s self, v: V) -> V::Output
    where
        Self: Sized,
    {
        v.plain(self)
    }

    /// The energy (Jacobi integral) h = q̇·p − L.
    fn energy(&self, q: &[f64; N], qdot: &[f64; N], t: f64) -> f64 {
        // Not through `energy_and_momenta`: an override of that one may call this.
        jet_energy_and_momenta(self, q, qdot, t).0
    }
}

/// What is done with a system according to what it declares: the visitor of
/// [`Lagrangian::declared`], which calls exactly one of these methods (the run of a
/// [`Simulation`](crate::Simulation) is one such visitor).
///
/// ```
/// use lagrange_runtime::lagrangian::Declared;
/// use lagrange_runtime::{Holonomic, Lagrangian, Scalar, Unilateral};
/// # struct Free;
/// # impl Lagrangian<1> for Free {
/// #     const COORDINATES: [&'static str; 1] = ["x"];
/// #     const CYCLIC: [bool; 1] = [true];
/// #     const AUTONOMOUS: bool = true;
/// #     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
/// # }
/// /// How many constraints or contacts a system declares.
/// struct Count;
/// impl<'s, L: Lagrangian<1> + 's> Declared<'s, L, 1> for Count {
///     type Output = (usize, usize);
///     fn plain(self, _: &'s L) -> (usize, usize) { (0, 0) }
///     fn constrained<const K: usize>(self, _: &'s L) -> (usize, usize) where L: Holonomic<1, K> { (K, 0) }
///     fn contacts<const K: usize>(self, _: &'s L) -> (usize, usize) where L: Unilateral<1, K> { (0, K) }
/// }
/// assert_eq!(Free.declared(Count), (0, 0));
/// ```
pub trait Declared<'s, L: Lagrangian<N> + 's, const N: usize> {
    /// What the visitor gives.
    type Output;
    /// The system as it is: no constraints, no contacts.
    fn plain(self, sys: &'s L) -> Self::Output;
    /// The system with its `K` holonomic and velocity constraints ([`Holonomic`](crate::Holonomic),
    /// the velocity rows last).
    fn constrained<const K: usize>(self, sys: &'s L) -> Self::Output
    where
        L: crate::constraints::Holonomic<N, K>;
    /// The system with its `K` unilateral contacts ([`Unilateral`](crate::Unilateral)).
    fn contacts<const K: usize>(self, sys: &'s L) -> Self::Output
    where
        L: crate::contact::Unilateral<N, K>;
}

/// What `#[lagrangian]` compiled for a system beyond the trait's methods:
/// [`Lagrangian::COMPILED`].
///
/// ```
/// use lagrange_runtime::lagrangian::Compiled;
/// assert!(!Compiled::NONE.lanes);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Compiled {
    /// Whether q̈ is generated straight-line code over any [`Real`] width
    /// ([`Lagrangian::accelerations_in`]; `#[lagrangian]` in symbolic mode for a small system, or
    /// with `#[lagrangian(lanes)]`): an [`Ensemble`](crate::Ensemble) then runs 4 members per
    /// vector by default.
    pub lanes: bool,
    /// The construct of the body that is not analytic along the motion (`abs`, `signum`, `max`,
    /// `min`, `clamp`, the square root of a square), where it has one: the Taylor method, whose
    /// steps sum a series across any kink, refuses such a system (`Simulation::run` returns
    /// [`InvalidOptions`](crate::SimulationError::InvalidOptions) naming it).
    pub not_analytic: Option<&'static str>,
    /// Whether the system declares holonomic constraints (`fn constraints` under
    /// `#[lagrangian]`): [`Linearize::linearize`](crate::Linearize::linearize), which linearizes
    /// the unconstrained L, then refuses with
    /// [`DynamicsError::Constrained`]. A hand-written
    /// `impl Holonomic` should set it too.
    pub constrained: bool,
}

impl Compiled {
    /// Nothing compiled beyond the trait's methods (jets mode, hand-written impls).
    pub const NONE: Compiled = Compiled {
        lanes: false,
        not_analytic: None,
        constrained: false,
    };
}

/// The compiled kernels' parameters for `members` (lane l for `members[l]`): `params` as it is
/// when it holds `P` values, else filled first with `load` of every member (parameter p of every
/// lane in `params[p]`; a lane past the members is NaN). What the generated
/// [`Lagrangian::accelerations_in`] and [`Lagrangian::series_in`] read their parameters with.
///
/// ```
/// use lagrange_runtime::{lagrangian::kernel_params, lanes::Lanes};
/// struct Spring { k: f64 }
/// let (a, b) = (Spring { k: 1.0 }, Spring { k: 4.0 });
/// let mut params: Vec<Lanes<2>> = Vec::new();
/// let p = kernel_params(&[&a, &b], &mut params, |s: &Spring| [s.k]);
/// assert_eq!(p.map(|p| p[0].0), Some([1.0, 4.0]));
/// ```
#[doc(hidden)]
#[inline(always)]
pub fn kernel_params<'p, R: Real, L, const P: usize>(
    members: &[&L],
    params: &'p mut Vec<R>,
    load: impl Fn(&L) -> [f64; P],
) -> Option<&'p [R; P]> {
    if params.len() != P {
        load_params(members, params, load);
    }
    params.first_chunk::<P>()
}

/// The cold part of [`kernel_params`]: the gather, once per change of the members.
#[inline(never)]
fn load_params<R: Real, L, const P: usize>(
    members: &[&L],
    params: &mut Vec<R>,
    load: impl Fn(&L) -> [f64; P],
) {
    let each: Vec<[f64; P]> = members.iter().map(|m| load(m)).collect();
    params.clear();
    params.extend((0..P).map(|p| R::from_lanes(|l| each.get(l).map_or(f64::NAN, |v| v[p]))));
}

/// h = q̇·p − L and p from one jet pass: the defaults of `energy` and `energy_and_momenta`.
fn jet_energy_and_momenta<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> (f64, [f64; N])
where
    L: Lagrangian<N> + ?Sized,
{
    let (l, p) = if const { N > crate::jet::EL_BY_COLUMNS_ABOVE } {
        value_and_momenta_by_column(sys, q, qdot, t)
    } else {
        let l = el_jet(sys, q, qdot, t);
        (l.value(), l.grad_qdot())
    };
    let mut h = -l;
    for i in 0..N {
        h += qdot[i] * p[i];
    }
    (h, p)
}

/// L evaluated in the Euler–Lagrange jet at (q, q̇, t): value, ∂L/∂q, ∂L/∂q̇, M and the mixed term.
///
/// Each number of the evaluation carries N² + 3N + 3 values and the seeds are 2N of them: above
/// [`EL_BY_COLUMNS_ABOVE`](crate::jet::EL_BY_COLUMNS_ABOVE) coordinates this needs more stack
/// than a 2 MiB thread has (the trait's defaults take [`jet_pieces`] by columns there).
///
/// ```
/// use lagrange_runtime::{el_jet, Lagrangian, Scalar};
/// struct Free;
/// impl Lagrangian<1> for Free {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [true];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
/// }
/// assert_eq!(el_jet(&Free, &[0.0], &[3.0], 0.0).grad_qdot(), [3.0]);
/// ```
#[inline(always)]
pub fn el_jet<L, const N: usize>(sys: &L, q: &[f64; N], qdot: &[f64; N], t: f64) -> ElJet<N>
where
    L: Lagrangian<N> + ?Sized,
{
    let (qj, vj, tj) = ElJet::seed(q, qdot, t);
    sys.lagrangian(&qj, &vj, tj)
}

/// L and p = ∂L/∂q̇ from one evaluation in [`ColumnJet`](crate::jet::ColumnJet)s (no column):
/// the momenta and the energy of a system above
/// [`EL_BY_COLUMNS_ABOVE`](crate::jet::EL_BY_COLUMNS_ABOVE) coordinates.
#[inline(never)]
fn value_and_momenta_by_column<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> (f64, [f64; N])
where
    L: Lagrangian<N> + ?Sized,
{
    use crate::jet::ColumnJet;
    crate::jet::with_jet_stack(N, core::mem::size_of::<ColumnJet<N>>(), || {
        let (qj, vj) = ColumnJet::seed(q, qdot, None);
        let l = sys.lagrangian(&qj, &vj, ColumnJet::from(t));
        (l.value(), l.grad_qdot())
    })
}

/// L evaluated in the dense Hessian jet at (q, q̇) and fixed t: gradient and full Hessian in (q, q̇).
///
/// ```
/// use lagrange_runtime::{hessian_jet, Lagrangian, Scalar};
/// struct Spring;
/// impl Lagrangian<1> for Spring {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S { (v[0] * v[0] - q[0] * q[0]) * 0.5 }
/// }
/// assert_eq!(hessian_jet(&Spring, &[2.0], &[0.0], 0.0).hess_qq(), [[-1.0]]);
/// ```
pub fn hessian_jet<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> HessianJet<N>
where
    L: Lagrangian<N> + ?Sized,
{
    // An inline const: each system instantiates only the path its N takes.
    if const { N > crate::jet::HESSIAN_BY_COLUMNS_ABOVE } {
        hessian_by_columns(sys, q, qdot, t)
    } else {
        hessian_whole(sys, q, qdot, t)
    }
}

/// [`hessian_jet`] in one evaluation (its own frame: a large N's would be reserved on the stack
/// even where the columns are taken).
#[inline(never)]
fn hessian_whole<L, const N: usize>(sys: &L, q: &[f64; N], qdot: &[f64; N], t: f64) -> HessianJet<N>
where
    L: Lagrangian<N> + ?Sized,
{
    let (qj, vj) = HessianJet::seed(q, qdot);
    sys.lagrangian(&qj, &vj, HessianJet::from(t))
}

/// [`hessian_jet`] column by column (see [`HESSIAN_BY_COLUMNS_ABOVE`](crate::jet::HESSIAN_BY_COLUMNS_ABOVE)).
#[inline(never)]
fn hessian_by_columns<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> HessianJet<N>
where
    L: Lagrangian<N> + ?Sized,
{
    HessianJet::by_columns(q, qdot, |qj, vj| {
        sys.lagrangian(qj, vj, crate::jet::ColumnJet::from(t))
    })
}

// ---- The jets defaults of the trait: M, f_L, Q − ∂D/∂q̇, the power and the Jacobians of the
// applied forces derived from L, D and Q with the run-time jets. ----

/// The pieces derived by the run-time jets: one evaluation of L and of D in the Euler–Lagrange
/// jet ([`jet_pieces_whole`]) up to [`EL_BY_COLUMNS_ABOVE`](crate::jet::EL_BY_COLUMNS_ABOVE)
/// coordinates, N + 1 evaluations of L in column jets above ([`jet_pieces_by_columns`], whose
/// numbers are O(N) instead of O(N²)). The default of [`Lagrangian::pieces`].
///
/// ```
/// use lagrange_runtime::{lagrangian::jet_pieces, Lagrangian, Scalar};
/// /// L = m q̇²/2 − k q²/2.
/// struct Osc;
/// impl Lagrangian<1> for Osc {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
///         v[0] * v[0] * 1.0 - q[0] * q[0] * 2.0
///     }
/// }
/// let p = jet_pieces(&Osc, &[1.5], &[0.0], 0.0);
/// assert_eq!((p.mass, p.lagrangian_force), ([[2.0]], [-6.0]));
/// ```
#[inline(always)]
pub fn jet_pieces<L, const N: usize>(sys: &L, q: &[f64; N], qdot: &[f64; N], t: f64) -> Pieces<N>
where
    L: Lagrangian<N> + ?Sized,
{
    // An inline const: each system instantiates only the path its N takes.
    if const { N > crate::jet::EL_BY_COLUMNS_ABOVE } {
        jet_pieces_by_columns(sys, q, qdot, t)
    } else {
        jet_pieces_whole(sys, q, qdot, t)
    }
}

/// [`jet_pieces`] from one evaluation of L in the [`ElJet`]: what it is at or below
/// [`EL_BY_COLUMNS_ABOVE`](crate::jet::EL_BY_COLUMNS_ABOVE) coordinates. At any N (a test
/// compares it with [`jet_pieces_by_columns`]), but its stack grows as N³: 9 MiB at N = 64.
///
/// ```
/// use lagrange_runtime::{lagrangian::jet_pieces_whole, Lagrangian, Scalar};
/// struct Osc;
/// impl Lagrangian<1> for Osc {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
///         v[0] * v[0] * 1.0 - q[0] * q[0] * 2.0
///     }
/// }
/// let p = jet_pieces_whole(&Osc, &[1.5], &[0.0], 0.0);
/// assert_eq!((p.mass, p.lagrangian_force), ([[2.0]], [-6.0]));
/// ```
#[inline(always)]
pub fn jet_pieces_whole<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> Pieces<N>
where
    L: Lagrangian<N> + ?Sized,
{
    // One seeding serves L and D.
    let (qj, vj, tj) = ElJet::seed(q, qdot, t);
    let l = sys.lagrangian(&qj, &vj, tj);
    let mut mass = [[0.0; N]; N];
    for (i, row) in mass.iter_mut().enumerate() {
        for (k, e) in row.iter_mut().enumerate().skip(i) {
            *e = l.hess_qdot(i, k);
        }
    }
    let applied = forces_minus(sys, q, qdot, t, || {
        sys.dissipation(&qj, &vj, tj).grad_qdot()
    });
    assemble(mass, l.grad_q(), l.mixed(), applied)
}

/// [`jet_pieces`] column by column: what it is above
/// [`EL_BY_COLUMNS_ABOVE`](crate::jet::EL_BY_COLUMNS_ABOVE) coordinates. L is evaluated N + 1
/// times in [`ColumnJet`](crate::jet::ColumnJet)s of 4N + 2 numbers each: column k of M along
/// q̇ₖ, and once along the direction (q̇, 0, 1) in (q, q̇, t), whose gradient in q is ∂L/∂q and
/// whose column in q̇ is (∂²L/∂q̇∂q) q̇ + ∂²L/∂q̇∂t; D once, on the latter's seeds, for ∂D/∂q̇
/// (Q in `f64`, as in [`jet_pieces_whole`]). Run where the stack has room for it
/// ([`with_jet_stack`](crate::jet::with_jet_stack)).
///
/// ```
/// use lagrange_runtime::lagrangian::{jet_pieces_by_columns, jet_pieces_whole};
/// use lagrange_runtime::{Lagrangian, Scalar};
/// /// L = (1 + q₀²) q̇₀²/2 + q̇₀ q̇₁ t − cos q₁, D = q₀² q̇₁²/2.
/// struct S;
/// impl Lagrangian<2> for S {
///     const COORDINATES: [&'static str; 2] = ["a", "b"];
///     const CYCLIC: [bool; 2] = [false, false];
///     const AUTONOMOUS: bool = false;
///     fn lagrangian<S2: Scalar>(&self, q: &[S2; 2], v: &[S2; 2], t: S2) -> S2 {
///         (q[0] * q[0] + 1.0) * v[0] * v[0] * 0.5 + v[0] * v[1] * t - q[1].cos()
///     }
///     fn dissipation<S2: Scalar>(&self, q: &[S2; 2], v: &[S2; 2], _t: S2) -> S2 {
///         q[0] * q[0] * v[1] * v[1] * 0.5
///     }
/// }
/// let (q, v) = ([0.3, -0.7], [1.1, 0.4]);
/// let (a, b) = (jet_pieces_by_columns(&S, &q, &v, 2.0), jet_pieces_whole(&S, &q, &v, 2.0));
/// for i in 0..2 {
///     assert!((a.lagrangian_force[i] - b.lagrangian_force[i]).abs() < 1e-15);
///     assert!((a.applied[i] - b.applied[i]).abs() < 1e-15);
///     for k in i..2 {
///         assert!((a.mass[i][k] - b.mass[i][k]).abs() < 1e-15);
///     }
/// }
/// ```
#[inline(never)]
pub fn jet_pieces_by_columns<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> Pieces<N>
where
    L: Lagrangian<N> + ?Sized,
{
    use crate::jet::ColumnJet;
    crate::jet::with_jet_stack(N, core::mem::size_of::<ColumnJet<N>>(), || {
        let mut mass = [[0.0; N]; N];
        let tj = ColumnJet::from(t);
        for k in 0..N {
            let (qj, vj) = ColumnJet::seed(q, qdot, Some(N + k));
            let cv = sys.lagrangian(&qj, &vj, tj).column_qdot();
            // The upper triangle: M[i][k] = ∂²L/∂q̇ᵢ∂q̇ₖ for i ≤ k.
            for (row, c) in mass.iter_mut().zip(cv).take(k + 1) {
                row[k] = c;
            }
        }
        // One seeding along (q̇, 0, 1) serves L and D.
        let (qj, vj, tj) = ColumnJet::seed_along(q, qdot, t, qdot, 1.0);
        let l = sys.lagrangian(&qj, &vj, tj);
        let applied = forces_minus(sys, q, qdot, t, || {
            sys.dissipation(&qj, &vj, tj).grad_qdot()
        });
        assemble(mass, l.grad_q(), l.column_qdot(), applied)
    })
}

/// The pieces from M (upper triangle), ∂L/∂q and the mixed term (∂²L/∂q̇∂q) q̇ + ∂²L/∂q̇∂t, so
/// f_L = ∂L/∂q − mixed, and the applied forces.
#[inline(always)]
fn assemble<const N: usize>(
    mass: [[f64; N]; N],
    grad_q: [f64; N],
    mixed: [f64; N],
    applied: [f64; N],
) -> Pieces<N> {
    let mut f = [0.0; N];
    for i in 0..N {
        f[i] = grad_q[i] - mixed[i];
    }
    Pieces::new(mass, f).with_applied(applied)
}

/// Q − ∂D/∂q̇: Q evaluated in `f64`, then ∂D/∂q̇ from `grad_d` (D's gradient in q̇ from whichever
/// jet the caller seeded).
#[inline(always)]
fn forces_minus<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
    grad_d: impl FnOnce() -> [f64; N],
) -> [f64; N]
where
    L: Lagrangian<N> + ?Sized,
{
    let mut applied = sys.generalized_forces(q, qdot, t);
    let dd = grad_d();
    for (a, d) in applied.iter_mut().zip(dd) {
        *a -= d;
    }
    applied
}

/// The applied forces Q − ∂D/∂q̇ at a state: [`Lagrangian::generalized_forces`] evaluated in
/// `f64`, ∂D/∂q̇ from one evaluation of [`Lagrangian::dissipation`] in the jet. Zero (and free
/// after inlining) for a system that supplies neither.
///
/// ```
/// use lagrange_runtime::{lagrangian::jet_applied_forces, Lagrangian, Scalar};
/// struct Drag;
/// impl Lagrangian<1> for Drag {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [true];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * 0.5 }
///     fn dissipation<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S { v[0] * v[0] * v[0].abs() / 3.0 }
///     fn generalized_forces<S: Scalar>(&self, _q: &[S; 1], _v: &[S; 1], t: S) -> [S; 1] { [t] }
/// }
/// // Q − ∂D/∂ẋ = t − ẋ|ẋ| at ẋ = 2, t = 1
/// assert_eq!(jet_applied_forces(&Drag, &[0.0], &[2.0], 1.0), [1.0 - 4.0]);
/// ```
#[inline(always)]
pub fn jet_applied_forces<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> [f64; N]
where
    L: Lagrangian<N> + ?Sized,
{
    // An inline const: each system instantiates only the path its N takes.
    if const { N > crate::jet::EL_BY_COLUMNS_ABOVE } {
        applied_forces_by_column(sys, q, qdot, t)
    } else {
        let (qj, vj, tj) = ElJet::seed(q, qdot, t);
        forces_minus(sys, q, qdot, t, || {
            sys.dissipation(&qj, &vj, tj).grad_qdot()
        })
    }
}

/// [`jet_applied_forces`] above [`EL_BY_COLUMNS_ABOVE`](crate::jet::EL_BY_COLUMNS_ABOVE)
/// coordinates: ∂D/∂q̇ from one evaluation of D in [`ColumnJet`](crate::jet::ColumnJet)s.
#[inline(never)]
fn applied_forces_by_column<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> [f64; N]
where
    L: Lagrangian<N> + ?Sized,
{
    use crate::jet::ColumnJet;
    forces_minus(sys, q, qdot, t, || {
        crate::jet::with_jet_stack(N, core::mem::size_of::<ColumnJet<N>>(), || {
            let (qj, vj) = ColumnJet::seed(q, qdot, None);
            sys.dissipation(&qj, &vj, ColumnJet::from(t)).grad_qdot()
        })
    })
}

/// The power dh/dt = (Q − ∂D/∂q̇)·q̇ − ∂L/∂t from the jets: the default of
/// [`Lagrangian::power`]. ∂L/∂t comes from a jet that moves t alone (exact, and skipped for an
/// autonomous L).
///
/// ```
/// use lagrange_runtime::{lagrangian::jet_power, Lagrangian, Scalar};
/// /// A particle in a potential that grows in time, L = ẋ²/2 − t x².
/// struct Growing;
/// impl Lagrangian<1> for Growing {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = false;
///     fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], t: S) -> S { v[0] * v[0] * 0.5 - t * q[0] * q[0] }
/// }
/// assert_eq!(jet_power(&Growing, &[3.0], &[1.0], 2.0), 9.0); // −∂L/∂t = x²
/// ```
pub fn jet_power<L, const N: usize>(sys: &L, q: &[f64; N], qdot: &[f64; N], t: f64) -> f64
where
    L: Lagrangian<N> + ?Sized,
{
    let applied = jet_applied_forces(sys, q, qdot, t);
    let mut p = 0.0;
    for i in 0..N {
        p += applied[i] * qdot[i];
    }
    if !L::AUTONOMOUS {
        p -= if const { N > crate::jet::EL_BY_COLUMNS_ABOVE } {
            time_derivative_by_column(sys, q, qdot, t)
        } else {
            let (qj, vj, tj) = ElJet::seed_time(q, qdot, t);
            sys.lagrangian(&qj, &vj, tj).directional()
        };
    }
    p
}

/// ∂L/∂t from one evaluation of L in [`ColumnJet`](crate::jet::ColumnJet)s seeded along
/// (0, 0, 1): [`jet_power`] above [`EL_BY_COLUMNS_ABOVE`](crate::jet::EL_BY_COLUMNS_ABOVE)
/// coordinates.
#[inline(never)]
fn time_derivative_by_column<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> f64
where
    L: Lagrangian<N> + ?Sized,
{
    use crate::jet::ColumnJet;
    crate::jet::with_jet_stack(N, core::mem::size_of::<ColumnJet<N>>(), || {
        let (qj, vj, tj) = ColumnJet::seed_along(q, qdot, t, &[0.0; N], 1.0);
        sys.lagrangian(&qj, &vj, tj).slope()
    })
}

/// The applied forces F = Q − ∂D/∂q̇ at a state with their derivatives, exact from the Hessian
/// jet: what an implicit integrator's Newton Jacobian (and a linearization's damping) needs.
///
/// ```
/// use lagrange_runtime::{lagrangian::applied_jacobian, Lagrangian, Scalar};
/// /// Drag D = c ẋ² x²/2 and a force Q = x t.
/// struct S;
/// impl Lagrangian<1> for S {
///     const COORDINATES: [&'static str; 1] = ["x"];
///     const CYCLIC: [bool; 1] = [false];
///     const AUTONOMOUS: bool = true;
///     fn lagrangian<S2: Scalar>(&self, _q: &[S2; 1], v: &[S2; 1], _t: S2) -> S2 { v[0] * v[0] * 0.5 }
///     fn dissipation<S2: Scalar>(&self, q: &[S2; 1], v: &[S2; 1], _t: S2) -> S2 { v[0] * v[0] * q[0] * q[0] * 0.5 }
///     fn generalized_forces<S2: Scalar>(&self, q: &[S2; 1], _v: &[S2; 1], t: S2) -> [S2; 1] { [q[0] * t] }
/// }
/// let j = applied_jacobian(&S, &[2.0], &[3.0], 5.0);
/// assert_eq!(j.value, [10.0 - 3.0 * 4.0]);     // x t − ẋ x²
/// assert_eq!(j.d_q, [[5.0 - 2.0 * 3.0 * 2.0]]); // t − 2 ẋ x
/// assert_eq!(j.d_qdot, [[-4.0]]);                // −x²
/// ```
pub fn applied_jacobian<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> AppliedJacobian<N>
where
    L: Lagrangian<N> + ?Sized,
{
    // An inline const: each system instantiates only the path its N takes.
    if const { N > crate::jet::HESSIAN_BY_COLUMNS_ABOVE } {
        applied_by_columns(sys, q, qdot, t)
    } else {
        applied_whole(sys, q, qdot, t)
    }
}

/// [`applied_jacobian`] from one evaluation of Q and D in Hessian jets (its own frame, as
/// [`hessian_jet`](crate::hessian_jet)'s).
#[inline(never)]
fn applied_whole<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> AppliedJacobian<N>
where
    L: Lagrangian<N> + ?Sized,
{
    let (qj, vj) = HessianJet::seed(q, qdot);
    let tj = HessianJet::from(t);
    let forces = sys.generalized_forces(&qj, &vj, tj);
    let d = sys.dissipation(&qj, &vj, tj);
    let (dv, dqv, dvv) = (d.grad_qdot(), d.hess_qqdot(), d.hess_qdotqdot());
    let mut out = AppliedJacobian::ZERO;
    for i in 0..N {
        let (gq, gv) = (forces[i].grad_q(), forces[i].grad_qdot());
        out.value[i] = forces[i].value() - dv[i];
        for k in 0..N {
            out.d_q[i][k] = gq[k] - dqv[k][i];
            out.d_qdot[i][k] = gv[k] - dvv[i][k];
        }
    }
    out
}

/// [`applied_jacobian`] for a large system: Q's gradients from one evaluation in
/// [`ColumnJet`](crate::jet::ColumnJet)s, D's Hessian in q̇ from one evaluation per column.
#[inline(never)]
fn applied_by_columns<L, const N: usize>(
    sys: &L,
    q: &[f64; N],
    qdot: &[f64; N],
    t: f64,
) -> AppliedJacobian<N>
where
    L: Lagrangian<N> + ?Sized,
{
    use crate::jet::{ColumnJet, JetCalculus};
    let tj = ColumnJet::from(t);
    let (qj, vj) = ColumnJet::seed(q, qdot, None);
    let forces = sys.generalized_forces(&qj, &vj, tj);
    let mut out = AppliedJacobian::ZERO;
    for i in 0..N {
        let (gq, gv) = (forces[i].grad_q(), forces[i].grad_qdot());
        out.value[i] = forces[i].value();
        out.d_q[i] = gq;
        out.d_qdot[i] = gv;
    }
    // Column k of D's Hessian along q̇_k: ∂²D/∂q_a∂q̇_k and ∂²D/∂q̇_a∂q̇_k.
    for k in 0..N {
        let (qj, vj) = ColumnJet::seed(q, qdot, Some(N + k));
        let d = sys.dissipation(&qj, &vj, tj);
        if d.is_constant() {
            // No dissipation (the default's zero): nothing in any column.
            break;
        }
        let (cq, cv) = (d.column_q(), d.column_qdot());
        if k == 0 {
            let dv = d.grad_qdot();
            for i in 0..N {
                out.value[i] -= dv[i];
            }
        }
        for i in 0..N {
            // d_q[i][k] −= ∂²D/∂q_k∂q̇_i, d_qdot[i][k] −= ∂²D/∂q̇_i∂q̇_k (symmetric).
            out.d_qdot[i][k] -= cv[i];
            out.d_q[k][i] -= cq[i];
        }
    }
    out
}

/// The applied forces F = Q − ∂D/∂q̇ and their Jacobians (see [`applied_jacobian`]).
///
/// ```
/// use lagrange_runtime::lagrangian::AppliedJacobian;
/// let j = AppliedJacobian::<1> { value: [1.0], d_q: [[0.0]], d_qdot: [[-0.5]] };
/// assert_eq!(j.d_qdot[0][0], -0.5);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AppliedJacobian<const N: usize> {
    /// Fᵢ.
    pub value: [f64; N],
    /// ∂Fᵢ/∂qₖ (`d_q[i][k]`).
    pub d_q: [[f64; N]; N],
    /// ∂Fᵢ/∂q̇ₖ (`d_qdot[i][k]`).
    pub d_qdot: [[f64; N]; N],
}

impl<const N: usize> AppliedJacobian<N> {
    /// Every entry zero (what the derivations add into).
    const ZERO: Self = AppliedJacobian {
        value: [0.0; N],
        d_q: [[0.0; N]; N],
        d_qdot: [[0.0; N]; N],
    };
}

/// A non-finite dynamics error traced to the applied forces where that is where it starts: at
/// the failing state, non-finite generalized forces (`fn forces`) or dissipation forces −∂D/∂q̇
/// (`fn dissipation`) are named in the message instead of "the derivatives of L". Any other
/// error is returned as it is.
pub(crate) fn blame_applied<L: Lagrangian<N> + ?Sized, const N: usize>(
    sys: &L,
    e: DynamicsError,
) -> DynamicsError {
    let DynamicsError::NonFinite {
        t,
        q,
        qdot,
        message,
    } = e
    else {
        return e;
    };
    let state = <[f64; N]>::try_from(&q[..])
        .ok()
        .zip(<[f64; N]>::try_from(&qdot[..]).ok());
    let what = match state {
        Some((qa, va)) if t.is_finite() && qa.iter().chain(&va).all(|x| x.is_finite()) => {
            let forces = sys.generalized_forces(&qa, &va, t);
            if !all_finite(&forces) {
                Some(format!(
                    "the generalized forces Q of `fn forces` (Lagrangian::generalized_forces) are \
                     not finite here: Q = {}",
                    crate::error::Short(&forces[..])
                ))
            } else {
                let applied = sys.pieces(&qa, &va, t).applied;
                (!all_finite(&applied)).then(|| {
                    format!(
                        "the dissipation forces −∂D/∂q̇ of `fn dissipation` \
                         (Lagrangian::dissipation) are not finite here: Q − ∂D/∂q̇ = {}",
                        crate::error::Short(&applied[..])
                    )
                })
            }
        }
        _ => None,
    };
    let message = match what {
        Some(what) => format!(
            "{what} (NaN or ∞). Check that function at this state (a division by zero, a sqrt or \
             ln of a negative number, a parameter that is NaN); if an integrator got here, a \
             smaller step or a tighter tolerance may keep the solution from blowing up."
        ),
        None => message,
    };
    DynamicsError::NonFinite {
        t,
        q,
        qdot,
        message,
    }
}
