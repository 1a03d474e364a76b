//! # lagrange
//!
//! Write a Lagrangian L(q, q̇, t) as ordinary Rust; get the Euler–Lagrange equations derived
//! exactly (forward-mode jets), solved for the accelerations, and integrated.
//!
//! ```
//! use lagrange::prelude::*;
//!
//! /// A plane pendulum of length l.
//! pub struct Pendulum { pub g: f64, pub l: f64 }
//!
//! #[lagrangian]
//! impl Pendulum {
//!     fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
//!         0.5 * self.l * self.l * theta_dot.powi(2) + self.g * self.l * theta.cos()
//!     }
//! }
//!
//! let p = Pendulum { g: 9.81, l: 2.0 };
//! let a = p.accelerations(&[0.3], &[0.0], 0.0).unwrap();
//! assert!((a[0] + 9.81 / 2.0 * 0.3_f64.sin()).abs() < 1e-14);
//! ```
//!
//! ## Running it
//!
//! A [`Simulation`] integrates one motion (DOP853, Dormand–Prince, RK4, the Taylor method, Radau
//! IIA for stiff systems or a variational integrator; samples, events, the drift of every
//! conserved quantity); an
//! [`Ensemble`] runs many members in parallel (and several per SIMD vector); [`Linearize`] gives
//! M, C, K about an equilibrium or a steady motion, with eigenvalues, stability and modes.
//!
//! ```
//! use lagrange::prelude::*;
//!
//! /// A plane pendulum of length l.
//! pub struct Pendulum { pub g: f64, pub l: f64 }
//!
//! #[lagrangian]
//! impl Pendulum {
//!     fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
//!         0.5 * self.l * self.l * theta_dot.powi(2) + self.g * self.l * theta.cos()
//!     }
//! }
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let p = Pendulum { g: 9.81, l: 1.0 };
//! // One run: a swing of 0.01 rad keeps its energy; its period is 2π √(l/g) (1 + θ₀²/16 + …).
//! let tr = Simulation::new(&p, [0.01], [0.0])
//!     .method(Method::Dop853 { rtol: 1e-12, atol: 1e-12 })
//!     .until(10.0)
//!     .sample_every(0.01)
//!     .event(Event::zero_crossing("swing back", |_t, _q, v: &[f64; 1]| v[0]).falling())
//!     .run()?;
//! assert!(tr.invariants().max_rel() < 1e-10);
//! let period = tr.events[1].t - tr.events[0].t;
//! let t0 = 2.0 * std::f64::consts::PI / 9.81_f64.sqrt();
//! assert!((period - t0 * (1.0 + 1e-4 / 16.0 + 11.0 * 1e-8 / 3072.0)).abs() < 1e-9);
//! println!("{}\n{}", tr.stats, tr.invariants().named(&tr.coordinates));
//!
//! // Many runs: the swing's amplitude grows the period (members in parallel, in member order).
//! let swings = Ensemble::new(4, |i| Member::new(Pendulum { g: 9.81, l: 1.0 }, [0.5 * (i + 1) as f64], [0.0]))
//!     .configure(|sim| sim.until(4.0).sample_at([4.0]))
//!     .run();
//! let last: Vec<f64> = swings.results.iter().map(|r| r.as_ref().map_or(f64::NAN, |t| t.q[t.len() - 1][0])).collect();
//! assert!(last.iter().all(|x| x.is_finite()));
//!
//! // The linearization about the bottom: K/M = g/l, stable; about the top, unstable.
//! let bottom = p.linearize(&[0.0], &[0.0], 0.0)?;
//! assert!((bottom.k[(0, 0)] / bottom.m[(0, 0)] - 9.81).abs() < 1e-12);
//! assert_eq!(bottom.stability()?.to_string(), "marginally stable");
//! let top = p.linearize(&[std::f64::consts::PI], &[0.0], 0.0)?;
//! assert!(!top.stability()?.is_stable());
//! # Ok(())
//! # }
//! ```
//!
//! ## Dissipation and generalized forces
//!
//! Forces that L does not describe go into two optional functions in the same impl block, in
//! both modes: `fn dissipation`, the Rayleigh dissipation function D(q, q̇, t) ≥ 0 (returns
//! `Scalar`), and `fn forces`, the generalized forces Q(q, q̇, t) (returns `[Scalar; N]`, one
//! entry per coordinate slot in declaration order; a `Coord3` takes three, x, y, z). The
//! equations of motion become d/dt ∂L/∂q̇ − ∂L/∂q = Q − ∂D/∂q̇.
//!
//! Their coordinate parameters are `lagrangian`'s, all of them, in the same order and of the
//! same kinds (`Coord`, `Coord3`); any binding may be `_` (`(x, _)`, `(_, _)`) and names may
//! differ; `t: Time` is optional in each function independently. Bindings a body does not use
//! produce no warnings.
//!
//! ```
//! use lagrange::prelude::*;
//!
//! /// A damped pendulum driven by a periodic torque.
//! pub struct DrivenPendulum { pub m: f64, pub l: f64, pub g: f64, pub b: f64, pub a: f64, pub w: f64 }
//!
//! #[lagrangian]
//! impl DrivenPendulum {
//!     fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
//!         0.5 * self.m * self.l * self.l * theta_dot.powi(2) + self.m * self.g * self.l * theta.cos()
//!     }
//!     /// Rayleigh dissipation function D(q, q̇, t) ≥ 0; its −∂D/∂q̇ joins the generalized forces.
//!     fn dissipation(&self, (_, theta_dot): Coord) -> Scalar {
//!         0.5 * self.b * theta_dot.powi(2)
//!     }
//!     /// Generalized forces Q(q, q̇, t), one per coordinate in declaration order.
//!     fn forces(&self, _: Coord, t: Time) -> [Scalar; 1] {
//!         [self.a * (self.w * t).cos()]
//!     }
//! }
//!
//! let p = DrivenPendulum { m: 1.0, l: 1.0, g: 9.81, b: 0.5, a: 2.0, w: 1.0 };
//! let a = p.accelerations(&[0.0], &[1.0], 0.0).unwrap();
//! assert!((a[0] - (2.0 - 0.5)).abs() < 1e-14); // a cos(0) − b θ̇
//! // The printed equations show where each term comes from: L, then Q, then −∂D/∂q̇.
//! assert_eq!(DrivenPendulum::EQUATIONS, "theta: m l² θ̈ = −m l g sin(θ) + a cos(w t) − b θ̇");
//! // Neither the energy nor the momentum is conserved here.
//! assert!(!<DrivenPendulum as Lagrangian<1>>::ENERGY_CONSERVED);
//! ```
//!
//! The conservation flags follow a syntactic rule in both modes: `CYCLIC[i]` when qᵢ appears
//! in none of L, D and Q; `MOMENTUM_CONSERVED[i]` when qᵢ is cyclic, q̇ᵢ does not appear in D and
//! the i-th entry of the array `fn forces` ends with is a literal zero (`0.0`); `ENERGY_CONSERVED`
//! when L has no explicit t, there is no D, Q is absent or every entry a literal zero, and no
//! constraint of `fn constraints` moves (one that reads `t: Time` does work on the system).
//! `AUTONOMOUS` still means that L has no explicit t. The symbolic mode also reads them from the
//! derived expressions: `CYCLIC[i]` when ∂L/∂qᵢ, ∂D/∂qᵢ and every ∂Qⱼ/∂qᵢ vanish identically
//! (expanded, and reduced modulo sin²x + cos²x = 1), so a coordinate that leaves L only through an
//! identity is cyclic (ψ in a heavy top written from its rotation matrix); `AUTONOMOUS` when
//! ∂L/∂t vanishes; `MOMENTUM_CONSERVED[i]` and `ENERGY_CONSERVED` when, besides, Qᵢ − ∂D/∂q̇ᵢ
//! (every i for the energy) vanishes. A flag is true when either rule says so; neither says true
//! where it does not hold (an expression too large to expand is not simplified, and its flag
//! keeps the syntactic answer). In symbolic mode `fn forces` must end in an array literal.
//!
//! ## Holonomic constraints
//!
//! `fn constraints` in the same impl block, in both modes, declares K holonomic constraints
//! g(q, t) = 0 (returns `[Scalar; K]`, K a number ≥ 1, and its body ends in an array literal of
//! K entries) and makes the macro also emit `impl Holonomic<N, K>`: the equations of motion
//! become M q̈ = f + Gᵀλ with G = ∂g/∂q and the multipliers λ
//! ([`Holonomic::constrained_accelerations`]). Its coordinate parameters follow the rule above;
//! the constraints depend on the positions only, so every velocity is bound as `_` (`(x, _)`),
//! and a moving constraint declares `t: Time`. `CONSTRAINED_COORDINATES[i]` is `true` when qᵢ
//! appears in the body (a `Coord3` marks its three slots) and `SCLERONOMIC` when it does not use
//! the time. The body is evaluated generically over the runtime's jets in both modes.
//!
//! ```
//! use lagrange::prelude::*;
//!
//! /// A plane pendulum written in x, y, the rod a constraint.
//! pub struct Pendulum { pub m: f64, pub g: f64, pub l: f64 }
//!
//! #[lagrangian]
//! impl Pendulum {
//!     fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
//!         0.5 * self.m * (x_dot * x_dot + y_dot * y_dot) - self.m * self.g * y
//!     }
//!     /// Holonomic constraints g(q, t) = 0, one entry per constraint.
//!     fn constraints(&self, (x, _): Coord, (y, _): Coord) -> [Scalar; 1] {
//!         [x * x + y * y - self.l * self.l]
//!     }
//! }
//!
//! let p = Pendulum { m: 2.0, g: 9.81, l: 1.5 };
//! // At the bottom moving at 3 m/s: the centripetal acceleration v²/l, upwards.
//! let (a, lambda) = p.constrained_accelerations(&[0.0, -1.5], &[3.0, 0.0], 0.0).unwrap();
//! assert!(a[0].abs() < 1e-12 && (a[1] - 9.0 / 1.5).abs() < 1e-12);
//! // Gᵀλ = (2x, 2y) λ is the rod's pull, m g + m v²/l.
//! assert!((-3.0 * lambda[0] - (2.0 * 9.81 + 2.0 * 9.0 / 1.5)).abs() < 1e-12);
//! assert_eq!(<Pendulum as lagrange::Holonomic<2, 1>>::CONSTRAINED_COORDINATES, [true, true]);
//! assert!(<Pendulum as lagrange::Holonomic<2, 1>>::SCLERONOMIC);
//! ```
//!
//! ## Geometry: velocities and rotations
//!
//! [`geometry::velocity`] gives the time derivative of a position written from the coordinates,
//! and [`geometry::Rotation`] (elementary rotations, a unit quaternion, products, `r * v`,
//! `transpose`) with [`geometry::angular_velocity`] (space axes, Ṙ Rᵀ = ω̂) and
//! [`geometry::body_angular_velocity`] (body axes, Rᵀ Ṙ = ω̂) give a rigid body's kinetic energy
//! from its orientation. Both modes; the symbolic mode simplifies sin² + cos² = 1, so the heavy
//! top written from its rotation prints eq. 92's equations:
//!
//! ```
//! use lagrange::prelude::*;
//!
//! /// The symmetric heavy top from its rotation R = R_z(φ) R_x(θ) R_z(ψ).
//! pub struct Top { pub i_perp: f64, pub i_par: f64, pub mgl: f64 }
//!
//! #[lagrangian]
//! impl Top {
//!     fn lagrangian(&self, (theta, theta_dot): Coord, (phi, phi_dot): Coord, (psi, psi_dot): Coord) -> Scalar {
//!         let r = Rotation::about_z(phi) * Rotation::about_x(theta) * Rotation::about_z(psi);
//!         let w = body_angular_velocity(&r);
//!         0.5 * (self.i_perp * (w.x * w.x + w.y * w.y) + self.i_par * w.z * w.z)
//!             - self.mgl * (r * Vector3::z()).z
//!     }
//! }
//!
//! assert_eq!(<Top as Lagrangian<3>>::CYCLIC, [false, true, true]);
//! let top = Top { i_perp: 1.3, i_par: 0.7, mgl: 2.0 };
//! let (q, v) = ([0.8, 0.1, 0.2], [0.3, 1.1, 4.0]);
//! let a = top.accelerations(&q, &v, 0.0).unwrap();
//! // eq. 92's θ equation: I⊥ θ̈ = I⊥ φ̇² sin θ cos θ − I∥ ω₃ φ̇ sin θ + m g l sin θ, ω₃ = φ̇ cos θ + ψ̇
//! let (s, c) = q[0].sin_cos();
//! let w3 = v[1] * c + v[2];
//! let want = (1.3 * v[1] * v[1] * s * c - 0.7 * w3 * v[1] * s + 2.0 * s) / 1.3;
//! assert!((a[0] - want).abs() < 1e-12);
//! ```
//!
//! And the double pendulum from the positions of its bobs (here in the jets mode):
//!
//! ```
//! use lagrange::prelude::*;
//!
//! pub struct Double { pub m: f64, pub l: f64, pub g: f64 }
//!
//! #[lagrangian(mode = "jets")]
//! impl Double {
//!     fn lagrangian(&self, (a, a_dot): Coord, (b, b_dot): Coord) -> Scalar {
//!         let p1 = Vector3::new(self.l * a.sin(), -self.l * a.cos(), 0.0 * a);
//!         let p2 = p1 + Vector3::new(self.l * b.sin(), -self.l * b.cos(), 0.0 * b);
//!         let (v1, v2) = (velocity(p1), velocity(p2));
//!         0.5 * self.m * (v1.norm_squared() + v2.norm_squared()) - self.m * self.g * (p1.y + p2.y)
//!     }
//! }
//!
//! let d = Double { m: 1.0, l: 1.0, g: 9.81 };
//! // released from rest at (a, b) = (0.5, 0): the closed form of the first instant,
//! // 2 ä + b̈ cos a = −2 g sin a and ä cos a + b̈ = 0.
//! let acc = d.accelerations(&[0.5, 0.0], &[0.0, 0.0], 0.0).unwrap();
//! let c = 0.5_f64.cos();
//! let a_dd = -2.0 * 9.81 * 0.5_f64.sin() / (2.0 - c * c);
//! assert!((acc[0] - a_dd).abs() < 1e-12 && (acc[1] + a_dd * c).abs() < 1e-12);
//! ```
//!
//! ## Contacts and impacts
//!
//! An optional `fn contacts(&self, (x, _): Coord, ..., t: Time) -> [Contact; K]` declares K
//! unilateral contacts, each from its gap g(q, t) ≥ 0 written from the positions
//! ([`Contact::gap`], with `.restitution(e)`, `.sticking(s)` for a contact point that does not
//! slide, `.named(..)`), and makes the macro also emit `impl Unilateral<N, K>`.
//! [`Simulation::new`] runs it with them: impacts by the impact law derived from M and the gaps'
//! gradients, contacts at rest acting as constraints with a normal force λ ≥ 0 until it
//! vanishes, a Zeno accumulation of impacts resolved to resting contact (README "Impacts").
//!
//! ```
//! use lagrange::prelude::*;
//!
//! /// A ball above the floor y = 0, restitution e.
//! pub struct Ball { pub m: f64, pub g: f64, pub e: f64 }
//!
//! #[lagrangian]
//! impl Ball {
//!     fn lagrangian(&self, (y, y_dot): Coord) -> Scalar {
//!         0.5 * self.m * y_dot * y_dot - self.m * self.g * y
//!     }
//!     fn contacts(&self, (y, _): Coord) -> [Contact; 1] {
//!         [Contact::gap(y).restitution(self.e).named("floor")]
//!     }
//! }
//!
//! let ball = Ball { m: 1.0, g: 9.81, e: 0.5 };
//! let tr = Simulation::new(&ball, [1.0], [0.0]).until(2.0).run().unwrap();
//! // First impact at t₁ = √(2h/g), leaving at e times the speed it arrived with.
//! let t1 = (2.0 / 9.81_f64).sqrt();
//! assert!((tr.jumps[0].t - t1).abs() < 1e-10);
//! assert!((tr.jumps[0].after.1[0] + 0.5 * tr.jumps[0].before.1[0]).abs() < 1e-12);
//! // The bounces accumulate at t₁ (1 + e)/(1 − e) = 3 t₁; from there it rests, λ = m g.
//! let z = tr.zeno.as_ref().unwrap();
//! assert!((z.t_accumulation - 3.0 * t1).abs() < 1e-9);
//! assert!((tr.lambda.last().unwrap()[0] - 9.81).abs() < 1e-9);
//! ```
//!
//! ## What the default (symbolic) mode accepts
//!
//! The body is lowered to an expression graph at compile time. Besides arithmetic, `let`
//! bindings (also `let mut` with `+=`), tuples, `Vector3` algebra (`dot`, `cross`, `norm`,
//! `norm_squared`, `normalize`, `scale`, `component_mul`) and `if` on parameters, it takes:
//!
//! - every function of the jets (the elementary ones are the rows of `functions/src/lib.rs`): `sin cos tan asin acos atan sinh cosh tanh asinh acosh atanh
//!   exp exp2 exp_m1 ln ln_1p log10 log2 sqrt cbrt abs signum powi powf atan2 hypot recip
//!   mul_add sin_cos`, and `max`, `min`, `clamp` (exact, with the jets' one-sided derivative at a
//!   tie: the receiver wins, and |x| has slope +1 at ±0);
//! - constants: `std::f64::consts::*`, `core::f64::consts::*`, `f64::EPSILON`, `f64::MAX`;
//! - any code that uses parameters only (`Self::K`, `self.n as f64`, `self.k[i]`, a `match` on a
//!   parameter, a function of parameters): evaluated once per call, as written, and printed as
//!   written in `EQUATIONS`.
//!
//! - coordinate arrays: `(q, q_dot): Coords<6>` binds `q` and `q_dot` as `[Scalar; 6]` (the
//!   length an integer literal), named `q[0]` … `q[5]` in `COORDINATES` and `EQUATIONS`;
//!   `Coord`, `Coord3` and `Coords<K>` mix in one signature;
//! - `for` loops, unrolled when the macro expands: over ranges whose bounds it knows (literals,
//!   loop variables, `q.len()`, integer `const`s of the impl block written `Self::N`), over
//!   arrays, and over `.iter()`, `.enumerate()`, `.zip(..)` (also with an `f64` array field,
//!   `self.m.iter()`, stopping at the shorter side like Rust's `zip`: the field's length is read
//!   at run time, and `EQUATIONS` print its elements as if it were long enough), `.rev()`,
//!   `.skip(k)`, `.take(k)`, `.step_by(k)`; `.map(..)`, `.sum()`,
//!   `.product()` and `.fold(..)` on them; indexing with constants and loop variables; local
//!   arrays (`[0.0; 3]`, written element by element); `if` on a loop variable;
//! - helpers, inlined: methods of the same impl block written with `Scalar`
//!   (`fn kinetic(&self, m: f64, v: Scalar) -> Scalar`, called as `self.kinetic(m, v)` or
//!   `Self::kinetic(self, m, v)`; both modes make them generic, so they stay ordinary methods,
//!   callable with `f64`), closures, and nested `fn` items in the body;
//! - at most 100 000 loop iterations and inlined calls in total per body (`fn lagrangian`,
//!   `fn dissipation`, `fn forces` each): past that (1000 × 1000 nested loops, a helper that
//!   calls itself twice per level) the macro stops with a compile error at the loop or call that
//!   crosses it, saying to use `#[lagrangian(mode = "jets")]`.
//!
//! A call of a function the macro cannot see with the state, recursion, or an `if`/`match` on
//! the state is a compile error at that expression that says to use
//! `#[lagrangian(mode = "jets")]`, where anything Rust can compute generically over `Scalar`
//! works. `EQUATIONS` and `EQUATIONS_LATEX` are each one string, one line per coordinate (a very
//! large system says from which equation on it is too large to print).
//!
//! ```
//! use lagrange::prelude::*;
//!
//! /// Three beads on a ring of springs, written with an array, a loop, a helper and a closure.
//! pub struct Beads { pub m: [f64; 3], pub k: f64 }
//!
//! #[lagrangian]
//! impl Beads {
//!     fn spring(&self, a: Scalar, b: Scalar) -> Scalar {
//!         0.5 * self.k * (a - b).powi(2)
//!     }
//!     fn lagrangian(&self, (x, x_dot): Coords<3>) -> Scalar {
//!         let kinetic = |m: f64, v: Scalar| 0.5 * m * v * v;
//!         let mut l = 0.0;
//!         for (i, (v, m)) in x_dot.iter().zip(self.m.iter()).enumerate() {
//!             l += kinetic(*m, *v) - self.spring(x[i], x[(i + 1) % 3]);
//!         }
//!         l
//!     }
//! }
//!
//! let b = Beads { m: [1.0, 2.0, 4.0], k: 8.0 };
//! assert_eq!(Beads::COORDINATES, ["x[0]", "x[1]", "x[2]"]);
//! // Bead 0 pulled by its neighbours at 1 and −1: (8 (1 − 0) + 8 (−1 − 0)) / 1 = 0.
//! let a = b.accelerations(&[0.0, 1.0, -1.0], &[0.0; 3], 0.0).unwrap();
//! assert_eq!(a, [0.0, 8.0 * (-1.0 - 1.0 + 0.0 - 1.0) / 2.0, 8.0 * (0.0 + 1.0 + 1.0 + 1.0) / 4.0]);
//! assert!(Beads::EQUATIONS.contains("x[1]: m[1] x\u{308}[1] = k x[0]")); // ẍ: x and a combining ¨
//! ```
//!
//! ```
//! use lagrange::prelude::*;
//!
//! #[derive(Clone, Copy)]
//! pub enum Stop { Soft, Hard }
//!
//! /// A mass between two stops: a one-sided spring beyond |x| = 1, stiffness by a `match`.
//! pub struct Bumper { pub m: f64, pub stop: Stop }
//!
//! #[lagrangian]
//! impl Bumper {
//!     const GAP: f64 = 1.0;
//!     fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {
//!         let k = match self.stop { Stop::Soft => 10.0, Stop::Hard => 1000.0 };
//!         let overlap = (x.abs() - Self::GAP).max(0.0);
//!         0.5 * self.m * x_dot.powi(2) - 0.5 * k * overlap.powi(2)
//!     }
//! }
//!
//! let b = Bumper { m: 2.0, stop: Stop::Soft };
//! assert_eq!(b.accelerations(&[0.5], &[1.0], 0.0).unwrap(), [0.0]); // between the stops
//! assert_eq!(b.accelerations(&[1.5], &[1.0], 0.0).unwrap(), [-2.5]); // −k (|x| − 1) / m
//! ```
#![forbid(unsafe_code)]
#![warn(missing_docs)]

/// Derives `impl Lagrangian<N>` from `fn lagrangian(&self, (q, q_dot): Coord, ...) -> Scalar`
/// (and the optional `fn dissipation` and `fn forces`) written as plain Rust. See the crate
/// documentation above.
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
/// `fn constraints` (`VELOCITY_ROWS = K`), so `Simulation::new` runs both.
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
/// `impl Unilateral<N, K>`; `Simulation::new` runs the system with them (see the crate docs).
///
/// # Scene
///
/// An optional `fn scene(&self, (x, _): Coord, ..., t: Time) -> Scene` says what the system
/// looks like at a state: shapes placed from the positions with `Rotation` and `Vector3`
/// (`Scene::new().rod("arm", a, b, 0.02, Rgb::GREY).sphere("bob", b, 0.1, Rgb::RED)`). It takes
/// `lagrangian`'s coordinates with the velocities as `_`, like `fn constraints`, and makes the
/// macro emit `impl Visual<N>`, which `Trajectory::write_gltf` and `Trajectory::write_html`
/// animate (README, "Seeing it move").
pub use lagrange_macros::lagrangian;

// What users build with, in the index.
pub use lagrange_runtime::{animation, ensemble, geometry, linearize, rigid, scene};
pub use lagrange_runtime::{
    equilibrium, ConstrainedLinearization, Linearization, LinearizationError, Linearize,
    LinearizeConstrained, Mode, Stability,
};
pub use lagrange_runtime::{
    ConstraintResidual, DenseOutputError, Direction, Drift, Event, EventHit, Invariants, Jump,
    Method, NamedInvariants, PartialTrajectory, Sample, Simulation, SimulationError, Stats,
    Stiffness, Trajectory, Zeno, INVARIANT_FLOOR,
};
pub use lagrange_runtime::{
    Contact, DynamicsError, Ensemble, Holonomic, Lagrangian, Member, Nonholonomic, Scalar,
    Unilateral, Velocity,
};
pub use lagrange_runtime::{SMatrix, Vector3};
// How a hand-written impl with constraints or contacts says so (`Lagrangian::declared`).
pub use lagrange_runtime::lagrangian::Declared;
// Sensitivities, periodic orbits and Lyapunov exponents.
pub use lagrange_runtime::sensitivity;
pub use lagrange_runtime::{DMatrix, EventSensitivity, Sensitivities, Sensitivity};
// First-order forward mode through the compiled kernels (`Tangent<K>`), what the sensitivities
// differentiate the generated code with.
pub use lagrange_runtime::tangent;

// The machinery under them: reachable (tests, benches and curious readers use it), not in the
// index.
#[doc(hidden)]
pub use lagrange_runtime::{
    constraints, contact, eom, error, impact, integrate, jet, lagrangian, lanes, linalg, real,
    taylor,
};
#[doc(hidden)]
pub use lagrange_runtime::{el_jet, hessian_jet, solve_mass_matrix};

/// Marker for one generalized coordinate in a `#[lagrangian]` signature: `(x, x_dot): Coord`.
///
/// The macro replaces it; it is never constructed.
#[derive(Debug, Clone, Copy)]
pub enum Coord {}
/// Marker for three coordinates bound as `Vector3<Scalar>`: `(r, r_dot): Coord3`.
///
/// The macro replaces it; it is never constructed.
#[derive(Debug, Clone, Copy)]
pub enum Coord3 {}
/// Marker for `K` coordinates bound as arrays `[Scalar; K]`: `(q, q_dot): Coords<6>`.
///
/// `K` is an integer literal; the slots are named `q[0]` … `q[K-1]` in `COORDINATES` and in the
/// printed equations. The macro replaces it; it is never constructed.
#[derive(Debug, Clone, Copy)]
pub enum Coords<const K: usize> {}
/// Marker for explicit time in a `#[lagrangian]` signature: `t: Time`.
///
/// The macro replaces it; it is never constructed.
#[derive(Debug, Clone, Copy)]
pub enum Time {}

/// Everything a user of `#[lagrangian]` needs: `use lagrange::prelude::*;`.
pub mod prelude {
    pub use crate::{lagrangian, Coord, Coord3, Coords, Time};
    pub use lagrange_runtime::geometry::{
        angular_velocity, body_angular_velocity, velocity, Rotation,
    };
    pub use lagrange_runtime::scene::{Rgb, Scene, Visual};
    pub use lagrange_runtime::{
        equilibrium, Linearization, LinearizationError, Linearize, LinearizeConstrained, Stability,
    };
    pub use lagrange_runtime::{Contact, Ensemble, Member, Nonholonomic, Unilateral, Velocity};
    pub use lagrange_runtime::{DynamicsError, Holonomic, Lagrangian, SMatrix, Scalar, Vector3};
    pub use lagrange_runtime::{Event, EventHit, Method, Simulation, SimulationError, Trajectory};
    pub use lagrange_runtime::{Sensitivities, Sensitivity};
}

/// The only door through which code generated by `#[lagrangian]` reaches the runtime.
/// Not public API: it may change in any release.
#[doc(hidden)]
pub mod __private {
    // What the generated code names, and nothing else (each path is used by `lagrange-macros`).
    pub use lagrange_runtime::constraints::{jet_constraint_rows, splice_velocity_rows};
    pub use lagrange_runtime::contact::EqualityRows;
    pub use lagrange_runtime::jet::{timed_state, Timed};
    pub use lagrange_runtime::lagrangian::{kernel_params, Compiled, Declared};
    pub use lagrange_runtime::mix::*;
    pub use lagrange_runtime::real::Real;
    pub use lagrange_runtime::scene::{Scene, Visual};
    pub use lagrange_runtime::Nonholonomic;
    pub use lagrange_runtime::{eom, linalg, taylor};
    pub use lagrange_runtime::{solve_mass_matrix, DynamicsError, Holonomic, Lagrangian};
    pub use lagrange_runtime::{Contact, SMatrix, Scalar, Unilateral, Vector3};
    pub use nalgebra;
}
