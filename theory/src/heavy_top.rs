//! The symmetric heavy top of the reference text's section D (eqs. 92–102), in closed form and by
//! precise quadrature.
//!
//! Conventions (eq. 92): θ is the **polar** angle of the symmetry axis from the upward vertical, φ
//! its **azimuth** (the text's first paragraph of section D swaps the two names), ψ the spin about
//! the axis, and
//!
//! L = I⊥/2 (θ̇² + φ̇² sin²θ) + I∥/2 (ψ̇ + φ̇ cos θ)² − m g l cos θ.
//!
//! From a state, [`Constants::from_state`] computes the conserved L∥ (eq. 93), L_φ (eq. 94) and E
//! (eq. 95) and the reduced constants of the nutation ([`Nutation`]): Ω = L∥/I⊥, p0 = L_φ/L∥,
//! ω0 = √(mgl/I⊥) and p_E = (E − L∥²/2I∥)/mgl. In p = cos θ the nutation obeys eq. 96,
//! ṗ² = f(p) = 2ω0²(1 − p²)(p_E − p) − Ω²(p0 − p)², a cubic with roots p1 ≤ p2 ≤ p3
//! ([`Nutation::roots`]); the axis nutates between p1 and p2.
//!
//! - [`Nutation::period`]: eq. 97 in closed form, T = 2π / (ω0 · AGM(1, k′) · √(2(p3 − p1))) with
//!   k′² = (p3 − p2)/(p3 − p1) (the complete elliptic integral K via the arithmetic–geometric mean).
//! - [`Nutation::mean_precession_rate`]: ⟨φ̇⟩ over one nutation period, the average of
//!   φ̇ = Ω(p0 − p)/(1 − p²) weighted by dt = dp/√f, computed after the substitution
//!   p = p1 + (p2 − p1) sin²u (which removes the inverse-square-root end points) by adaptive
//!   Gauss–Kronrod quadrature to about 1e-13 relative.
//!
//! The roots are found from the cubic written around the state's own p (x = p − cos θ), with the
//! coefficients computed without cancellation, so nearly double roots (a top released close to the
//! vertical, a nearly regular precession) keep their small separations accurate.
//!
//! The fast-top approximations of Example 2 are [`fast_top_cos_theta`] (eq. 101) and
//! [`fast_top_precession_rate`] (eq. 102 as corrected in `docs/ERRATA.md`:
//! φ̇ ≈ (mgl/L∥)(1 − cos Ωt), so ⟨φ̇⟩ ≈ mgl/L∥, not the printed mgl/(2L∥)).
//!
//! ```
//! use lagrange_theory::heavy_top::{Constants, Motion, Top};
//! let top = Top { i_perp: 1.0, i_par: 0.6, mgl: 1.0 };
//! // θ0 = 1, φ̇0 = −0.5, ψ̇0 = 8: loops (φ̇ changes sign during a nutation).
//! let c = Constants::from_state(&top, &[1.0, 0.0, 0.0], &[0.0, -0.5, 8.0]).unwrap();
//! let n = c.nutation;
//! let r = n.roots().unwrap();
//! assert!(r.p1 < r.p2 && r.p2 < 1.0 && 1.0 < r.p3);
//! assert_eq!(n.motion().unwrap(), Motion::Loops);
//! let t = n.period().unwrap();
//! assert!(t > 0.0 && t < 2.0);
//! ```

use std::f64::consts::{FRAC_PI_2, PI};
use std::fmt;

/// The physical parameters of a symmetric heavy top: the two principal moments of inertia about
/// the fixed point and m g l.
///
/// ```
/// let top = lagrange_theory::heavy_top::Top { i_perp: 1.0, i_par: 0.5, mgl: 2.0 };
/// assert_eq!(top.omega0(), 2.0_f64.sqrt());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Top {
    /// I⊥, the moment of inertia about any axis through the fixed point perpendicular to the
    /// symmetry axis.
    pub i_perp: f64,
    /// I∥, the moment of inertia about the symmetry axis.
    pub i_par: f64,
    /// m g l: mass × gravity × distance from the fixed point to the centre of mass.
    pub mgl: f64,
}

impl Top {
    /// ω0 = √(mgl/I⊥), the small-oscillation frequency of the non-spinning top hanging down.
    ///
    /// ```
    /// let top = lagrange_theory::heavy_top::Top { i_perp: 4.0, i_par: 1.0, mgl: 1.0 };
    /// assert_eq!(top.omega0(), 0.5);
    /// ```
    pub fn omega0(&self) -> f64 {
        (self.mgl / self.i_perp).sqrt()
    }

    fn validate(&self) -> Result<(), TheoryError> {
        for (name, value) in [
            ("i_perp", self.i_perp),
            ("i_par", self.i_par),
            ("mgl", self.mgl),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(TheoryError::InvalidParameter { name, value });
            }
        }
        Ok(())
    }
}

/// Why a theoretical quantity could not be computed.
///
/// ```
/// use lagrange_theory::heavy_top::{Constants, TheoryError, Top};
/// let top = Top { i_perp: 1.0, i_par: 1.0, mgl: 1.0 };
/// // No spin about the axis: p0 = L_φ / L∥ is undefined.
/// let err = Constants::from_state(&top, &[1.0, 0.0, 0.0], &[0.0, 0.0, 0.0]).unwrap_err();
/// assert_eq!(err, TheoryError::NoSpin);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TheoryError {
    /// A parameter is not finite and positive (the theory needs I⊥, I∥, mgl > 0, ω0 > 0).
    InvalidParameter {
        /// Which parameter.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// The state has a non-finite component.
    NonFiniteState,
    /// L∥ = 0: the reduced constants Ω, p0 of the text are undefined.
    NoSpin,
    /// The cubic of eq. 96 has no interval p1 ≤ p ≤ p2 where f ≥ 0 (constants not from a motion).
    NoNutationInterval,
}

impl fmt::Display for TheoryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TheoryError::InvalidParameter { name, value } => {
                write!(
                    f,
                    "heavy top: parameter {name} = {value} must be finite and > 0"
                )
            }
            TheoryError::NonFiniteState => write!(f, "heavy top: the state is not finite"),
            TheoryError::NoSpin => write!(
                f,
                "heavy top: L∥ = 0, so Ω = L∥/I⊥ = 0 and p0 = L_φ/L∥ is undefined"
            ),
            TheoryError::NoNutationInterval => write!(
                f,
                "heavy top: the cubic of eq. 96 has no interval p1 ≤ p ≤ p2 with f(p) ≥ 0"
            ),
        }
    }
}

impl std::error::Error for TheoryError {}

/// The conserved quantities of a heavy-top state and the reduced constants of its nutation.
///
/// ```
/// use lagrange_theory::heavy_top::{Constants, Top};
/// let top = Top { i_perp: 2.0, i_par: 1.0, mgl: 3.0 };
/// let c = Constants::from_state(&top, &[0.5, 0.1, 0.2], &[0.3, 0.4, 5.0]).unwrap();
/// let (s, k) = 0.5_f64.sin_cos();
/// let l_par = 1.0 * (5.0 + 0.4 * k);
/// assert!((c.l_par - l_par).abs() < 1e-14);
/// assert!((c.l_phi - (2.0 * 0.4 * s * s + l_par * k)).abs() < 1e-14);
/// assert!((c.nutation.omega - l_par / 2.0).abs() < 1e-14);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Constants {
    /// L∥ = ∂L/∂ψ̇ = I∥(ψ̇ + φ̇ cos θ) (eq. 93).
    pub l_par: f64,
    /// L_φ = ∂L/∂φ̇ = I⊥ φ̇ sin²θ + L∥ cos θ (eq. 94).
    pub l_phi: f64,
    /// E = I⊥/2 (θ̇² + φ̇² sin²θ) + L∥²/2I∥ + mgl cos θ (eq. 95).
    pub energy: f64,
    /// Ω, p0, ω0, p_E and the cubic of eq. 96.
    pub nutation: Nutation,
}

impl Constants {
    /// The constants of the motion through the state q = (θ, φ, ψ), q̇ = (θ̇, φ̇, ψ̇).
    ///
    /// p0 and p_E are computed as cos θ + φ̇ sin²θ/Ω and cos θ + (θ̇² + φ̇² sin²θ)/2ω0², which
    /// equal L_φ/L∥ and (E − L∥²/2I∥)/mgl without their cancellations.
    ///
    /// ```
    /// use lagrange_theory::heavy_top::{Constants, Top};
    /// let top = Top { i_perp: 1.0, i_par: 0.5, mgl: 4.0 };
    /// // Released from rest (θ̇ = φ̇ = 0): p0 = p_E = cos θ (Example 2 of the text).
    /// let c = Constants::from_state(&top, &[0.7, 0.0, 0.0], &[0.0, 0.0, 30.0]).unwrap();
    /// assert_eq!(c.nutation.p0, 0.7_f64.cos());
    /// assert_eq!(c.nutation.p_e, 0.7_f64.cos());
    /// assert_eq!(c.nutation.omega0, 2.0);
    /// ```
    pub fn from_state(top: &Top, q: &[f64; 3], qdot: &[f64; 3]) -> Result<Self, TheoryError> {
        top.validate()?;
        if !(q.iter().chain(qdot.iter()).all(|x| x.is_finite())) {
            return Err(TheoryError::NonFiniteState);
        }
        let (sin_t, cos_t) = q[0].sin_cos();
        let (theta_dot, phi_dot, psi_dot) = (qdot[0], qdot[1], qdot[2]);
        let s2 = sin_t * sin_t;
        let l_par = top.i_par * (psi_dot + phi_dot * cos_t);
        let l_phi = top.i_perp * phi_dot * s2 + l_par * cos_t;
        let transverse = theta_dot * theta_dot + phi_dot * phi_dot * s2;
        let energy =
            top.i_perp / 2.0 * transverse + l_par * l_par / (2.0 * top.i_par) + top.mgl * cos_t;
        if l_par == 0.0 {
            return Err(TheoryError::NoSpin);
        }
        let omega = l_par / top.i_perp;
        let omega0_sq = top.mgl / top.i_perp;
        let omega0 = omega0_sq.sqrt();
        let d0 = phi_dot * s2 / omega;
        let de = transverse / (2.0 * omega0_sq);
        let r = omega * omega / (2.0 * omega0_sq);
        // 1 − cos θ and 1 + cos θ without cancellation.
        let (one_minus, one_plus) = if cos_t >= 0.0 {
            (s2 / (1.0 + cos_t), 1.0 + cos_t)
        } else {
            (1.0 - cos_t, s2 / (1.0 - cos_t))
        };
        // f/2ω0² around x = p − cos θ; the constant term is ṗ²/2ω0² = sin²θ θ̇²/2ω0² exactly.
        let cubic = Shifted {
            p_ref: cos_t,
            one_minus,
            one_plus,
            d0,
            a: 2.0 * cos_t - de - r,
            b: -s2 - 2.0 * cos_t * de + 2.0 * r * d0,
            c: s2 * theta_dot * theta_dot / (2.0 * omega0_sq),
        };
        Ok(Constants {
            l_par,
            l_phi,
            energy,
            nutation: Nutation {
                omega,
                p0: cos_t + d0,
                omega0,
                p_e: cos_t + de,
                cubic,
            },
        })
    }
}

/// The reduced constants Ω, p0, ω0, p_E that determine the nutation (eqs. 94–97), with the cubic
/// of eq. 96.
///
/// ```
/// use lagrange_theory::heavy_top::Nutation;
/// let n = Nutation::new(10.0, 0.5, 1.0, 0.5).unwrap();
/// assert_eq!(n.f(0.5), 0.0); // released from rest at p = p0 = p_E
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nutation {
    /// Ω = L∥/I⊥ (signed: negative for a negative spin).
    pub omega: f64,
    /// p0 = L_φ/L∥: φ̇ = 0 where cos θ = p0.
    pub p0: f64,
    /// ω0 = √(mgl/I⊥).
    pub omega0: f64,
    /// p_E = (E − L∥²/2I∥)/mgl.
    pub p_e: f64,
    cubic: Shifted,
}

/// f(p)/2ω0² written around p_ref: g(x) = x³ + a x² + b x + c, x = p − p_ref.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Shifted {
    p_ref: f64,
    /// 1 − p_ref.
    one_minus: f64,
    /// 1 + p_ref.
    one_plus: f64,
    /// p0 − p_ref.
    d0: f64,
    a: f64,
    b: f64,
    c: f64,
}

impl Shifted {
    fn g(&self, x: f64) -> f64 {
        ((x + self.a) * x + self.b) * x + self.c
    }
    fn dg(&self, x: f64) -> f64 {
        (3.0 * x + 2.0 * self.a) * x + self.b
    }
    /// A bound on the rounding error of `g(x)`.
    fn g_tol(&self, x: f64) -> f64 {
        let ax = x.abs();
        16.0 * f64::EPSILON * (((ax + self.a.abs()) * ax + self.b.abs()) * ax + self.c.abs())
    }

    /// The three real roots x1 ≤ x2 ≤ x3 of g, with x1 ≤ (local max) ≤ x2 ≤ (local min) ≤ x3.
    fn roots(&self) -> Result<[f64; 3], TheoryError> {
        let (a, b) = (self.a, self.b);
        let disc = a * a - 3.0 * b;
        if disc.is_nan() || disc <= 0.0 {
            return Err(TheoryError::NoNutationInterval);
        }
        // Critical points of g, from g' = 3x² + 2ax + b, in the cancellation-free form.
        let q = -(a + if a >= 0.0 { 1.0 } else { -1.0 } * disc.sqrt());
        let (r1, r2) = (q / 3.0, if q != 0.0 { b / q } else { 0.0 });
        let (xa, xb) = if r1 <= r2 { (r1, r2) } else { (r2, r1) };
        let (ga, gb) = (self.g(xa), self.g(xb));
        if ga < -self.g_tol(xa) || gb > self.g_tol(xb) {
            return Err(TheoryError::NoNutationInterval);
        }
        let double_low = ga <= self.g_tol(xa);
        let double_high = gb >= -self.g_tol(xb);
        let step0 = 1.0 + xa.abs().max(xb.abs());
        let x1 = if double_low {
            xa
        } else {
            let mut lo = xa - step0;
            let mut k = 0;
            while self.g(lo) >= 0.0 && k < 200 {
                lo = xa - (lo - xa).abs() * 2.0;
                k += 1;
            }
            self.bracketed_root(lo, xa, true)
        };
        let x2 = if double_low {
            xa
        } else if double_high {
            xb
        } else {
            self.bracketed_root(xa, xb, false)
        };
        let x3 = if double_high {
            xb
        } else {
            let mut hi = xb + step0;
            let mut k = 0;
            while self.g(hi) <= 0.0 && k < 200 {
                hi = xb + (hi - xb).abs() * 2.0;
                k += 1;
            }
            self.bracketed_root(xb, hi, true)
        };
        // A motion needs −1 ≤ p1 ≤ p2 ≤ 1 (up to the accuracy of a double root).
        let physical = x1 >= -self.one_plus - 1e-7 && x2 <= self.one_minus + 1e-7;
        if !([x1, x2, x3].iter().all(|x| x.is_finite()) && physical) {
            return Err(TheoryError::NoNutationInterval);
        }
        Ok([x1, x2, x3])
    }

    /// The root of g in [lo, hi], where g is monotone (increasing or not): safeguarded Newton.
    fn bracketed_root(&self, mut lo: f64, mut hi: f64, increasing: bool) -> f64 {
        let mut x = 0.5 * (lo + hi);
        for _ in 0..300 {
            let gx = self.g(x);
            if gx == 0.0 {
                return x;
            }
            if (gx > 0.0) == increasing {
                hi = x;
            } else {
                lo = x;
            }
            if hi - lo <= 2.0 * f64::EPSILON * lo.abs().max(hi.abs()) {
                break;
            }
            let d = self.dg(x);
            if d != 0.0 {
                let step = gx / d;
                let newton = x - step;
                if step.abs() <= 2.0 * f64::EPSILON * x.abs() {
                    return newton.clamp(lo, hi);
                }
                if newton > lo && newton < hi {
                    x = newton;
                    continue;
                }
            }
            x = 0.5 * (lo + hi);
        }
        x
    }
}

/// The roots p1 ≤ p2 ≤ p3 of the cubic of eq. 96; the axis nutates between p1 and p2.
///
/// ```
/// use lagrange_theory::heavy_top::Nutation;
/// // Example 1 of the text: p0 = p_E = 1, Ω = ω0: roots −1/2 (= Ω²/2ω0² − 1) and a double 1.
/// let r = Nutation::new(1.0, 1.0, 1.0, 1.0).unwrap().roots().unwrap();
/// assert!((r.p1 + 0.5).abs() < 1e-12 && (r.p2 - 1.0).abs() < 1e-7);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Roots {
    /// Lowest turning point of cos θ (largest θ).
    pub p1: f64,
    /// Highest turning point of cos θ (smallest θ).
    pub p2: f64,
    /// The third root, ≥ 1 for a physical motion.
    pub p3: f64,
}

impl Roots {
    /// The nutation range (θ_min, θ_max) = (acos p2, acos p1), clamped to [0, π].
    ///
    /// ```
    /// use lagrange_theory::heavy_top::Roots;
    /// let r = Roots { p1: 0.0, p2: 1.0, p3: 2.0 };
    /// assert_eq!(r.theta_range(), (0.0, std::f64::consts::FRAC_PI_2));
    /// ```
    pub fn theta_range(&self) -> (f64, f64) {
        (
            self.p2.clamp(-1.0, 1.0).acos(),
            self.p1.clamp(-1.0, 1.0).acos(),
        )
    }
}

/// The shape of the trace of the symmetry axis seen from above.
///
/// ```
/// use lagrange_theory::heavy_top::{Motion, Nutation};
/// // Released from rest: φ̇ = 0 at the top turning point, the trace has cusps.
/// assert_eq!(Nutation::new(5.0, 0.3, 1.0, 0.3).unwrap().motion().unwrap(), Motion::Cusps);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// p1 = p2: steady precession at constant θ.
    RegularPrecession,
    /// p0 outside [p1, p2]: φ̇ keeps its sign, the trace is a wave.
    Wavy,
    /// p0 at a turning point: φ̇ vanishes there, the trace has cusps.
    Cusps,
    /// p1 < p0 < p2: φ̇ changes sign, the trace makes loops.
    Loops,
}

impl Nutation {
    /// The nutation of reduced constants Ω, p0, ω0 (> 0) and p_E, as printed in eqs. 94–96.
    ///
    /// ```
    /// use lagrange_theory::heavy_top::Nutation;
    /// let n = Nutation::new(3.0, 0.2, 1.5, 0.4).unwrap();
    /// assert_eq!((n.omega, n.p0, n.omega0, n.p_e), (3.0, 0.2, 1.5, 0.4));
    /// assert!(Nutation::new(3.0, 0.2, 0.0, 0.4).is_err());
    /// ```
    pub fn new(omega: f64, p0: f64, omega0: f64, p_e: f64) -> Result<Self, TheoryError> {
        if !(omega0.is_finite() && omega0 > 0.0) {
            return Err(TheoryError::InvalidParameter {
                name: "omega0",
                value: omega0,
            });
        }
        if !(omega.is_finite() && p0.is_finite() && p_e.is_finite()) {
            return Err(TheoryError::NonFiniteState);
        }
        if omega == 0.0 {
            return Err(TheoryError::NoSpin);
        }
        let r = omega * omega / (2.0 * omega0 * omega0);
        // Written around p_ref = 0: g(p) = p³ − (p_E + r)p² + (2r p0 − 1)p + p_E − r p0².
        let cubic = Shifted {
            p_ref: 0.0,
            one_minus: 1.0,
            one_plus: 1.0,
            d0: p0,
            a: -p_e - r,
            b: 2.0 * r * p0 - 1.0,
            c: p_e - r * p0 * p0,
        };
        Ok(Nutation {
            omega,
            p0,
            omega0,
            p_e,
            cubic,
        })
    }

    /// The right-hand side of eq. 96: ṗ² = f(p) = 2ω0²(1 − p²)(p_E − p) − Ω²(p0 − p)².
    ///
    /// ```
    /// use lagrange_theory::heavy_top::Nutation;
    /// let n = Nutation::new(2.0, 0.5, 1.0, 0.8).unwrap();
    /// assert!((n.f(0.0) - (2.0 * 0.8 - 4.0 * 0.25)).abs() < 1e-15);
    /// ```
    pub fn f(&self, p: f64) -> f64 {
        2.0 * self.omega0 * self.omega0 * (1.0 - p) * (1.0 + p) * (self.p_e - p)
            - self.omega * self.omega * (self.p0 - p) * (self.p0 - p)
    }

    /// The precession rate at cos θ = p (eq. 94): φ̇ = Ω(p0 − p)/(1 − p²).
    ///
    /// ```
    /// use lagrange_theory::heavy_top::Nutation;
    /// let n = Nutation::new(2.0, 0.5, 1.0, 0.8).unwrap();
    /// assert_eq!(n.precession_rate(0.0), 1.0);
    /// assert_eq!(n.precession_rate(0.5), 0.0);
    /// ```
    pub fn precession_rate(&self, p: f64) -> f64 {
        self.omega * (self.p0 - p) / ((1.0 - p) * (1.0 + p))
    }

    /// The roots p1 ≤ p2 ≤ p3 of the cubic of eq. 96.
    ///
    /// Found by safeguarded Newton iteration bracketed by the cubic's critical points; a double
    /// root (regular precession, or the separatrix of Example 1) is returned twice.
    ///
    /// ```
    /// use lagrange_theory::heavy_top::Nutation;
    /// let n = Nutation::new(4.0, 0.6, 1.0, 0.6).unwrap();
    /// let r = n.roots().unwrap();
    /// for p in [r.p1, r.p2, r.p3] { assert!(n.f(p).abs() < 1e-13); }
    /// assert!(r.p1 < r.p2 && r.p2 <= 1.0 && r.p3 > 1.0);
    /// ```
    pub fn roots(&self) -> Result<Roots, TheoryError> {
        let [x1, x2, x3] = self.cubic.roots()?;
        let p = self.cubic.p_ref;
        Ok(Roots {
            p1: p + x1,
            p2: p + x2,
            p3: p + x3,
        })
    }

    /// The nutation period of eq. 97, T = 2∫_{p1}^{p2} dp/√f(p), in closed form:
    /// T = 2π / (ω0 · AGM(1, k′) · √(2(p3 − p1))), k′² = (p3 − p2)/(p3 − p1).
    ///
    /// Infinite when p2 = p3 (the separatrix: the axis approaches p2 asymptotically).
    ///
    /// ```
    /// use lagrange_theory::heavy_top::Nutation;
    /// // A fast top released from rest: T → 2π/√(Ω² − 4ω0²p0) as Ω/ω0 → ∞.
    /// let n = Nutation::new(100.0, 0.5, 1.0, 0.5).unwrap();
    /// let t = n.period().unwrap();
    /// let approx = 2.0 * std::f64::consts::PI / (1e4_f64 - 2.0).sqrt();
    /// assert!((t / approx - 1.0).abs() < 1e-7);
    /// ```
    pub fn period(&self) -> Result<f64, TheoryError> {
        let [x1, x2, x3] = self.cubic.roots()?;
        let span = x3 - x1;
        let k_prime = ((x3 - x2) / span).sqrt();
        let m = agm(1.0, k_prime);
        if m == 0.0 {
            return Ok(f64::INFINITY);
        }
        Ok(2.0 * PI / (self.omega0 * m * (2.0 * span).sqrt()))
    }

    /// The mean precession rate over one nutation period, ⟨φ̇⟩ = (2/T)∫_{p1}^{p2} φ̇(p) dp/√f(p),
    /// by adaptive Gauss–Kronrod quadrature after the substitution p = p1 + (p2 − p1) sin²u.
    ///
    /// ```
    /// use lagrange_theory::heavy_top::Nutation;
    /// // Fast top released from rest: ⟨φ̇⟩ → ω0²/Ω = mgl/L∥ (not mgl/2L∥, see docs/ERRATA.md).
    /// let n = Nutation::new(100.0, 0.5, 1.0, 0.5).unwrap();
    /// let rate = n.mean_precession_rate().unwrap();
    /// assert!((rate / 0.01 - 1.0).abs() < 1e-3);
    /// ```
    pub fn mean_precession_rate(&self) -> Result<f64, TheoryError> {
        let [x1, x2, x3] = self.cubic.roots()?;
        let c = &self.cubic;
        let (width, gap) = (x2 - x1, x3 - x2);
        let phi_dot = |x: f64| self.omega * (c.d0 - x) / ((c.one_minus - x) * (c.one_plus + x));
        if width == 0.0 {
            return Ok(phi_dot(x1));
        }
        // dt ∝ w(u) du with w = 1/√(p3 − p); ∫_0^{π/2} w du = K(k)/√(p3 − p1) exactly.
        let integrand = |u: f64| {
            let (s, co) = u.sin_cos();
            let x = x1 + width * s * s;
            phi_dot(x) / (gap + width * co * co).sqrt()
        };
        let num = gauss_kronrod_adaptive(integrand, 0.0, FRAC_PI_2, 1e-14);
        let den = FRAC_PI_2 / (agm(1.0, (gap / (x3 - x1)).sqrt()) * (x3 - x1).sqrt());
        Ok(num / den)
    }

    /// Classifies the trace of the axis: regular precession (p2 − p1 ≤ 1e-10), waves, cusps
    /// (p0 within 1e-9 (p2 − p1) of a turning point) or loops.
    ///
    /// ```
    /// use lagrange_theory::heavy_top::{Motion, Nutation};
    /// assert_eq!(Nutation::new(5.0, 0.3, 1.0, 0.5).unwrap().motion().unwrap(), Motion::Loops);
    /// assert_eq!(Nutation::new(5.0, 0.3, 1.0, 0.29).unwrap().motion().unwrap(), Motion::Wavy);
    /// ```
    pub fn motion(&self) -> Result<Motion, TheoryError> {
        let [x1, x2, _] = self.cubic.roots()?;
        let width = x2 - x1;
        let d0 = self.cubic.d0;
        Ok(if width <= 1e-10 {
            Motion::RegularPrecession
        } else if (d0 - x2).abs() <= 1e-9 * width || (d0 - x1).abs() <= 1e-9 * width {
            Motion::Cusps
        } else if x1 < d0 && d0 < x2 {
            Motion::Loops
        } else {
            Motion::Wavy
        })
    }
}

/// Eq. 101 (Example 2): cos θ(t) ≈ p0 + (ω0/Ω)²(1 − p0²)(cos Ωt − 1) for a fast top released at
/// rest (θ̇ = φ̇ = 0) from cos θ = p0; the error is O((ω0/Ω)²) relative to the amplitude.
///
/// ```
/// use lagrange_theory::heavy_top::fast_top_cos_theta;
/// let pi = std::f64::consts::PI;
/// assert_eq!(fast_top_cos_theta(0.5, 1.0, 10.0, 0.0), 0.5);
/// assert!((fast_top_cos_theta(0.5, 1.0, 10.0, pi / 10.0) - (0.5 - 2.0 * 0.01 * 0.75)).abs() < 1e-15);
/// ```
pub fn fast_top_cos_theta(p0: f64, omega0: f64, omega: f64, t: f64) -> f64 {
    p0 + (omega0 / omega).powi(2) * (1.0 - p0 * p0) * ((omega * t).cos() - 1.0)
}

/// Eq. 102, corrected: φ̇(t) ≈ (mgl/L∥)(1 − cos Ωt) = (ω0²/Ω)(1 − cos Ωt) for the fast top
/// released at rest, so ⟨φ̇⟩ ≈ mgl/L∥ (the text prints (mgl/L∥)(cos Ωt − 1) and mgl/2L∥).
///
/// ```
/// use lagrange_theory::heavy_top::fast_top_precession_rate;
/// let pi = std::f64::consts::PI;
/// assert_eq!(fast_top_precession_rate(2.0, 40.0, 0.0), 0.0);
/// assert!((fast_top_precession_rate(2.0, 40.0, pi / 40.0) - 0.2).abs() < 1e-15);
/// ```
pub fn fast_top_precession_rate(omega0: f64, omega: f64, t: f64) -> f64 {
    omega0 * omega0 / omega * (1.0 - (omega * t).cos())
}

/// Example 1: the sleeping top (p0 = p_E = 1) with Ω < 2ω0 falls to cos θ = Ω²/2ω0² − 1;
/// `None` when Ω ≥ 2ω0 (it stays up).
///
/// ```
/// use lagrange_theory::heavy_top::sleeping_top_lowest_cos;
/// assert_eq!(sleeping_top_lowest_cos(1.0, 1.0), Some(-0.5));
/// assert_eq!(sleeping_top_lowest_cos(2.5, 1.0), None);
/// ```
pub fn sleeping_top_lowest_cos(omega: f64, omega0: f64) -> Option<f64> {
    (omega.abs() < 2.0 * omega0).then(|| omega * omega / (2.0 * omega0 * omega0) - 1.0)
}

/// Example 1, stable side: a top released at rest at a small θ0 with Ω > 2ω0 nutates up to
/// θ_max ≈ θ0 Ω/√(Ω² − 4ω0²) (small-oscillation bound, error O(θ0²) relative); `None` for Ω ≤ 2ω0.
///
/// ```
/// use lagrange_theory::heavy_top::sleeping_top_max_angle;
/// assert_eq!(sleeping_top_max_angle(1e-3, 5.0, 1.5), Some(1.25e-3));
/// assert_eq!(sleeping_top_max_angle(1e-3, 1.0, 1.0), None);
/// ```
pub fn sleeping_top_max_angle(theta0: f64, omega: f64, omega0: f64) -> Option<f64> {
    let d = omega * omega - 4.0 * omega0 * omega0;
    (d > 0.0).then(|| theta0 * omega.abs() / d.sqrt())
}

/// The arithmetic–geometric mean of two non-negative numbers.
fn agm(mut a: f64, mut b: f64) -> f64 {
    if a == 0.0 || b == 0.0 {
        return 0.0;
    }
    for _ in 0..64 {
        if (a - b).abs() <= 2.0 * f64::EPSILON * a {
            break;
        }
        let next = 0.5 * (a + b);
        b = (a * b).sqrt();
        a = next;
    }
    0.5 * (a + b)
}

/// Gauss–Kronrod (7, 15) nodes on [−1, 1] (QUADPACK `qk15`), non-negative half.
#[allow(clippy::excessive_precision)] // the published QUADPACK digits
const XGK: [f64; 8] = [
    0.991_455_371_120_812_639_206_854_697_526_329,
    0.949_107_912_342_758_524_526_189_684_047_851,
    0.864_864_423_359_769_072_789_712_788_640_926,
    0.741_531_185_599_394_439_863_864_773_280_788,
    0.586_087_235_467_691_130_294_144_845_693_013,
    0.405_845_151_377_397_166_906_606_412_076_961,
    0.207_784_955_007_898_467_600_689_403_773_245,
    0.0,
];
/// Kronrod weights for `XGK`.
#[allow(clippy::excessive_precision)] // the published QUADPACK digits
const WGK: [f64; 8] = [
    0.022_935_322_010_529_224_963_732_008_058_970,
    0.063_092_092_629_978_553_290_700_663_189_204,
    0.104_790_010_322_250_183_839_876_322_541_518,
    0.140_653_259_715_525_918_745_189_590_510_238,
    0.169_004_726_639_267_902_826_583_426_598_550,
    0.190_350_578_064_785_409_913_256_402_421_014,
    0.204_432_940_075_298_892_414_161_999_234_649,
    0.209_482_141_084_727_828_012_999_174_891_714,
];
/// Gauss weights for the nodes `XGK[1], XGK[3], XGK[5], XGK[7]`.
#[allow(clippy::excessive_precision)] // the published QUADPACK digits
const WG: [f64; 4] = [
    0.129_484_966_168_869_693_270_611_432_679_082,
    0.279_705_391_489_276_667_901_467_771_423_780,
    0.381_830_050_505_118_944_950_369_775_488_975,
    0.417_959_183_673_469_387_755_102_040_816_327,
];

/// One G7–K15 panel: (Kronrod value, |Kronrod − Gauss|, ∫|f|).
fn gk15<F: Fn(f64) -> f64>(f: &F, a: f64, b: f64) -> (f64, f64, f64) {
    let (c, h) = (0.5 * (a + b), 0.5 * (b - a));
    let fc = f(c);
    let (mut k, mut g, mut abs) = (WGK[7] * fc, WG[3] * fc, WGK[7] * fc.abs());
    for j in 0..7 {
        let (f1, f2) = (f(c - h * XGK[j]), f(c + h * XGK[j]));
        k += WGK[j] * (f1 + f2);
        abs += WGK[j] * (f1.abs() + f2.abs());
        if j % 2 == 1 {
            g += WG[j / 2] * (f1 + f2);
        }
    }
    (k * h, ((k - g) * h).abs(), abs * h.abs())
}

/// Globally adaptive G7–K15 quadrature of f on [a, b] to `rel` relative to ∫|f|.
fn gauss_kronrod_adaptive<F: Fn(f64) -> f64>(f: F, a: f64, b: f64, rel: f64) -> f64 {
    const MAX_PANELS: usize = 4000;
    let first = gk15(&f, a, b);
    let mut panels = vec![(a, b, first.0, first.1, first.2)];
    loop {
        let (mut err, mut abs, mut worst) = (0.0, 0.0, 0);
        for (i, p) in panels.iter().enumerate() {
            err += p.3;
            abs += p.4;
            if p.3 > panels[worst].3 {
                worst = i;
            }
        }
        if err <= rel * abs || panels.len() >= MAX_PANELS || !err.is_finite() {
            break;
        }
        let (lo, hi, ..) = panels.swap_remove(worst);
        let mid = 0.5 * (lo + hi);
        if !(mid > lo && mid < hi) {
            break;
        }
        let left = gk15(&f, lo, mid);
        let right = gk15(&f, mid, hi);
        panels.push((lo, mid, left.0, left.1, left.2));
        panels.push((mid, hi, right.0, right.1, right.2));
    }
    panels.iter().map(|p| p.2).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Gauss–Chebyshev quadrature of eq. 97 from the roots, independent of the AGM:
    /// ∫ dp/√((p − p1)(p2 − p)) h(p) = (π/n) Σ h(p_k).
    fn period_gauss_chebyshev(n: &Nutation, nodes: usize) -> f64 {
        let r = n.roots().unwrap();
        let (mid, half) = (0.5 * (r.p1 + r.p2), 0.5 * (r.p2 - r.p1));
        let mut sum = 0.0;
        for k in 1..=nodes {
            let p = mid + half * ((2 * k - 1) as f64 * PI / (2 * nodes) as f64).cos();
            sum += 1.0 / (r.p3 - p).sqrt();
        }
        2.0 / (n.omega0 * 2.0_f64.sqrt()) * PI / nodes as f64 * sum
    }

    fn mean_rate_gauss_chebyshev(n: &Nutation, nodes: usize) -> f64 {
        let r = n.roots().unwrap();
        let (mid, half) = (0.5 * (r.p1 + r.p2), 0.5 * (r.p2 - r.p1));
        let (mut num, mut den) = (0.0, 0.0);
        for k in 1..=nodes {
            let p = mid + half * ((2 * k - 1) as f64 * PI / (2 * nodes) as f64).cos();
            let w = 1.0 / (r.p3 - p).sqrt();
            num += n.precession_rate(p) * w;
            den += w;
        }
        num / den
    }

    fn cases() -> Vec<Nutation> {
        let top = Top {
            i_perp: 1.0,
            i_par: 0.6,
            mgl: 1.0,
        };
        let heavy = Top {
            i_perp: 1.0,
            i_par: 0.5,
            mgl: 4.905,
        };
        let below = Top {
            i_perp: 2.3,
            i_par: 0.7,
            mgl: 3.1,
        };
        let states = [
            (top, [1.0, 0.0, 0.0], [0.0, -0.5, 8.0]),   // loops
            (heavy, [0.7, 0.0, 0.0], [0.0, 0.8, 12.0]), // wavy
            (top, [0.8, 0.0, 0.0], [0.0, 0.0, 6.0]),    // cusps
            (below, [2.2, 0.3, 0.0], [0.4, 0.3, -9.0]), // below the horizontal
            (top, [0.3, 0.0, 0.0], [0.0, 0.2, 1.5]),    // slow, large nutation
        ];
        states
            .iter()
            .map(|(t, q, v)| Constants::from_state(t, q, v).unwrap().nutation)
            .collect()
    }

    #[test]
    fn roots_are_roots_and_bracket_the_state() {
        for n in cases() {
            let r = n.roots().unwrap();
            let scale = 2.0 * n.omega0.powi(2) + n.omega.powi(2);
            for p in [r.p1, r.p2, r.p3] {
                assert!(n.f(p).abs() < 1e-12 * scale, "f({p}) = {}", n.f(p));
            }
            assert!(
                -1.0 <= r.p1 && r.p1 < r.p2 && r.p2 <= 1.0 && 1.0 <= r.p3,
                "{r:?}"
            );
            // Vieta: p1 + p2 + p3 = p_E + Ω²/2ω0².
            let sum = n.p_e + n.omega.powi(2) / (2.0 * n.omega0.powi(2));
            assert!((r.p1 + r.p2 + r.p3 - sum).abs() < 1e-12 * sum.abs().max(1.0));
        }
    }

    #[test]
    fn period_agm_matches_gauss_chebyshev() {
        for n in cases() {
            let agm = n.period().unwrap();
            let gc = period_gauss_chebyshev(&n, 400);
            assert!((agm / gc - 1.0).abs() < 1e-13, "{agm} vs {gc}");
        }
    }

    #[test]
    fn mean_rate_kronrod_matches_gauss_chebyshev() {
        for n in cases() {
            let gk = n.mean_precession_rate().unwrap();
            let gc = mean_rate_gauss_chebyshev(&n, 2000);
            assert!((gk - gc).abs() < 1e-12 * gc.abs().max(1.0), "{gk} vs {gc}");
        }
    }

    #[test]
    fn gauss_kronrod_is_exact_for_polynomials_and_adapts_to_peaks() {
        // K15 integrates degree ≤ 22 exactly.
        let v = gauss_kronrod_adaptive(|x: f64| x.powi(22) + 3.0 * x.powi(5), 0.0, 1.0, 1e-15);
        assert!((v - (1.0 / 23.0 + 0.5)).abs() < 1e-15);
        // A sharp Lorentzian: ∫_0^1 ε/(x² + ε²) dx = atan(1/ε).
        let eps = 1e-6;
        let v = gauss_kronrod_adaptive(|x: f64| eps / (x * x + eps * eps), 0.0, 1.0, 1e-14);
        assert!((v / (1.0 / eps).atan() - 1.0).abs() < 1e-12, "{v}");
    }

    #[test]
    fn agm_gives_known_elliptic_k() {
        // K(1/√2) = Γ(1/4)²/(4√π) = 1.854 074 677 301 372 0...
        let k = FRAC_PI_2 / agm(1.0, (0.5_f64).sqrt());
        assert!((k - 1.854_074_677_301_372).abs() < 1e-15);
        assert_eq!(agm(1.0, 1.0), 1.0);
        assert_eq!(agm(1.0, 0.0), 0.0);
    }

    #[test]
    fn pendulum_limit_gives_the_plane_pendulum_period() {
        // Ω → 0 with p0 = −1... use a tiny spin and p0 = 0: the axis swings through the bottom
        // like a plane pendulum of amplitude α around θ = π, cos θ has half its period.
        let alpha: f64 = 1.2;
        let n = Nutation::new(1e-9, 0.0, 1.3, -alpha.cos()).unwrap();
        let k = (alpha / 2.0).sin();
        let kk = FRAC_PI_2 / agm(1.0, (1.0 - k * k).sqrt());
        let want = 2.0 * kk / 1.3;
        assert!((n.period().unwrap() / want - 1.0).abs() < 1e-8);
        // Series K = π/2 (1 + k²/4 + 9k⁴/64 + 25k⁶/256 + 1225k⁸/16384 + ...) as an independent check.
        let k2 = k * k;
        let series: f64 = {
            let mut term = 1.0;
            let mut sum = 1.0;
            for j in 1..200 {
                let f = (2 * j - 1) as f64 / (2 * j) as f64;
                term *= f * f * k2;
                sum += term;
            }
            FRAC_PI_2 * sum
        };
        assert!((kk / series - 1.0).abs() < 1e-13);
    }

    #[test]
    fn fast_top_limits() {
        // Released from rest at p0: T → 2π/√(Ω² − 4ω0²p0) with error O((ω0/Ω)⁴);
        // ⟨φ̇⟩ → ω0²/Ω with error O((ω0/Ω)²).
        let p0 = 0.3;
        let mut prev = (0.0, 0.0);
        for (i, ratio) in [20.0_f64, 40.0, 80.0].iter().enumerate() {
            let n = Nutation::new(*ratio, p0, 1.0, p0).unwrap();
            let t_err =
                (n.period().unwrap() * (ratio * ratio - 4.0 * p0).sqrt() / (2.0 * PI) - 1.0).abs();
            let r_err = (n.mean_precession_rate().unwrap() * ratio - 1.0).abs();
            if i > 0 {
                assert!((prev.0 / t_err - 16.0).abs() < 1.0, "{} {}", prev.0, t_err);
                assert!((prev.1 / r_err - 4.0).abs() < 0.2, "{} {}", prev.1, r_err);
            }
            prev = (t_err, r_err);
        }
    }

    #[test]
    fn regular_precession_and_motion_kinds() {
        // Steady precession: θ̇ = 0 and φ̇ solving θ̈ = 0; then p1 = p2 = cos θ.
        let top = Top {
            i_perp: 1.0,
            i_par: 0.5,
            mgl: 2.0,
        };
        let (theta, spin): (f64, f64) = (0.9, 20.0);
        // I⊥ φ̇² c − I∥ ω3 φ̇ + mgl = 0 with ω3 = ψ̇ + φ̇ c; take the slow root with ψ̇ chosen so ω3 = spin.
        let c = theta.cos();
        let w3 = spin;
        let disc = (top.i_par * w3).powi(2) - 4.0 * top.i_perp * c * top.mgl;
        let phi_dot = (top.i_par * w3 - disc.sqrt()) / (2.0 * top.i_perp * c);
        let psi_dot = w3 - phi_dot * c;
        let k = Constants::from_state(&top, &[theta, 0.0, 0.0], &[0.0, phi_dot, psi_dot]).unwrap();
        let n = k.nutation;
        let r = n.roots().unwrap();
        assert!((r.p2 - r.p1).abs() < 1e-7, "{r:?}");
        assert_eq!(n.motion().unwrap(), Motion::RegularPrecession);
        assert!((n.mean_precession_rate().unwrap() / phi_dot - 1.0).abs() < 1e-9);
        let period = n.period().unwrap();
        assert!(period.is_finite() && period > 0.0);

        let kinds: Vec<Motion> = cases().iter().map(|n| n.motion().unwrap()).collect();
        assert_eq!(kinds[0], Motion::Loops);
        assert_eq!(kinds[1], Motion::Wavy);
        assert_eq!(kinds[2], Motion::Cusps);
    }

    #[test]
    fn near_vertical_release_keeps_the_small_root_gap() {
        // Example 1, θ0 = 1e-3, Ω/ω0 = 2.5 > 2: stays up, θ_max ≈ θ0 Ω/√(Ω² − 4ω0²).
        let top = Top {
            i_perp: 1.0,
            i_par: 1.0,
            mgl: 1.0,
        };
        let theta0 = 1e-3;
        let k = Constants::from_state(&top, &[theta0, 0.0, 0.0], &[0.0, 0.0, 2.5]).unwrap();
        let r = k.nutation.roots().unwrap();
        let (th_min, th_max) = r.theta_range();
        assert!((th_min / theta0 - 1.0).abs() < 1e-9, "{th_min}");
        let bound = sleeping_top_max_angle(theta0, 2.5, 1.0).unwrap();
        assert!((th_max / bound - 1.0).abs() < 1e-5, "{th_max} vs {bound}");
        // Ω/ω0 = 1.5 < 2: falls to p = Ω²/2ω0² − 1 = 0.125.
        let k = Constants::from_state(&top, &[theta0, 0.0, 0.0], &[0.0, 0.0, 1.5]).unwrap();
        let r = k.nutation.roots().unwrap();
        assert!((r.p1 - sleeping_top_lowest_cos(1.5, 1.0).unwrap()).abs() < 1e-5);
        assert!(k.nutation.period().unwrap().is_finite());
    }

    #[test]
    fn sleeping_top_at_threshold_and_logarithmic_period_below_it() {
        let top = Top {
            i_perp: 1.0,
            i_par: 1.0,
            mgl: 1.0,
        };
        // Ω = 2ω0 exactly: f = (p0 − p)·2ω0²(2ε − q²) with q = 1 − p, ε = 1 − cos θ0, so the
        // lowest point is p1 = 1 − 2 sin(θ0/2): θ_max ≈ √(2θ0) → 0 with θ0 (stable, marginally).
        for theta0 in [1e-3, 1e-5] {
            let k = Constants::from_state(&top, &[theta0, 0.0, 0.0], &[0.0, 0.0, 2.0]).unwrap();
            let r = k.nutation.roots().unwrap();
            let want = 1.0 - 2.0 * (theta0 / 2.0).sin();
            assert!((r.p1 - want).abs() < 1e-14, "{} vs {want}", r.p1);
        }
        // Ω < 2ω0: the axis leaves the vertical at the rate λ = √(ω0² − Ω²/4), so the period
        // grows by (2/λ) ln 10 per decade of θ0 (the separatrix of eq. 98 has T = ∞).
        let omega = 1.5;
        let lambda = (1.0 - omega * omega / 4.0_f64).sqrt();
        let period = |theta0: f64| {
            Constants::from_state(&top, &[theta0, 0.0, 0.0], &[0.0, 0.0, omega])
                .unwrap()
                .nutation
                .period()
                .unwrap()
        };
        let want = 2.0 / lambda * 10.0_f64.ln();
        for theta0 in [1e-4, 1e-5, 1e-6] {
            let growth = period(theta0 / 10.0) - period(theta0);
            assert!((growth / want - 1.0).abs() < 1e-6, "{growth} vs {want}");
        }
    }

    #[test]
    fn invalid_inputs_are_errors_not_panics() {
        let top = Top {
            i_perp: 1.0,
            i_par: 1.0,
            mgl: -1.0,
        };
        assert!(matches!(
            Constants::from_state(&top, &[1.0, 0.0, 0.0], &[0.0, 0.0, 1.0]),
            Err(TheoryError::InvalidParameter { name: "mgl", .. })
        ));
        let top = Top { mgl: 1.0, ..top };
        assert_eq!(
            Constants::from_state(&top, &[f64::NAN, 0.0, 0.0], &[0.0, 0.0, 1.0]),
            Err(TheoryError::NonFiniteState)
        );
        // Constants of no motion: p_E far below −1 with p0 = 0.
        let n = Nutation::new(1.0, 0.0, 1.0, -5.0).unwrap();
        assert_eq!(n.period(), Err(TheoryError::NoNutationInterval));
        assert!(!TheoryError::NoSpin.to_string().is_empty());
    }
}
