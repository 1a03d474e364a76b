//! Radau IIA of order 5 (three stages, L-stable; `radau5` of Hairer & Wanner, *Solving Ordinary
//! Differential Equations II*, section IV.8) on the first-order form y = (q, q̇) of the equations
//! of motion: an implicit method for stiff systems (a stiff spring next to slow motion), whose
//! step follows the slow motion while the fast modes are damped out instead of resolved.
//!
//! - The stage equations Z = h (A ⊗ I) F(y₀ + Z) are solved by simplified Newton with the matrix
//!   I − h A ⊗ J, J = ∂f/∂y = [[0, I], [−M⁻¹K, −M⁻¹C]] the exact Jacobian from the jets
//!   ([`jet_linearize`]: third derivatives of L, with the applied forces, the dissipation and an
//!   explicit time dependence; no finite differences). As in `radau5.f`, that system is
//!   transformed by A's eigenvectors into one real and one complex 2N × 2N system (I − γ h J,
//!   I − μ h J): two LUs of a fifth of the flops of the 6N × 6N one, the real one the error
//!   estimate's too.
//! - J is kept while Newton converges fast (rate θ ≤ 10⁻³), the LU while the step changes by
//!   less than 1.2×; Newton starts from the previous step's collocation polynomial, extrapolated.
//! - The error estimate is the embedded order-3 one, (I − γh J)⁻¹ (γ h f(y₀) + Σ eᵢ Zᵢ), with
//!   its second, stiffness-filtering evaluation after a rejection or at the first step; the
//!   tolerances are transformed as in `radau5.f` (rtol′ = 0.1 rtol^(2/3), atol′ = rtol′ atol/rtol)
//!   and the step follows Gustafsson's predictive controller.
//! - The dense output is the collocation polynomial (degree 3) through y₀ and the three stages.

use nalgebra::{Complex, DMatrix, DVector};

use crate::error::DynamicsError;
use crate::lagrangian::Lagrangian;
use crate::linearize::jet_linearize;

use super::control::{effective_atol, initial_step, too_small};
use super::state::Stats;
use super::state::{Fault, Y, finite, rhs};
use super::stepper::Stepper;

/// √6.
const SQ6: f64 = 2.449_489_742_783_178;

/// The nodes c = ((4 − √6)/10, (4 + √6)/10, 1).
pub(crate) const C: [f64; 3] = [(4.0 - SQ6) / 10.0, (4.0 + SQ6) / 10.0, 1.0];

/// The Radau IIA matrix A (its last row is the weights b).
pub(crate) const A: [[f64; 3]; 3] = [
    [
        (88.0 - 7.0 * SQ6) / 360.0,
        (296.0 - 169.0 * SQ6) / 1800.0,
        (-2.0 + 3.0 * SQ6) / 225.0,
    ],
    [
        (296.0 + 169.0 * SQ6) / 1800.0,
        (88.0 + 7.0 * SQ6) / 360.0,
        (-2.0 - 3.0 * SQ6) / 225.0,
    ],
    [(16.0 - SQ6) / 36.0, (16.0 + SQ6) / 36.0, 1.0 / 9.0],
];

/// γ: the real eigenvalue of A (1/γ₀, γ₀ ≈ 3.6378 the real eigenvalue of A⁻¹),
/// (6 + ∛81 − ∛9)/30. The embedded solution's weight on f(y₀) and the error estimate's matrix
/// I − γ h J.
pub(crate) const GAMMA: f64 = 0.274_888_829_595_677_4;

/// The error estimate's weights on the stages, divided by γ (`dd1..dd3` of `radau5.f`):
/// Σ eᵢ cᵢ = −1, Σ eᵢ cᵢ² = Σ eᵢ cᵢ³ = 0 (so that γ h f(y₀) + γ Σ eᵢ Zᵢ is y₁ minus an order-3
/// solution).
pub(crate) const E: [f64; 3] = [
    -(13.0 + 7.0 * SQ6) / 3.0,
    (-13.0 + 7.0 * SQ6) / 3.0,
    -1.0 / 3.0,
];

/// Newton iterations per step at most.
const NIT: usize = 7;
/// Newton's rate of convergence below which J is kept for the next step.
const THET: f64 = 1e-3;
/// The step ratios h_new / h within which the LU is kept (and the step too).
const QUOT1: f64 = 1.0;
const QUOT2: f64 = 1.2;
/// The safety factor of the step-size control.
const SAFE: f64 = 0.9;
/// The smallest and largest factors h_new / h (Hairer's facr = 1/8, facl = 5 as step factors).
const FAC_MAX: f64 = 8.0;
const FAC_MIN: f64 = 0.2;
/// f64's unit round-off.
const UROUND: f64 = 1e-16;

/// The collocation polynomial of a step in Newton form over the nodes 0, c₁, c₂ (and 1):
/// y(t₀ + s h) = y₀ + s (d₁ + (s − c₁)(d₂ + (s − c₂) d₃)), the rows (y₀, d₁, d₂, d₃).
pub(crate) fn collocation_rows<const N: usize>(y0: &Y<N>, z: &[Y<N>; 3]) -> [Y<N>; 4] {
    let mut r = [*y0, [[0.0; N]; 2], [[0.0; N]; 2], [[0.0; N]; 2]];
    for c in 0..2 {
        for i in 0..N {
            let (z1, z2, z3) = (z[0][c][i], z[1][c][i], z[2][c][i]);
            let f01 = z1 / C[0];
            let f12 = (z2 - z1) / (C[1] - C[0]);
            let f23 = (z3 - z2) / (1.0 - C[1]);
            let f012 = (f12 - f01) / C[1];
            let f123 = (f23 - f12) / (1.0 - C[0]);
            r[1][c][i] = f01;
            r[2][c][i] = f012;
            r[3][c][i] = f123 - f012;
        }
    }
    r
}

/// The displacement s (d₁ + (s − c₁)(d₂ + (s − c₂) d₃)) of the collocation polynomial at s.
fn displacement<const N: usize>(r: &[Y<N>; 4], s: f64) -> Y<N> {
    let mut out = [[0.0; N]; 2];
    for c in 0..2 {
        for i in 0..N {
            out[c][i] = s * (r[1][c][i] + (s - C[0]) * (r[2][c][i] + (s - C[1]) * r[3][c][i]));
        }
    }
    out
}

/// Evaluates the collocation polynomial at s = (t − t₀)/h ∈ [0, 1].
pub(crate) fn eval_dense<const N: usize>(r: &[Y<N>; 4], s: f64) -> Y<N> {
    let mut out = displacement(r, s);
    for c in 0..2 {
        for i in 0..N {
            out[c][i] += r[0][c][i];
        }
    }
    out
}

/// Component k of the flattened state (q then q̇).
#[inline(always)]
fn at<const N: usize>(y: &Y<N>, k: usize) -> f64 {
    y[k / N][k % N]
}

/// A's eigendecomposition A = V diag(γ, μ, μ̄) V⁻¹: μ, V's first two columns and V⁻¹'s first
/// two rows (V's third column and V⁻¹'s third row are the conjugates of the second).
struct Eigen {
    mu: Complex<f64>,
    v: [[Complex<f64>; 2]; 3],
    vinv: [[Complex<f64>; 3]; 2],
}

/// ∂f/∂p at (t, y) of a sensitivity run's parameters (column-major, 2N × P).
pub(crate) type Forcing<'l, const N: usize> =
    Box<dyn Fn(f64, &Y<N>) -> Result<Vec<f64>, Fault> + 'l>;

/// [`Eigen`], from A's trace and determinant (γ + 2 Re μ, γ |μ|²) and the null vectors of
/// A − γ I and A − μ I (the cross product of two of their rows).
fn eigen() -> &'static Eigen {
    // A's constants: computed once per process, not at every factorization.
    static EIGEN: std::sync::OnceLock<Eigen> = std::sync::OnceLock::new();
    EIGEN.get_or_init(decompose)
}

/// The computation behind [`eigen`].
fn decompose() -> Eigen {
    let a = |i: usize, j: usize, l: Complex<f64>| {
        Complex::new(A[i][j], 0.0) - if i == j { l } else { Complex::new(0.0, 0.0) }
    };
    let trace = A[0][0] + A[1][1] + A[2][2];
    let det = nalgebra::Matrix3::from_fn(|i, j| A[i][j]).determinant();
    let re = (trace - GAMMA) / 2.0;
    let mu = Complex::new(re, (det / GAMMA - re * re).sqrt());
    let null = |l: Complex<f64>| {
        let (r0, r1) = (
            [a(0, 0, l), a(0, 1, l), a(0, 2, l)],
            [a(1, 0, l), a(1, 1, l), a(1, 2, l)],
        );
        [
            r0[1] * r1[2] - r0[2] * r1[1],
            r0[2] * r1[0] - r0[0] * r1[2],
            r0[0] * r1[1] - r0[1] * r1[0],
        ]
    };
    let (v1, v2) = (null(Complex::new(GAMMA, 0.0)), null(mu));
    let full = nalgebra::Matrix3::from_fn(|i, j| [v1[i], v2[i], v2[i].conj()][j]);
    // V is invertible: its columns are eigenvectors of three distinct eigenvalues.
    let inv = full.try_inverse().unwrap_or(full);
    Eigen {
        mu,
        v: core::array::from_fn(|i| [v1[i], v2[i]]),
        vinv: core::array::from_fn(|k| core::array::from_fn(|j| inv[(k, j)])),
    }
}

/// The factorized matrices of a step size h: I − h A ⊗ J (Newton) transformed by A's
/// eigenvectors into I − γ h J (real; the error estimate's matrix too) and I − μ h J (complex),
/// as `radau5.f` does (one real and one complex 2N × 2N LU instead of a real 6N × 6N one: about
/// a fifth of the flops).
struct Factors {
    h: f64,
    eigen: &'static Eigen,
    real: nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>,
    complex: nalgebra::LU<Complex<f64>, nalgebra::Dyn, nalgebra::Dyn>,
}

impl Factors {
    /// Solves (I − h A ⊗ J) Δ = r in place (r, Δ: the three stages' 2N components in turn):
    /// with W = (V⁻¹ ⊗ I) r, X₁ = (I − γ h J)⁻¹ W₁, X₂ = (I − μ h J)⁻¹ W₂ (X₃ = X̄₂), and
    /// Δ = (V ⊗ I) X = V₁ X₁ + 2 Re(V₂ X₂). False where a solve fails.
    fn solve_stages(&self, r: &mut DVector<f64>) -> bool {
        let n = r.len() / 3;
        let Eigen { v, vinv, .. } = self.eigen;
        let mut w1 =
            DVector::<f64>::from_fn(n, |k, _| (0..3).map(|j| vinv[0][j].re * r[j * n + k]).sum());
        let mut w2 = DVector::<Complex<f64>>::from_fn(n, |k, _| {
            (0..3).map(|j| vinv[1][j] * r[j * n + k]).sum()
        });
        if !self.real.solve_mut(&mut w1) || !self.complex.solve_mut(&mut w2) {
            return false;
        }
        for i in 0..3 {
            for k in 0..n {
                r[i * n + k] = v[i][0].re * w1[k] + 2.0 * (v[i][1] * w2[k]).re;
            }
        }
        true
    }
}

/// Why a step attempt failed before its error was known.
enum Attempt {
    /// Newton diverged or converged too slowly: retry with the step times this factor.
    Retry(f64, Fault),
}

/// What Radau5 asks of the system besides what every run does (the first step): f and its
/// exact Jacobian. Object-safe, so the stepper is compiled once per number of coordinates
/// rather than once per system (every system a crate runs instantiates every method of the
/// driver; this one is large).
pub(crate) trait Dynamics<const N: usize>: super::system::System<N> {
    /// f(t, y) = (q̇, q̈).
    fn rhs(&self, t: f64, y: &Y<N>, stats: &mut Stats) -> Result<Y<N>, DynamicsError>;
    /// J = ∂f/∂y at (t, y), from the jets.
    fn jacobian(&self, t: f64, y: &Y<N>) -> Result<DMatrix<f64>, Fault>;
}

impl<L: Lagrangian<N>, const N: usize> Dynamics<N> for L {
    fn rhs(&self, t: f64, y: &Y<N>, stats: &mut Stats) -> Result<Y<N>, DynamicsError> {
        rhs(self, t, y, stats)
    }
    fn jacobian(&self, t: f64, y: &Y<N>) -> Result<DMatrix<f64>, Fault> {
        // A view's own (a constrained run's), else the sensitivity runs' Jacobian (the
        // compiled q̈ in tangents), else the jets'.
        if let Some(j) = self.first_order_jacobian(&y[0], &y[1], t) {
            return Ok(j?);
        }
        if let Some(j) = super::jacobian::compiled_state_jacobian(self, &y[0], &y[1], t) {
            return Ok(j);
        }
        let lin = jet_linearize(self, &y[0], &y[1], t)?;
        lin.state_matrix().map_err(|e| match e {
            crate::linearize::LinearizationError::Dynamics(d) => Fault::Dynamics(d),
            _ => Fault::Newton {
                iterations: 0,
                residual: f64::NAN,
                reason: "Radau5: the mass matrix is singular at the step's start, so the Jacobian of the \
                         accelerations does not exist",
            },
        })
    }
}

/// The adaptive Radau IIA stepper (see the module documentation).
pub(crate) struct Radau5<'a, const N: usize> {
    sys: &'a dyn Dynamics<N>,
    /// The transformed tolerances (rtol′, atol′).
    rtol: f64,
    atol: f64,
    hmax: f64,
    /// Newton's stopping tolerance on the (scaled) increments.
    fnewt: f64,
    t: f64,
    y: Y<N>,
    /// f(t, y) at the current node.
    f0: Y<N>,
    t_old: f64,
    h_old: f64,
    /// The last step's collocation polynomial (`collocation_rows`).
    r: [Y<N>; 4],
    /// The proposed next step.
    h: f64,
    /// J at the node where it was evaluated, and whether that is the current node.
    jac: Option<DMatrix<f64>>,
    jac_current: bool,
    /// Whether J must be evaluated anew before the next attempt.
    need_jac: bool,
    factors: Option<Factors>,
    /// Newton's rate of convergence in the last step, and Hairer's faccon.
    theta: f64,
    faccon: f64,
    /// No step accepted yet (no polynomial to extrapolate; a rejection divides h by 10).
    first: bool,
    /// The last attempt was rejected.
    reject: bool,
    /// Gustafsson's controller: the last accepted step and its error (floored at 10⁻²).
    h_acc: f64,
    err_acc: f64,
    accepted: usize,
    /// The fault behind the latest forced shrink since the last accepted step: reported instead
    /// of a bare underflow when the step then becomes too small.
    last_failure: Option<Fault>,
    /// A bound on the step after Newton failed: 0.8 of the smallest step it failed at, grown by
    /// 1.1 with each accepted step whose Newton converged within 3 iterations. Where the error
    /// estimate is small but a stiff direction turns with the motion (the elastic crank's rod),
    /// the error controller asks for steps 5–8× longer, at which simplified Newton diverges:
    /// without the bound every accepted step was followed by one or two failed attempts.
    newton_cap: f64,
    /// A sensitivity run's variations, carried through the accepted steps.
    var: Option<Variations<'a, N>>,
}

/// The variations a sensitivity run carries through Radau5's steps: the derivative of the
/// discrete flow. After an accepted step from y₀ with stages Z (Z = h (A ⊗ I) F(y₀ + Z)), the
/// implicit function theorem gives D = (∂Z/∂y₀) Φ₀ from
/// (I − h (A ⊗ I) diag(J₁, J₂, J₃)) D = h (A ⊗ I) (J₁ Φ₀, J₂ Φ₀, J₃ Φ₀), Jᵢ = ∂f/∂y exact at
/// the stages (the jets), and Φ₁ = Φ₀ + D₃ (the last stage is y₁); between nodes Φ follows
/// the derivative of the collocation polynomial.
pub(crate) struct Variations<'l, const N: usize> {
    /// Columns (2N rows each, column-major): Φ at the node and at the last step's start (Φ's
    /// columns, then one per parameter, whose derivative adds ∂f/∂p: `forcing`).
    cols: usize,
    /// ∂f/∂p at (t, y), column-major 2N × P for the last P columns (none without parameters).
    forcing: Option<Forcing<'l, N>>,
    phi: Vec<f64>,
    phi_old: Vec<f64>,
    /// Dᵢ of the last step.
    d: [Vec<f64>; 3],
    log: &'l core::cell::RefCell<super::sensitivity::Log>,
}

impl<'a, const N: usize> Radau5<'a, N> {
    /// Carries the variations `phi` (column-major, 2N rows; the last columns those of the
    /// parameters whose ∂f/∂p `forcing` gives) through the run, recording them in `log` at the
    /// samples and event hits.
    pub(crate) fn with_variations(
        mut self,
        phi: Vec<f64>,
        forcing: Option<Forcing<'a, N>>,
        log: &'a core::cell::RefCell<super::sensitivity::Log>,
    ) -> Self {
        let cols = phi.len() / (2 * N);
        self.var = Some(Variations {
            cols,
            forcing,
            phi_old: phi.clone(),
            phi,
            d: Default::default(),
            log,
        });
        self
    }

    /// Moves the variations over the step of size h from the node with stages `z` (see
    /// [`Variations`]); counts its Jacobians and its LU.
    // Out of line: a sensitivity run's large locals (Hessians of 64 coordinates) stay off
    // the plain step's frame.
    #[inline(never)]
    fn vary(&mut self, h: f64, z: &[Y<N>; 3], stats: &mut Stats) -> Result<(), Fault> {
        let Some(var) = self.var.as_mut() else {
            return Ok(());
        };
        let (n, m) = (2 * N, var.cols);
        let phi0 = DMatrix::from_column_slice(n, m, &var.phi);
        let mut jac = Vec::with_capacity(3);
        let mut jphi = Vec::with_capacity(3);
        for (i, zi) in z.iter().enumerate() {
            let mut yi = self.y;
            for c in 0..2 {
                for k in 0..N {
                    yi[c][k] += zi[c][k];
                }
            }
            let ti = self.t + C[i] * h;
            let j = self.sys.jacobian(ti, &yi)?;
            // The stage's slope of the columns: J Φ, plus ∂f/∂p in the parameters' columns.
            let mut slope = &j * &phi0;
            if let Some(forcing) = &var.forcing {
                let fp = forcing(ti, &yi)?;
                let p = fp.len() / n;
                let mut tail = slope.columns_mut(m - p, p);
                tail += DMatrix::from_column_slice(n, p, &fp);
            }
            jac.push(j);
            jphi.push(slope);
        }
        stats.jacobians += 3;
        stats.decompositions += 1;
        let mut mat = DMatrix::<f64>::identity(3 * n, 3 * n);
        let mut rhs = DMatrix::<f64>::zeros(3 * n, m);
        for bi in 0..3 {
            for bj in 0..3 {
                let s = h * A[bi][bj];
                let mut block = mat.view_mut((bi * n, bj * n), (n, n));
                block -= &jac[bj] * s;
                let mut r = rhs.view_mut((bi * n, 0), (n, m));
                r += &jphi[bj] * s;
            }
        }
        let d = mat.lu().solve(&rhs).ok_or(Fault::Newton {
            iterations: 0,
            residual: f64::NAN,
            reason: "Radau5: the derivative of the step with respect to its start is singular                      (I − h (A ⊗ I) diag(J) has no inverse)",
        })?;
        for (i, di) in var.d.iter_mut().enumerate() {
            *di = d.rows(i * n, n).iter().copied().collect();
        }
        var.phi_old.clone_from(&var.phi);
        for (p, d3) in var.phi.iter_mut().zip(&var.d[2]) {
            *p += d3;
        }
        Ok(())
    }

    /// Φ at t in the last step (the node's from its time on): column by column, the derivative
    /// of the collocation polynomial, Φ₀ + p(s; D₁, D₂, D₃).
    // Out of line: a sensitivity run's large locals (Hessians of 64 coordinates) stay off
    // the plain step's frame.
    #[inline(never)]
    fn phi_at(&self, t: f64) -> Option<Vec<f64>> {
        let var = self.var.as_ref()?;
        if t >= self.t || self.h_old == 0.0 {
            return Some(var.phi.clone());
        }
        let (n, s) = (2 * N, (t - self.t_old) / self.h_old);
        let column = |v: &[f64], j: usize| -> Y<N> {
            [
                core::array::from_fn(|k| v[j * n + k]),
                core::array::from_fn(|k| v[j * n + N + k]),
            ]
        };
        let mut out = Vec::with_capacity(n * var.cols);
        for j in 0..var.cols {
            let z = [
                column(&var.d[0], j),
                column(&var.d[1], j),
                column(&var.d[2], j),
            ];
            let p = eval_dense(&collocation_rows(&column(&var.phi_old, j), &z), s);
            out.extend(p.iter().flatten());
        }
        Some(out)
    }

    /// Starts at (t0, y0); evaluates f there and picks the first step.
    pub(crate) fn new(
        sys: &'a dyn Dynamics<N>,
        t0: f64,
        y0: Y<N>,
        rtol: f64,
        atol: f64,
        hmax: f64,
        stats: &mut Stats,
    ) -> Result<Self, Fault> {
        let f0 = sys.rhs(t0, &y0, stats)?;
        let h = initial_step(
            sys,
            t0,
            &y0,
            &f0,
            5,
            rtol,
            effective_atol(atol),
            hmax,
            stats,
        )?;
        let rt = 0.1 * rtol.powf(2.0 / 3.0);
        let at = effective_atol(rt * (atol / rtol));
        Ok(Radau5 {
            sys,
            rtol: rt,
            atol: at,
            hmax,
            fnewt: (10.0 * UROUND / rt).max(0.03_f64.min(rt.sqrt())),
            t: t0,
            y: y0,
            f0,
            t_old: t0,
            h_old: 0.0,
            r: [y0, [[0.0; N]; 2], [[0.0; N]; 2], [[0.0; N]; 2]],
            h,
            jac: None,
            jac_current: false,
            need_jac: true,
            factors: None,
            theta: THET,
            faccon: 1.0,
            first: true,
            reject: false,
            h_acc: h,
            err_acc: 1e-2,
            accepted: 0,
            newton_cap: f64::INFINITY,
            var: None,
            last_failure: None,
        })
    }

    /// J = ∂f/∂y at the current node, from the jets.
    fn jacobian(&self) -> Result<DMatrix<f64>, Fault> {
        self.sys.jacobian(self.t, &self.y)
    }

    /// Factorizes I − h A ⊗ J and I − γ h J for the step h; `None` where either is singular.
    fn factorize(j: &DMatrix<f64>, h: f64) -> Option<Factors> {
        let n = 2 * N;
        let eigen = eigen();
        let real = DMatrix::<f64>::from_fn(n, n, |r, c| {
            f64::from(u8::from(r == c)) - GAMMA * h * j[(r, c)]
        })
        .lu();
        let mu_h = eigen.mu * h;
        let complex = DMatrix::<Complex<f64>>::from_fn(n, n, |r, c| {
            Complex::new(f64::from(u8::from(r == c)), 0.0) - mu_h * j[(r, c)]
        })
        .lu();
        (real.is_invertible() && complex.is_invertible()).then_some(Factors {
            h,
            eigen,
            real,
            complex,
        })
    }

    /// The error weights at the step's start.
    fn scales(&self) -> Y<N> {
        let mut s = [[0.0; N]; 2];
        for c in 0..2 {
            for i in 0..N {
                s[c][i] = self.atol + self.rtol * self.y[c][i].abs();
            }
        }
        s
    }

    /// (I − γ h J)⁻¹ (γ h f + γ Σ eᵢ Zᵢ): the error estimate with f = f(y₀) (or, for the second
    /// evaluation, f at y₀ plus the first estimate).
    fn estimate(fac: &Factors, f: &Y<N>, z: &[Y<N>; 3]) -> Option<Y<N>> {
        let n = 2 * N;
        let mut v = DVector::<f64>::zeros(n);
        for k in 0..n {
            let s = E[0] * at(&z[0], k) + E[1] * at(&z[1], k) + E[2] * at(&z[2], k);
            v[k] = GAMMA * (fac.h * at(f, k) + s);
        }
        if !fac.real.solve_mut(&mut v) {
            return None;
        }
        let mut out = [[0.0; N]; 2];
        for k in 0..n {
            out[k / N][k % N] = v[k];
        }
        Some(out)
    }

    /// The root-mean-square of e / sk.
    fn norm(e: &Y<N>, sk: &Y<N>) -> f64 {
        let mut s = 0.0;
        for c in 0..2 {
            for i in 0..N {
                let x = e[c][i] / sk[c][i];
                s += x * x;
            }
        }
        (s / (2 * N) as f64).sqrt()
    }

    /// Solves the stage equations for the step h by simplified Newton: the stage displacements Z
    /// and the iterations taken, or why the step must be retried smaller.
    fn newton(
        &mut self,
        h: f64,
        sk: &Y<N>,
        stats: &mut Stats,
    ) -> Result<([Y<N>; 3], usize), Attempt> {
        let Some(fac) = self.factors.take() else {
            return Err(Attempt::Retry(0.5, Fault::NonFinite));
        };
        let out = self.newton_with(&fac, h, sk, stats);
        self.factors = Some(fac);
        out
    }

    /// `newton` with the factorized matrices of the step h.
    fn newton_with(
        &mut self,
        fac: &Factors,
        h: f64,
        sk: &Y<N>,
        stats: &mut Stats,
    ) -> Result<([Y<N>; 3], usize), Attempt> {
        let n = 2 * N;
        // The start: the last step's collocation polynomial, extrapolated (zero at the first
        // step).
        let mut z = [[[0.0; N]; 2]; 3];
        if !self.first && self.h_old > 0.0 {
            let end = displacement(&self.r, 1.0);
            for (i, zi) in z.iter_mut().enumerate() {
                let p = displacement(&self.r, 1.0 + C[i] * h / self.h_old);
                for c in 0..2 {
                    for k in 0..N {
                        zi[c][k] = p[c][k] - end[c][k];
                    }
                }
            }
        }
        self.faccon = self.faccon.max(UROUND).powf(0.8);
        self.theta = THET;
        let mut dynold = 0.0_f64;
        let mut thqold = 0.0_f64;
        let mut rhs_v = DVector::<f64>::zeros(3 * n);
        for newt in 1..=NIT {
            // F at the stages.
            let mut f = [[[0.0; N]; 2]; 3];
            for i in 0..3 {
                let mut yi = self.y;
                for c in 0..2 {
                    for k in 0..N {
                        yi[c][k] += z[i][c][k];
                    }
                }
                match self.sys.rhs(self.t + C[i] * h, &yi, stats) {
                    Ok(fi) => f[i] = fi,
                    Err(e) => return Err(Attempt::Retry(0.5, Fault::Dynamics(e))),
                }
            }
            stats.newton_iterations += 1;
            // The residual −Z + h (A ⊗ I) F and the increment.
            for i in 0..3 {
                for k in 0..n {
                    let s =
                        A[i][0] * at(&f[0], k) + A[i][1] * at(&f[1], k) + A[i][2] * at(&f[2], k);
                    rhs_v[i * n + k] = h * s - at(&z[i], k);
                }
            }
            if !fac.solve_stages(&mut rhs_v) {
                return Err(Attempt::Retry(0.5, Fault::NonFinite));
            }
            let mut sum = 0.0;
            for i in 0..3 {
                for k in 0..n {
                    let x = rhs_v[i * n + k] / at(sk, k);
                    sum += x * x;
                }
            }
            let dyno = (sum / (3 * n) as f64).sqrt();
            if !dyno.is_finite() {
                return Err(Attempt::Retry(0.5, Fault::NonFinite));
            }
            let fail = |residual: f64, reason: &'static str| Fault::Newton {
                iterations: newt,
                residual,
                reason,
            };
            if newt > 1 && newt < NIT {
                let thq = dyno / dynold;
                self.theta = if newt == 2 {
                    thq
                } else {
                    (thq * thqold).sqrt()
                };
                thqold = thq;
                if self.theta < 0.99 {
                    self.faccon = self.theta / (1.0 - self.theta);
                    let dyth =
                        self.faccon * dyno * self.theta.powi((NIT - 1 - newt) as i32) / self.fnewt;
                    if dyth >= 1.0 {
                        // Converging, too slowly to finish within NIT iterations.
                        let qnewt = dyth.clamp(1e-4, 20.0);
                        let fac = 0.8 * qnewt.powf(-1.0 / (4.0 + (NIT - 1 - newt) as f64));
                        return Err(Attempt::Retry(
                            fac,
                            fail(dyno, "Radau5: the stage equations converged too slowly"),
                        ));
                    }
                } else {
                    return Err(Attempt::Retry(
                        0.5,
                        fail(dyno, "Radau5: the stage equations diverged"),
                    ));
                }
            }
            dynold = dyno.max(UROUND);
            for i in 0..3 {
                for k in 0..n {
                    z[i][k / N][k % N] += rhs_v[i * n + k];
                }
            }
            if self.faccon * dyno <= self.fnewt {
                return Ok((z, newt));
            }
        }
        Err(Attempt::Retry(
            0.5,
            Fault::Newton {
                iterations: NIT,
                residual: dynold,
                reason: "Radau5: the stage equations did not converge",
            },
        ))
    }

    /// Records a failed attempt of step h: the next one is `factor` h, with J evaluated anew if
    /// it is not from this node.
    fn retry(&mut self, h: f64, factor: f64, fault: Fault, stats: &mut Stats) {
        stats.rejected += 1;
        self.reject = true;
        self.h = h * factor;
        self.need_jac = !self.jac_current;
        self.last_failure = Some(fault);
    }
}

impl<const N: usize> Stepper<N> for Radau5<'_, N> {
    fn t(&self) -> f64 {
        self.t
    }
    fn t_prev(&self) -> f64 {
        self.t_old
    }
    fn last_state(&self) -> Y<N> {
        self.y
    }
    fn set_node(&mut self, y: Y<N>, stats: &mut Stats) -> Result<(), Fault> {
        // The polynomial ends at y after adding δ s (d₁ += δ); f and J there anew.
        for c in 0..2 {
            for i in 0..N {
                self.r[1][c][i] += y[c][i] - self.y[c][i];
            }
        }
        self.y = y;
        self.f0 = self.sys.rhs(self.t, &y, stats)?;
        self.jac_current = false;
        Ok(())
    }
    fn advance(&mut self, t_end: f64, stats: &mut Stats) -> Result<(), Fault> {
        loop {
            let mut h = self.h.min(self.hmax);
            let last = self.t + 1.01 * h >= t_end;
            if last {
                h = t_end - self.t;
            }
            if too_small(h, self.t) || !h.is_finite() {
                return Err(self.last_failure.take().unwrap_or(Fault::Underflow { h }));
            }
            if self.need_jac || self.jac.is_none() {
                self.jac = Some(self.jacobian()?);
                stats.jacobians += 1;
                self.jac_current = true;
                self.need_jac = false;
                self.factors = None;
            }
            if self.factors.as_ref().is_none_or(|f| f.h != h) {
                let Some(j) = self.jac.as_ref() else {
                    return Err(Fault::NonFinite);
                };
                self.factors = Self::factorize(j, h);
                stats.decompositions += 1;
                if self.factors.is_none() {
                    stats.newton_failures += 1;
                    self.retry(
                        h,
                        0.5,
                        Fault::Newton {
                            iterations: 0,
                            residual: f64::NAN,
                            reason: "Radau5: the Newton matrix I − h A ⊗ J is singular",
                        },
                        stats,
                    );
                    continue;
                }
            }
            let sk = self.scales();
            let (z, newt) = match self.newton(h, &sk, stats) {
                Ok(ok) => ok,
                Err(Attempt::Retry(factor, fault)) => {
                    if matches!(fault, Fault::Newton { .. }) {
                        self.newton_cap = self.newton_cap.min(0.8 * h);
                        stats.newton_failures += 1;
                    }
                    self.retry(h, factor, fault, stats);
                    continue;
                }
            };
            let Some(fac) = self.factors.as_ref() else {
                return Err(Fault::NonFinite);
            };
            // The error estimate, filtered once more where the first one is large after a
            // rejection or at the first step.
            let mut err = match Self::estimate(fac, &self.f0, &z) {
                Some(e) => {
                    let mut err = Self::norm(&e, &sk);
                    if err >= 1.0 && (self.first || self.reject) {
                        let mut ye = self.y;
                        for c in 0..2 {
                            for i in 0..N {
                                ye[c][i] += e[c][i];
                            }
                        }
                        err = match self.sys.rhs(self.t, &ye, stats) {
                            Ok(f1) => Self::estimate(fac, &f1, &z)
                                .map_or(f64::INFINITY, |e2| Self::norm(&e2, &sk)),
                            Err(_) => f64::INFINITY,
                        };
                    }
                    err
                }
                None => f64::INFINITY,
            };
            if err.is_nan() {
                err = f64::INFINITY;
            }
            let err = err.max(1e-10);
            // The new step from the error and the Newton work (Hairer's fac).
            let cfac = SAFE * (1 + 2 * NIT) as f64;
            let safe = SAFE.min(cfac / (newt + 2 * NIT) as f64);
            let quot = (1.0 / FAC_MAX).max((1.0 / FAC_MIN).min(err.powf(0.25) / safe));
            let mut hnew = h / quot;
            if err < 1.0 {
                let mut y1 = self.y;
                for c in 0..2 {
                    for i in 0..N {
                        y1[c][i] += z[2][c][i];
                    }
                }
                if !finite(&y1) {
                    self.retry(h, 0.25, Fault::NonFinite, stats);
                    continue;
                }
                let t1 = if last { t_end } else { self.t + h };
                let f1 = match self.sys.rhs(t1, &y1, stats) {
                    Ok(f) => f,
                    Err(e) => {
                        self.retry(h, 0.25, Fault::Dynamics(e), stats);
                        continue;
                    }
                };
                // Gustafsson's predictive controller.
                if self.accepted >= 1 {
                    let facgus = (self.h_acc / h) * (err * err / self.err_acc).powf(0.25) / SAFE;
                    let facgus = (1.0 / FAC_MAX).max((1.0 / FAC_MIN).min(facgus));
                    hnew = h / quot.max(facgus);
                }
                self.vary(h, &z, stats)?;
                self.h_acc = h;
                self.err_acc = err.max(1e-2);
                self.accepted += 1;
                stats.steps += 1;
                self.r = collocation_rows(&self.y, &z);
                self.t_old = self.t;
                self.h_old = h;
                self.t = t1;
                self.y = y1;
                self.f0 = f1;
                self.first = false;
                self.jac_current = false;
                self.last_failure = None;
                if newt <= 3 {
                    self.newton_cap *= 1.1;
                }
                hnew = hnew.min(self.hmax).min(self.newton_cap);
                if self.reject {
                    hnew = hnew.min(h);
                }
                self.reject = false;
                // Keep J while Newton converged fast; keep the step (and the LU) too where the
                // new one would be less than 1.2× larger.
                let qt = hnew / h;
                if self.theta <= THET && (QUOT1..=QUOT2).contains(&qt) {
                    self.h = h;
                } else {
                    self.h = hnew;
                }
                self.need_jac = self.theta > THET;
                return Ok(());
            }
            // Rejected.
            stats.rejected += 1;
            self.reject = true;
            self.h = if self.first { 0.1 * h } else { hnew };
            self.need_jac = !self.jac_current;
            self.last_failure = None;
        }
    }
    fn interp(&mut self, t: f64, _stats: &mut Stats) -> Result<Y<N>, Fault> {
        if t >= self.t {
            return Ok(self.y);
        }
        Ok(eval_dense(&self.r, (t - self.t_old) / self.h_old))
    }
    /// The 4 rows of the collocation polynomial (`eval_dense`'s), scaled by h.
    fn dense_rows(&mut self, rows: &mut Vec<Y<N>>, _stats: &mut Stats) -> Result<f64, Fault> {
        rows.extend_from_slice(&self.r);
        Ok(self.h_old)
    }
    fn recorded(&mut self, t: f64, at: f64, _stats: &mut Stats) -> Result<(), Fault> {
        if let (Some(var), Some(cols)) = (self.var.as_ref(), self.phi_at(at)) {
            var.log.borrow_mut().samples.push((t, cols));
        }
        Ok(())
    }
    fn event_located(&mut self, t: f64, event: usize, stats: &mut Stats) -> Result<(), Fault> {
        let Some(cols) = self.phi_at(t) else {
            return Ok(());
        };
        let y = self.interp(t, stats)?;
        if let Some(var) = self.var.as_ref() {
            var.log.borrow_mut().event(t, event, cols, &y, None);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The collocation conditions Σⱼ aᵢⱼ cⱼ^(k−1) = cᵢ^k / k, k = 1, 2, 3 (stage order 3), the
    /// weights (last row) integrating polynomials of degree ≤ 4 exactly (order 5), and c₃ = 1.
    #[test]
    fn tableau_is_radau_iia() {
        for i in 0..3 {
            for k in 1..=3 {
                let s: f64 = (0..3).map(|j| A[i][j] * C[j].powi(k - 1)).sum();
                let want = C[i].powi(k) / f64::from(k);
                assert!((s - want).abs() < 1e-15, "row {i}, k {k}: {s} vs {want}");
            }
        }
        for k in 1..=5 {
            let s: f64 = (0..3).map(|j| A[2][j] * C[j].powi(k - 1)).sum();
            assert!((s - 1.0 / f64::from(k)).abs() < 1e-15, "k {k}: {s}");
        }
        assert_eq!(C[2], 1.0);
        // The nodes are the roots of the Radau polynomial: c₁ c₂ = 1/10, c₁ + c₂ = 4/5.
        assert!((C[0] * C[1] - 0.1).abs() < 1e-16 && (C[0] + C[1] - 0.8).abs() < 1e-16);
        assert!((SQ6 * SQ6 - 6.0).abs() < 1e-15);
    }

    /// γ is an eigenvalue of A (det(A − γ I) = 0), the closed form (6 + ∛81 − ∛9)/30, and A's
    /// only real one: the characteristic polynomial changes sign at γ alone.
    #[test]
    fn gamma_is_the_real_eigenvalue_of_a() {
        let det = |g: f64| {
            let m = DMatrix::from_fn(3, 3, |i, j| A[i][j] - if i == j { g } else { 0.0 });
            m.determinant()
        };
        assert!(det(GAMMA).abs() < 1e-16, "{}", det(GAMMA));
        let closed = (6.0 + 81.0_f64.cbrt() - 9.0_f64.cbrt()) / 30.0;
        assert!((GAMMA - closed).abs() < 2e-16, "{GAMMA} vs {closed}");
        let eig = DMatrix::from_fn(3, 3, |i, j| A[i][j]).complex_eigenvalues();
        let real: Vec<_> = eig.iter().filter(|l| l.im.abs() < 1e-12).collect();
        assert_eq!(real.len(), 1, "{eig:?}");
        assert!((real[0].re - GAMMA).abs() < 1e-14);
        // γ₀ = 1/γ, the real eigenvalue of A⁻¹, as Hairer tabulates it.
        assert!((1.0 / GAMMA - 3.637_834_252_744_496).abs() < 1e-12);
    }

    /// A = V diag(γ, μ, μ̄) V⁻¹ to round-off, and the transformed solve of the stage equations'
    /// linear system equals the direct solve of I − h A ⊗ J (a 6 × 6 J with a stiff, a
    /// rotating and a slow part).
    #[test]
    fn transformed_solve_is_the_direct_solve() {
        let e = eigen();
        let col = |i: usize, k: usize| match k {
            0 => e.v[i][0],
            1 => e.v[i][1],
            _ => e.v[i][1].conj(),
        };
        let row = |k: usize, j: usize| match k {
            0 | 1 => e.vinv[k][j],
            _ => e.vinv[1][j].conj(),
        };
        let lambda = [Complex::new(GAMMA, 0.0), e.mu, e.mu.conj()];
        for i in 0..3 {
            for j in 0..3 {
                let a: Complex<f64> = (0..3).map(|k| col(i, k) * lambda[k] * row(k, j)).sum();
                assert!(
                    (a.re - A[i][j]).abs() < 1e-15 && a.im.abs() < 1e-15,
                    "{i} {j} {a}"
                );
            }
        }
        let n = 6;
        let j = DMatrix::from_fn(n, n, |r, c| {
            let x = (r * 7 + c * 3) as f64;
            if r == c {
                -1e4 * (r + 1) as f64
            } else {
                (x * 0.37).sin() * 50.0
            }
        });
        let h = 0.013;
        let fac = Radau5::<3>::factorize(&j, h).unwrap();
        let mut m = DMatrix::<f64>::identity(3 * n, 3 * n);
        for bi in 0..3 {
            for bj in 0..3 {
                for r in 0..n {
                    for c in 0..n {
                        m[(bi * n + r, bj * n + c)] -= h * A[bi][bj] * j[(r, c)];
                    }
                }
            }
        }
        let r = DVector::from_fn(3 * n, |k, _| ((k * k) as f64 * 0.11).cos());
        let direct = m.lu().solve(&r).unwrap();
        let mut transformed = r.clone();
        assert!(fac.solve_stages(&mut transformed));
        let scale = direct.amax();
        for k in 0..3 * n {
            assert!((transformed[k] - direct[k]).abs() < 1e-13 * scale, "{k}");
        }
    }

    /// The embedded solution ŷ₁ = y₀ + h (γ f₀ + Σ b̂ⱼ fⱼ), b̂ = b + Aᵀ(γ e), has order 3: the
    /// estimate's weights satisfy Σ eᵢ cᵢ = −1, Σ eᵢ cᵢ² = Σ eᵢ cᵢ³ = 0 (these determine them).
    #[test]
    fn error_weights_make_an_order_3_embedding() {
        let m = |k: i32| -> f64 { (0..3).map(|i| E[i] * C[i].powi(k)).sum() };
        assert!((m(1) + 1.0).abs() < 1e-13, "{}", m(1));
        assert!(
            m(2).abs() < 1e-13 && m(3).abs() < 1e-13,
            "{} {}",
            m(2),
            m(3)
        );
        // ŷ's weights: b̂₀ = γ and b̂ = b + γ Aᵀe integrate 1, t, t² exactly, t³ not.
        let bhat: Vec<f64> = (0..3)
            .map(|j| A[2][j] + GAMMA * (0..3).map(|i| E[i] * A[i][j]).sum::<f64>())
            .collect();
        let quad = |k: i32| -> f64 {
            let b0 = if k == 0 { GAMMA } else { 0.0 };
            b0 + (0..3).map(|j| bhat[j] * C[j].powi(k)).sum::<f64>()
        };
        for k in 0..3 {
            assert!((quad(k) - 1.0 / f64::from(k + 1)).abs() < 1e-13, "k {k}");
        }
        assert!((quad(3) - 0.25).abs() > 1e-3);
    }

    /// A nonlinear system with everything the Jacobian must see: a configuration-dependent
    /// mass matrix, an explicit time dependence in L, a nonlinear dissipation and a force that
    /// depends on q, q̇ and t.
    struct Everything;
    impl Lagrangian<2> for Everything {
        const COORDINATES: [&'static str; 2] = ["a", "b"];
        const CYCLIC: [bool; 2] = [false, false];
        const AUTONOMOUS: bool = false;
        const ENERGY_CONSERVED: bool = false;
        fn lagrangian<S: crate::Scalar>(&self, q: &[S; 2], v: &[S; 2], t: S) -> S {
            let c = (q[0] - q[1]).cos();
            (v[0] * v[0] * 2.0 + v[1] * v[1] + c * v[0] * v[1]) * 0.5
                + q[0].cos() * (t.sin() * 0.3 + 1.0) * 9.0
                - q[1] * q[1] * 40.0
        }
        fn dissipation<S: crate::Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
            (v[0] * v[0] * (q[1] * q[1] + 1.0) + v[1] * v[1] * v[1] * v[1] * 0.1) * 0.5
        }
        fn generalized_forces<S: crate::Scalar>(&self, q: &[S; 2], v: &[S; 2], t: S) -> [S; 2] {
            [(t * 2.0).cos() * q[1] * 3.0, v[0] * q[0] * 0.7 - t.sin()]
        }
    }

    /// The Jacobian from the jets is ∂f/∂y: central differences of the right-hand side agree to
    /// their own truncation error, for forces, dissipation and explicit time alike.
    #[test]
    fn jacobian_is_the_derivative_of_the_right_hand_side() {
        let mut stats = Stats::default();
        let (t, y) = (0.7, [[0.4, -0.3], [1.1, 0.6]]);
        let r = Radau5::new(&Everything, t, y, 1e-8, 1e-8, 1.0, &mut stats).unwrap();
        let j = r.jacobian().unwrap();
        let d = 1e-6;
        for k in 0..4 {
            let (mut yp, mut ym) = (y, y);
            yp[k / 2][k % 2] += d;
            ym[k / 2][k % 2] -= d;
            let fp = rhs(&Everything, t, &yp, &mut stats).unwrap();
            let fm = rhs(&Everything, t, &ym, &mut stats).unwrap();
            for i in 0..4 {
                let fd = (at(&fp, i) - at(&fm, i)) / (2.0 * d);
                assert!(
                    (j[(i, k)] - fd).abs() <= 1e-7 * fd.abs().max(1.0),
                    "J[{i}][{k}] = {} vs {fd}",
                    j[(i, k)]
                );
            }
        }
    }

    /// ẍ = 1/(1 − x)²: the motion reaches x = 1 with infinite speed at a finite time. The run
    /// ends in a typed error (the steps shrink to the round-off limit), never a panic, with the
    /// trajectory up to there (measured: a step-size underflow 1e-9 before the collapse time); a Newton failure names the implicit step.
    struct Collapse;
    impl Lagrangian<1> for Collapse {
        const COORDINATES: [&'static str; 1] = ["x"];
        const CYCLIC: [bool; 1] = [false];
        const AUTONOMOUS: bool = true;
        fn lagrangian<S: crate::Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
            v[0] * v[0] * 0.5 + S::constant(1.0) / (S::constant(1.0) - q[0])
        }
    }

    #[test]
    fn a_singular_motion_ends_in_a_typed_error() {
        use crate::integrate::{Method, Simulation, SimulationError};
        let err = Simulation::new(&Collapse, [0.0], [0.0])
            .method(Method::Radau5 {
                rtol: 1e-8,
                atol: 1e-10,
            })
            .until(10.0)
            .run()
            .unwrap_err();
        let m = err.to_string();
        match &err {
            SimulationError::NewtonFailed { reason, .. } => {
                assert!(
                    reason.starts_with("Radau5") && m.contains("implicit step"),
                    "{m}"
                );
            }
            SimulationError::StepSizeUnderflow { .. }
            | SimulationError::NonFinite { .. }
            | SimulationError::Dynamics { .. } => {}
            other => panic!("{other}"),
        }
        let tr = err
            .partial_trajectory::<1>()
            .expect("the trajectory so far");
        // The collapse time of ẍ = 1/(1 − x)² from rest at 0 is π/(2√2) ≈ 1.11.
        let t_end = *tr.t.last().unwrap();
        let collapse = core::f64::consts::PI / (2.0 * core::f64::consts::SQRT_2);
        assert!((t_end - collapse).abs() < 1e-6, "{t_end}: {m}");
    }

    /// The dense polynomial passes through y₀ and the three stages, and reproduces a cubic.
    #[test]
    fn dense_output_interpolates_the_stages() {
        let cubic = |s: f64| {
            [
                [1.0 + 2.0 * s - s * s + 0.5 * s.powi(3)],
                [-3.0 * s.powi(3)],
            ]
        };
        let y0 = cubic(0.0);
        let z: [Y<1>; 3] = core::array::from_fn(|i| {
            let y = cubic(C[i]);
            [[y[0][0] - y0[0][0]], [y[1][0] - y0[1][0]]]
        });
        let r = collocation_rows(&y0, &z);
        for s in [0.0, C[0], C[1], 1.0, 0.37, 1.3] {
            let got = eval_dense(&r, s);
            let want = cubic(s);
            for c in 0..2 {
                assert!(
                    (got[c][0] - want[c][0]).abs() < 1e-14,
                    "s {s}: {got:?} {want:?}"
                );
            }
        }
    }
}
