//! The `#[lagrangian]` attribute macro of [lagrange](https://docs.rs/lagrange).
//!
//! The pipeline is parse → validate → the front end (`front/`: each body's entry names and
//! mentions, the callables, scopes and the pattern binder, the iterator vocabulary, the bodies
//! that read rates; resolved once) → the flags (`analyze.rs`) and the jets back end (`jets/`) →
//! the symbolic back end (`symbolic/`, `mode = "symbolic"`) → emit, one module each, run by the
//! driver in `expand.rs`.
//! Every stage pushes its errors into one sink, spanned at the user's tokens, so all are
//! reported at once. While errors exist, what is emitted is:
//!
//! - the annotated item is not an impl block: the errors and the item as written;
//! - parse or validation errors: the errors, the impl block without its `fn lagrangian`,
//!   `fn dissipation`, `fn forces` and `fn constraints` (and without any other function taking
//!   `Coord`, `Coord3` or `Time`), and, for an inherent impl
//!   without generics, a stub `impl Lagrangian<N>` whose `fn lagrangian` is `unreachable!` (and,
//!   when `fn constraints` returns `[Scalar; K]`, a stub `impl Holonomic<N, K>`), so
//!   uses of the type elsewhere do not cascade into "trait not implemented";
//! - errors of the symbolic stage (a body the symbolic mode cannot derive): the errors and the
//!   impl the jets mode would emit (the rest of the impl block, and `impl Lagrangian<N>` with
//!   `COORDINATES`, `CYCLIC`, `AUTONOMOUS` (and, with forces or dissipation,
//!   `MOMENTUM_CONSERVED` and `ENERGY_CONSERVED`), the jets `fn lagrangian` and the generic
//!   `fn dissipation` / `fn generalized_forces`, and `impl Holonomic<N, K>`), without the symbolic
//!   methods and the `EQUATIONS` consts: rustc still type-checks the body as written, so a
//!   genuine type error there is reported at the user's token too. The build fails either way.
//!
//! Every identifier the macro generates comes from `names.rs` and carries a reserved prefix, so
//! no name in the user's scope can collide with it. See the facade crate for the user-facing
//! documentation.
#![forbid(unsafe_code)]

mod analyze;
mod emit;
mod errors;
mod expand;
mod front;
mod jets;
mod model;
mod names;
mod parse;
mod symbolic;
mod validate;

use proc_macro::TokenStream;

/// Derives `impl Lagrangian<N>` from `fn lagrangian(&self, (q, q_dot): Coord, ...) -> Scalar`
/// (and the optional `fn dissipation` and `fn forces`) written as plain Rust. See the `lagrange`
/// crate documentation.
///
/// # Arguments
///
/// `#[lagrangian]` derives symbolically at compile time; `#[lagrangian(mode = "jets")]` with the
/// run-time jets. `#[lagrangian(lanes)]` asks the symbolic mode for its lanes code (SIMD
/// ensembles) whatever the system's size: by default only systems of up to 300 generated
/// operations (the heavy top, a 6-link chain) get it, since every `Ensemble` compiles the lanes
/// engines around it (a 12-link chain's release build took 123 s against 12 s without).
///
/// # Signature forms
///
/// `fn lagrangian(&self, <coordinates>, t: Time) -> Scalar` (`self: &Self` also works), each
/// coordinate parameter one of `(x, x_dot): Coord` (a `Scalar`), `(r, r_dot): Coord3` (a
/// `Vector3<Scalar>`, slots `r.x`, `r.y`, `r.z`) or `(q, q_dot): Coords<K>` (a `[Scalar; K]`, K an
/// integer literal, slots `q[0]` … `q[K-1]`), mixed freely; `t: Time` is optional. Methods of
/// the same impl block written with `Scalar` are helpers: generic over the number type in both
/// modes, inlined by the symbolic mode.
///
/// ```
/// use lagrange::prelude::*;
///
/// pub struct Chain { pub m: f64, pub l: f64, pub g: f64 }
///
/// #[lagrangian]
/// impl Chain {
///     fn lagrangian(&self, (q, q_dot): Coords<3>) -> Scalar {
///         let (mut vx, mut vy, mut y, mut l) = (0.0, 0.0, 0.0, 0.0);
///         for k in 0..q.len() {
///             let (s, c) = q[k].sin_cos();
///             vx += self.l * c * q_dot[k];
///             vy += self.l * s * q_dot[k];
///             y -= self.l * c;
///             l += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
///         }
///         l
///     }
/// }
///
/// let c = Chain { m: 1.0, l: 1.0, g: 9.81 };
/// let a = c.accelerations(&[0.0; 3], &[0.0; 3], 0.0).unwrap();
/// assert_eq!(a, [0.0; 3]); // hanging straight down, at rest
/// assert_eq!(Chain::COORDINATES, ["q[0]", "q[1]", "q[2]"]);
/// ```
///
/// # Constraints
///
/// An optional `fn constraints(&self, (x, _): Coord, ..., t: Time) -> [Scalar; K]` next to
/// `fn lagrangian` declares K holonomic constraints g(q, t) = 0 and makes the macro also emit
/// `impl Holonomic<N, K>` (in both modes). It takes `lagrangian`'s coordinates, all of them, in
/// the same order and of the same kinds; any binding may be `_`, every velocity must be (the
/// constraints depend on the positions, and on `t: Time` for a moving constraint, only), and the
/// body ends in an array literal of K entries. `CONSTRAINED_COORDINATES` marks the coordinates
/// the body mentions; `SCLERONOMIC` is `true` when it does not use the time.
///
/// ```
/// use lagrange::prelude::*;
///
/// /// A bead on a vertical line that moves as x = a cos(ω t).
/// pub struct Bead { pub g: f64, pub a: f64, pub w: f64 }
///
/// #[lagrangian(mode = "jets")]
/// impl Bead {
///     fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
///         0.5 * (x_dot * x_dot + y_dot * y_dot) - self.g * y
///     }
///     fn constraints(&self, (x, _): Coord, (_, _): Coord, t: Time) -> [Scalar; 1] {
///         [x - self.a * (self.w * t).cos()]
///     }
/// }
///
/// let b = Bead { g: 9.81, a: 0.5, w: 2.0 };
/// let (acc, _) = b.constrained_accelerations(&[0.5, 0.0], &[0.0, 0.0], 0.0).unwrap();
/// assert!((acc[0] + 0.5 * 4.0).abs() < 1e-12 && (acc[1] + 9.81).abs() < 1e-12);
/// assert_eq!(<Bead as lagrange::Holonomic<2, 1>>::CONSTRAINED_COORDINATES, [true, false]);
/// assert!(!<Bead as lagrange::Holonomic<2, 1>>::SCLERONOMIC);
/// ```
///
/// # Velocity constraints
///
/// An optional `fn velocity_constraints(&self, (x, x_dot): Coord, ..., t: Time) -> [Scalar; K]`
/// declares K velocity (nonholonomic) constraints A(q, t) q̇ + b(q, t) = 0, rolling without
/// slipping: the velocities are bound (and `velocity`, the angular velocities may be used), each
/// entry must be affine in them (checked at the token). The macro emits
/// `impl Nonholonomic<N, K>` and folds the rows into `impl Holonomic<N, KH + K>` after those of
/// `fn constraints` (`VELOCITY_ROWS = K`), so `Simulation::constrained` runs both.
///
/// ```
/// use lagrange::prelude::*;
///
/// /// A skate: (x, y) and the heading φ; it cannot slide sideways.
/// pub struct Skate { pub m: f64, pub i: f64 }
///
/// #[lagrangian]
/// impl Skate {
///     fn lagrangian(&self, (_x, x_dot): Coord, (_y, y_dot): Coord, (_phi, phi_dot): Coord) -> Scalar {
///         0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) + 0.5 * self.i * phi_dot * phi_dot
///     }
///     fn velocity_constraints(&self, (_, x_dot): Coord, (_, y_dot): Coord, (phi, _): Coord) -> [Scalar; 1] {
///         [y_dot * phi.cos() - x_dot * phi.sin()]
///     }
/// }
///
/// // Moving along its heading while turning: the blade's side force bends the path.
/// let s = Skate { m: 2.0, i: 0.5 };
/// let (acc, lambda) = s.constrained_accelerations(&[0.0, 0.0, 0.0], &[3.0, 0.0, 1.0], 0.0).unwrap();
/// assert!(acc[0].abs() < 1e-12 && (acc[1] - 3.0).abs() < 1e-12); // ÿ = ẋ φ̇
/// assert!((lambda[0] - 6.0).abs() < 1e-12); // m ẋ φ̇
/// assert_eq!(<Skate as lagrange::Holonomic<3, 1>>::VELOCITY_ROWS, 1);
/// ```
///
/// # Contacts
///
/// An optional `fn contacts(&self, (x, _): Coord, ..., t: Time) -> [Contact; K]` declares K
/// unilateral contacts, each from its gap g(q, t) ≥ 0 (`Contact::gap(g)`, with
/// `.restitution(e)`, `.sticking(s)`, `.named(..)`), and makes the macro emit
/// `impl Unilateral<N, K>`, which `Simulation::contacts` runs (see the crate docs).
#[proc_macro_attribute]
pub fn lagrangian(args: TokenStream, input: TokenStream) -> TokenStream {
    // On a stack of its own (256 MiB reserved, committed as used, on this thread so the compiler's
    // token streams stay reachable): syn parses and prints nested expressions recursively.
    stacker::grow(STACK, || expand::expand(args.into(), input.into()).into())
}

/// The stack the expansion runs on.
const STACK: usize = 256 << 20;

#[cfg(test)]
mod deep_bodies;
#[cfg(test)]
mod expanded_example;
