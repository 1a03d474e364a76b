//! Linearization about equilibria and steady motions against closed forms: M, C, K, the
//! eigenvalues of M δq̈ + C δq̇ + K δq = 0, the normal modes, the stability classification, and
//! `equilibrium`.
//!
//! Tolerances are stated per test; the closed forms are derived in the comments (the heavy top's
//! from eqs. 92–98 of the reference text, section III D, and the free top's from the Euler
//! equations 83–85).

use lagrange::linearize::{equilibrium, Linearization, LinearizationError, Stability};
use lagrange::prelude::*;
use nalgebra::Complex;

// ---------------------------------------------------------------------------------------------
// Systems
// ---------------------------------------------------------------------------------------------

use crate::support::double_pendulum::DoublePendulum;
use crate::support::hand::Oscillator;

/// An N-link chain of point masses mᵢ on massless rods lᵢ, angles from the downward vertical.
struct Chain<const N: usize> {
    m: [f64; N],
    l: [f64; N],
    g: f64,
}

impl<const N: usize> Lagrangian<N> for Chain<N> {
    const COORDINATES: [&'static str; N] = ["theta"; N];
    const CYCLIC: [bool; N] = [false; N];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; N], v: &[S; N], _t: S) -> S {
        let zero = S::constant(0.0);
        let (mut y, mut vx, mut vy, mut l) = (zero, zero, zero, zero);
        for i in 0..N {
            let (s, c) = (q[i].sin(), q[i].cos());
            y -= c * self.l[i];
            vx += c * v[i] * self.l[i];
            vy += s * v[i] * self.l[i];
            l += (vx * vx + vy * vy) * (self.m[i] / 2.0) - y * (self.m[i] * self.g);
        }
        l
    }
}

/// A pendulum L = m l² θ̇²/2 + m g l cos θ, optionally pushed by a constant torque τ.
struct Pendulum {
    m: f64,
    l: f64,
    g: f64,
    torque: f64,
}

impl Lagrangian<1> for Pendulum {
    const COORDINATES: [&'static str; 1] = ["theta"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    const ENERGY_CONSERVED: bool = false;
    fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
        v[0] * v[0] * (self.m * self.l * self.l / 2.0) + q[0].cos() * (self.m * self.g * self.l)
    }
    fn generalized_forces<S: Scalar>(&self, _q: &[S; 1], _v: &[S; 1], _t: S) -> [S; 1] {
        [S::constant(self.torque)]
    }
}

/// A particle falling in uniform gravity (no equilibrium anywhere).
struct Falling;

impl Lagrangian<1> for Falling {
    const COORDINATES: [&'static str; 1] = ["z"];
    const CYCLIC: [bool; 1] = [false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 1], v: &[S; 1], _t: S) -> S {
        v[0] * v[0] * 0.5 - q[0] * 9.81
    }
}

/// A rigid body about a fixed point in Tait–Bryan angles (α, β, γ), R = Rx(α) Ry(β) Rz(γ)
/// (extrinsic z, then y, then x): regular wherever cos β ≠ 0, in particular at the identity.
/// Body angular velocity ω = Rᵀ Ṙ:
///   ω₁ = α̇ cos β cos γ + β̇ sin γ,  ω₂ = −α̇ cos β sin γ + β̇ cos γ,  ω₃ = α̇ sin β + γ̇.
/// Principal moments `i` about the body axes; the centre of mass at distance l along body z,
/// height l cos α cos β (lab z up), weight `mgl` (0 for the free top).
struct TaitBryanTop {
    i: [f64; 3],
    mgl: f64,
}

impl Lagrangian<3> for TaitBryanTop {
    const COORDINATES: [&'static str; 3] = ["alpha", "beta", "gamma"];
    // γ is absent only for a symmetric top (I₁ = I₂), α only without weight: claim neither
    const CYCLIC: [bool; 3] = [false, false, false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 3], v: &[S; 3], _t: S) -> S {
        let (sb, cb) = (q[1].sin(), q[1].cos());
        let (sg, cg) = (q[2].sin(), q[2].cos());
        let w1 = v[0] * cb * cg + v[1] * sg;
        let w2 = -(v[0] * cb * sg) + v[1] * cg;
        let w3 = v[0] * sb + v[2];
        (w1 * w1 * self.i[0] + w2 * w2 * self.i[1] + w3 * w3 * self.i[2]) * 0.5
            - q[0].cos() * cb * self.mgl
    }
}

/// The heavy symmetric top of eq. 92 in Euler angles (θ, φ, ψ), θ from the upward vertical.
struct EulerTop {
    i_perp: f64,
    i_par: f64,
    mgl: f64,
}

impl Lagrangian<3> for EulerTop {
    const COORDINATES: [&'static str; 3] = ["theta", "phi", "psi"];
    const CYCLIC: [bool; 3] = [false, true, true];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 3], v: &[S; 3], _t: S) -> S {
        let (s, c) = (q[0].sin(), q[0].cos());
        let spin = v[2] + v[1] * c;
        (v[0] * v[0] + v[1] * v[1] * s * s) * (self.i_perp / 2.0) + spin * spin * (self.i_par / 2.0)
            - c * self.mgl
    }
}

/// The Foucault pendulum (section E, per unit mass): the bob at (x, y, −√(l² − x² − y²)) in
/// local east–north–up axes rotating with Ω = Ω (0, cos λ, sin λ); L = |ṙ + Ω×r|²/2 − g z, or,
/// with the centrifugal term |Ω×r|²/2 absorbed in g (`centrifugal: false`),
/// L = |ṙ|²/2 + ṙ·(Ω×r) − g z.
struct Foucault {
    g: f64,
    l: f64,
    omega: Vector3<f64>,
    centrifugal: bool,
}

impl Lagrangian<2> for Foucault {
    const COORDINATES: [&'static str; 2] = ["x", "y"];
    const CYCLIC: [bool; 2] = [false, false];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
        let (x, y) = (q[0], q[1]);
        let z = -(-(x * x) - y * y + self.l * self.l).sqrt();
        let z_dot = -(x * v[0] + y * v[1]) / z;
        let om = self.omega.map(S::constant);
        let r = Vector3::new(x, y, z);
        let rdot = Vector3::new(v[0], v[1], z_dot);
        let frame = om.cross(&r);
        let centrifugal = if self.centrifugal {
            frame.norm_squared() * 0.5
        } else {
            S::constant(0.0)
        };
        rdot.norm_squared() * 0.5 + rdot.dot(&frame) + centrifugal - z * self.g
    }
}

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

fn close(what: &str, got: f64, want: f64, tol: f64) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: got {got:.17e}, want {want:.17e} (diff {:e}, tol {tol:e})",
        (got - want).abs()
    );
}

/// Every expected eigenvalue matched by a distinct computed one to `tol` (absolute).
fn assert_spectrum(got: &[Complex<f64>], want: &[Complex<f64>], tol: f64) {
    assert_eq!(got.len(), want.len(), "{got:?} vs {want:?}");
    let mut used = vec![false; got.len()];
    for w in want {
        let best = (0..got.len())
            .filter(|&i| !used[i])
            .min_by(|&a, &b| (got[a] - w).norm().total_cmp(&(got[b] - w).norm()));
        let i = best.expect("a free eigenvalue");
        assert!(
            (got[i] - w).norm() <= tol,
            "expected eigenvalue {w} not found (nearest {}, diff {:e}, tol {tol:e}) in {got:?}",
            got[i],
            (got[i] - w).norm()
        );
        used[i] = true;
    }
}

fn c(re: f64, im: f64) -> Complex<f64> {
    Complex::new(re, im)
}

// ---------------------------------------------------------------------------------------------
// Equilibria: double pendulum, chain, damped oscillator
// ---------------------------------------------------------------------------------------------

/// Double pendulum, unequal masses and lengths. M = [[(m₁+m₂)l₁², m₂l₁l₂], [m₂l₁l₂, m₂l₂²]],
/// K = diag((m₁+m₂)gl₁, m₂gl₂); det(K − ω²M) = 0, divided by m₂l₁l₂, is
/// m₁l₁l₂ω⁴ − (m₁+m₂)g(l₁+l₂)ω² + (m₁+m₂)g² = 0 (for any lengths). The first row of
/// (K − ω²M)v = 0 gives the shape θ₂/θ₁ = (m₁+m₂)(g − ω²l₁)/(m₂l₂ω²). Tolerance 1e-12 relative.
#[test]
fn double_pendulum_modes_match_the_quartic() {
    let (m1, m2, l1, l2, g) = (1.3, 0.7, 0.9, 1.6, 9.81);
    let p = DoublePendulum { m1, m2, l1, l2, g };
    let lin = p.linearize(&[0.0, 0.0], &[0.0, 0.0], 0.0).unwrap();
    assert_eq!(lin.c, SMatrix::<f64, 2, 2>::zeros());
    let (a, b, cc) = (m1 * l1 * l2, -(m1 + m2) * g * (l1 + l2), (m1 + m2) * g * g);
    let disc = (b * b - 4.0 * a * cc).sqrt();
    let roots = [(-b - disc) / (2.0 * a), (-b + disc) / (2.0 * a)];
    let modes = lin.modes().unwrap();
    for (mode, w2) in modes.iter().zip(roots) {
        close("ω²", mode.omega_squared, w2, 1e-12 * w2);
        let ratio = (m1 + m2) * (g - w2 * l1) / (m2 * l2 * w2);
        close(
            "θ₂/θ₁",
            mode.shape[1] / mode.shape[0],
            ratio,
            1e-12 * ratio.abs(),
        );
        let norm = (mode.shape.transpose() * lin.m * mode.shape)[(0, 0)];
        close("vᵀMv", norm, 1.0, 1e-12);
    }
    // M-orthogonal shapes
    let cross = (modes[0].shape.transpose() * lin.m * modes[1].shape)[(0, 0)];
    close("v₁ᵀMv₂", cross, 0.0, 1e-12);
    // the eigenvalues of the first-order system are ±iω
    let want: Vec<_> = roots
        .iter()
        .flat_map(|w2| [c(0.0, w2.sqrt()), c(0.0, -w2.sqrt())])
        .collect();
    assert_spectrum(&lin.eigenvalues().unwrap(), &want, 1e-12 * roots[1].sqrt());
    assert_eq!(lin.stability().unwrap(), Stability::MarginallyStable);
}

/// A 4-link chain at rest hanging down: M_jk = l_j l_k Σ_{i ≥ max(j,k)} m_i and
/// K = diag(g l_j Σ_{i ≥ j} m_i), written out by hand for m = (1, 2, 3, 4), l = (1, ½, 2, 3/2),
/// g = 10 (tail masses μ = 10, 9, 7, 4). Exact in binary, compared to 1e-13.
#[test]
fn chain_of_four_matches_hand_written_matrices() {
    let chain = Chain::<4> {
        m: [1.0, 2.0, 3.0, 4.0],
        l: [1.0, 0.5, 2.0, 1.5],
        g: 10.0,
    };
    let lin = chain.linearize(&[0.0; 4], &[0.0; 4], 0.0).unwrap();
    #[rustfmt::skip]
    let m = SMatrix::<f64, 4, 4>::from_row_slice(&[
        10.0, 4.5, 14.0,  6.0,
         4.5, 2.25, 7.0,  3.0,
        14.0, 7.0, 28.0, 12.0,
         6.0, 3.0, 12.0,  9.0,
    ]);
    let k = SMatrix::<f64, 4, 4>::from_diagonal(&nalgebra::Vector4::new(100.0, 45.0, 140.0, 60.0));
    assert!((lin.m - m).amax() <= 1e-13, "M = {}", lin.m);
    assert!((lin.k - k).amax() <= 1e-13, "K = {}", lin.k);
    assert_eq!(lin.c, SMatrix::<f64, 4, 4>::zeros());
    let modes = lin.modes().unwrap();
    assert!(modes.iter().all(|m| m.omega_squared > 0.0));
    // K v = ω² M v for every mode
    for mode in &modes {
        let r = lin.k * mode.shape - lin.m * mode.shape * mode.omega_squared;
        assert!(
            r.amax() <= 1e-11 * mode.omega_squared.max(1.0),
            "residual {r}"
        );
    }
    // at the top (every link inverted) every direction is unstable: K = −diag
    let top = chain
        .linearize(&[std::f64::consts::PI; 4], &[0.0; 4], 0.0)
        .unwrap();
    assert!((top.k + k).amax() <= 1e-12);
    assert!(matches!(
        top.stability().unwrap(),
        Stability::Unstable { .. }
    ));
}

/// m ẍ + b ẋ + k x = 0: M = m, C = b, K = k; λ = −γ ± iω_d, γ = b/2m, ω_d = √(k/m − γ²).
/// Tolerance 1e-14 relative.
#[test]
fn damped_oscillator_decays_at_gamma() {
    let (m, b, k) = (2.0, 0.6, 18.0);
    let lin = Oscillator {
        m,
        k,
        b,
        f: 0.0,
        w: 0.0,
    }
    .linearize(&[0.0], &[0.0], 0.0)
    .unwrap();
    assert_eq!((lin.m[(0, 0)], lin.c[(0, 0)], lin.k[(0, 0)]), (m, b, k));
    let (gamma, wd) = (b / (2.0 * m), (k / m - (b / (2.0 * m)).powi(2)).sqrt());
    assert_spectrum(
        &lin.eigenvalues().unwrap(),
        &[c(-gamma, wd), c(-gamma, -wd)],
        1e-14 * wd,
    );
    assert_eq!(lin.stability().unwrap(), Stability::AsymptoticallyStable);
    assert!(lin.is_stable());
    // no real normal modes with damping: a typed error
    assert!(matches!(
        lin.modes(),
        Err(LinearizationError::NotUndamped { .. })
    ));
}

// ---------------------------------------------------------------------------------------------
// Gyroscopic: Foucault
// ---------------------------------------------------------------------------------------------

/// The Foucault pendulum at Paris (λ = 48.85°, l = 67 m, Earth's rate), centrifugal term absorbed
/// in g: about the bottom x = y = 0, M = I, K = (g/l) I and C is skew (gyroscopic),
/// C₂₁ = −C₁₂ = 2Ω sin λ, so ω± = √(g/l + Ω² sin² λ) ± Ω sin λ: the two frequencies split by
/// exactly 2Ω sin λ (the swing plane turns at Ω sin λ). Tolerance 1e-10 relative.
///
/// With the centrifugal term kept, `equilibrium` finds the bottom pushed north by
/// y* ≈ Ω² sin λ cos λ l²/g ≈ 1.2 µm, and the splitting changes by O(y*/l) ≈ 2e-8 relative
/// (checked to 1e-7).
#[test]
fn foucault_frequencies_split_by_twice_the_vertical_rotation() {
    let (g, l, lat, om) = (9.81, 67.0, 48.85_f64.to_radians(), 7.292_115e-5);
    let split = 2.0 * om * lat.sin();
    let omega = Vector3::new(0.0, om * lat.cos(), om * lat.sin());
    let frequencies = |lin: &Linearization<2>| {
        let eig = lin.eigenvalues().unwrap();
        assert!(
            eig.iter().all(|l| l.re.abs() <= 1e-12 * l.norm()),
            "{eig:?}"
        );
        let mut f: Vec<f64> = eig.iter().filter(|l| l.im > 0.0).map(|l| l.im).collect();
        f.sort_by(f64::total_cmp);
        assert_eq!(f.len(), 2);
        f
    };

    let p = Foucault {
        g,
        l,
        omega,
        centrifugal: false,
    };
    assert_eq!(
        equilibrium(&p, &[1e-3, -2e-3], 0.0)
            .unwrap()
            .map(|x| x.abs() < 1e-15),
        [true; 2]
    );
    let lin = p.linearize(&[0.0, 0.0], &[0.0, 0.0], 0.0).unwrap();
    assert!((lin.c + lin.c.transpose()).amax() <= 1e-18, "C = {}", lin.c);
    close("C₂₁", lin.c[(1, 0)], split, 1e-10 * split);
    close("K₁₁", lin.k[(0, 0)], g / l, 1e-14);
    let f = frequencies(&lin);
    close("ω₊ − ω₋", f[1] - f[0], split, 1e-10 * split);
    let mean = (g / l + (split / 2.0).powi(2)).sqrt();
    close("(ω₊ + ω₋)/2", (f[1] + f[0]) / 2.0, mean, 1e-14);
    assert_eq!(lin.stability().unwrap(), Stability::MarginallyStable);
    // gyroscopic: no real modes
    assert!(matches!(
        lin.modes(),
        Err(LinearizationError::NotUndamped { .. })
    ));

    let full = Foucault {
        centrifugal: true,
        ..p
    };
    let q = equilibrium(&full, &[0.0, 0.0], 0.0).unwrap();
    let y_est = om * om * lat.sin() * lat.cos() * l * l / g;
    assert!(
        q[0].abs() < 1e-15 && (q[1] - y_est).abs() < 1e-3 * y_est,
        "bottom at {q:?}"
    );
    let f = frequencies(&full.linearize(&q, &[0.0, 0.0], 0.0).unwrap());
    close("ω₊ − ω₋ with centrifugal", f[1] - f[0], split, 1e-7 * split);
}

// ---------------------------------------------------------------------------------------------
// Steady motions: free top, sleeping top, steady precession
// ---------------------------------------------------------------------------------------------

/// Free asymmetric top, I₁ > I₂ > I₃, steady rotation ϖ about each principal axis. The chart
/// must make that rotation an equilibrium of an autonomous linearization: the rotation runs
/// along the first Tait–Bryan angle α (about the lab x axis, absent from L for a free body), the
/// moments permuted so that the spin axis is body x, and q₀ = 0, q̇₀ = (ϖ, 0, 0) (regular:
/// cos β = 1). (β, γ) then measure the body against the frame that turns with α, so the exponents
/// are those of the Euler equations (83–85) in the body: small ω₂, ω₃ about the spin axis c with
/// the other moments a, b grow like e^(μt), μ² = ϖ²(I_c − I_a)(I_b − I_c)/(I_a I_b): imaginary
/// about the largest and the smallest axis, real about the intermediate with growth rate
/// ϖ √((I₁ − I₂)(I₂ − I₃)/(I₁ I₃)). The orientation adds ±iϖ (a rotation about a neighbouring
/// fixed axis, seen from the turning frame) and λ = 0 twice (the rate of α drifts). Tolerance
/// 1e-10 relative.
#[test]
fn free_top_is_unstable_only_about_the_intermediate_axis() {
    let (i1, i2, i3, w) = (3.0, 2.0, 1.2, 1.7);
    for (moments, spin_axis) in [([i1, i2, i3], 1), ([i2, i3, i1], 2), ([i3, i1, i2], 3)] {
        let top = TaitBryanTop {
            i: moments,
            mgl: 0.0,
        };
        let qdot0 = [w, 0.0, 0.0];
        assert_eq!(top.accelerations(&[0.0; 3], &qdot0, 0.0).unwrap(), [0.0; 3]);
        let lin = top.linearize(&[0.0; 3], &qdot0, 0.0).unwrap();
        let [cc, a, b] = moments;
        let mu2 = w * w * (cc - a) * (b - cc) / (a * b);
        let mu = Complex::new(mu2, 0.0).sqrt();
        let want = [mu, -mu, c(0.0, w), c(0.0, -w)];
        let eig = lin.eigenvalues().unwrap();
        let (nonzero, zero): (Vec<_>, Vec<_>) = eig.iter().partition(|l| l.norm() > 1e-6 * w);
        assert_eq!(zero.len(), 2, "axis {spin_axis}: {eig:?}");
        assert_spectrum(&nonzero, &want, 1e-10 * w);
        match lin.stability().unwrap() {
            Stability::Unstable { growth_rate } => {
                assert_eq!(spin_axis, 2);
                let want = w * ((i1 - i2) * (i2 - i3) / (i1 * i3)).sqrt();
                close("growth rate", growth_rate, want, 1e-10 * want);
            }
            Stability::MarginallyStable => assert_ne!(spin_axis, 2),
            s => panic!("axis {spin_axis}: {s:?}"),
        }
    }
}

/// The sleeping top exactly upright (Example 1) in Tait–Bryan angles: q₀ = 0, q̇₀ = (0, 0, s).
/// With Ω = L∥/I⊥ = I∥ s/I⊥ and ω₀² = mgl/I⊥, the tilt u = β − iα obeys I⊥ü − iL∥u̇ − mgl u = 0
/// (linearizing eq. 98 about p = 1), so λ = i(Ω ± √(Ω² − 4ω₀²))/2 and conjugates: marginally
/// stable iff Ω > Ω_c = 2ω₀; below, λ = ±√(4ω₀² − Ω²)/2 ± iΩ/2 (growth rate √(4ω₀² − Ω²)/2, so
/// that 1 − p = θ²/2 grows at √(4ω₀² − Ω²) as eq. 98 gives). The cyclic spin angle adds λ = 0
/// twice. Tolerance 1e-10 relative.
#[test]
fn sleeping_top_is_stable_above_twice_omega_zero() {
    let (i_perp, i_par, mgl): (f64, f64, f64) = (1.4, 0.8, 2.3);
    let w0 = (mgl / i_perp).sqrt();
    let top = TaitBryanTop {
        i: [i_perp, i_perp, i_par],
        mgl,
    };
    // a dense sweep (the eigenvalue iteration must converge at every rate; 0.025 once stalled
    // the plain Schur iteration) and points close to the threshold
    let sweep = (0..=160)
        .map(|k| k as f64 / 40.0)
        .filter(|r| (r - 2.0).abs() > 1e-9);
    for ratio in sweep.chain([1.99, 2.01]) {
        let big_omega = ratio * w0;
        let spin = big_omega * i_perp / i_par;
        let lin = top.linearize(&[0.0; 3], &[0.0, 0.0, spin], 0.0).unwrap();
        let eig = lin.eigenvalues().unwrap();
        let d = big_omega * big_omega - 4.0 * w0 * w0;
        let want: Vec<Complex<f64>> = if d > 0.0 {
            let (hi, lo) = ((big_omega + d.sqrt()) / 2.0, (big_omega - d.sqrt()) / 2.0);
            vec![
                c(0.0, hi),
                c(0.0, -hi),
                c(0.0, lo),
                c(0.0, -lo),
                c(0.0, 0.0),
                c(0.0, 0.0),
            ]
        } else {
            let (re, im) = ((-d).sqrt() / 2.0, big_omega / 2.0);
            vec![
                c(re, im),
                c(re, -im),
                c(-re, im),
                c(-re, -im),
                c(0.0, 0.0),
                c(0.0, 0.0),
            ]
        };
        // the λ = 0 pair is a Jordan block (the spin rate drifts): computed to √ε only
        let (nonzero, zero): (Vec<_>, Vec<_>) = eig.iter().partition(|l| l.norm() > 1e-6 * w0);
        if ratio == 0.0 {
            // no spin: λ = ±ω₀ twice (each tilt a pendulum), plus the free spin angle's pair
            assert_spectrum(
                &nonzero,
                &[c(w0, 0.0), c(w0, 0.0), c(-w0, 0.0), c(-w0, 0.0)],
                1e-10,
            );
            continue;
        }
        assert_eq!(zero.len(), 2, "Ω/ω₀ = {ratio}: {eig:?}");
        assert_spectrum(&nonzero, &want[..4], 1e-10 * w0 * ratio.max(1.0));
        let stable = lin.stability().unwrap();
        if ratio > 2.0 {
            assert_eq!(stable, Stability::MarginallyStable, "Ω/ω₀ = {ratio}");
        } else {
            match stable {
                Stability::Unstable { growth_rate } => {
                    close("growth", growth_rate, (-d).sqrt() / 2.0, 1e-10 * w0)
                }
                s => panic!("Ω/ω₀ = {ratio}: {s:?}"),
            }
        }
    }
}

/// Steady precession of the heavy top (eq. 92, Euler angles): θ̇ = 0 at θ₀ with φ̇, ψ̇ chosen
/// so that θ̈ = 0, i.e. I∥φ̇ψ̇ = mgl + (I⊥ − I∥)φ̇² cos θ₀. The nutation is the small oscillation
/// of p = cos θ in ṗ² = f(p) (eq. 96) about its double root p* = cos θ₀: p̈ = f′(p)/2, so
/// ω² = −f″(p*)/2 = Ω² − ω₀²(6p* − 2p_E), and with p_E = p* + φ̇²(1 − p*²)/(2ω₀²) from eq. 95,
/// ω_nut² = Ω² − 4ω₀²p* + φ̇²(1 − p*²), Ω = I∥(ψ̇ + φ̇ cos θ₀)/I⊥. Tolerance 1e-10 relative.
#[test]
fn steady_precession_nutates_at_the_effective_potential_frequency() {
    let (i_perp, i_par, mgl) = (1.1, 0.6, 1.9);
    let top = EulerTop { i_perp, i_par, mgl };
    let w0sq = mgl / i_perp;
    for (theta0, phi_dot) in [(0.7, 0.9), (1.2, -0.4), (2.3, 1.6)] {
        let p = f64::cos(theta0);
        let psi_dot = (mgl + (i_perp - i_par) * phi_dot * phi_dot * p) / (i_par * phi_dot);
        let (q0, qdot0) = ([theta0, 0.3, -1.1], [0.0, phi_dot, psi_dot]);
        let a0 = top.accelerations(&q0, &qdot0, 0.0).unwrap();
        assert!(a0.iter().all(|a| a.abs() < 1e-12), "not steady: {a0:?}");
        let lin = top.linearize(&q0, &qdot0, 0.0).unwrap();
        let big_omega = i_par * (psi_dot + phi_dot * p) / i_perp;
        let want = (big_omega.powi(2) - 4.0 * w0sq * p + phi_dot * phi_dot * (1.0 - p * p)).sqrt();
        let eig = lin.eigenvalues().unwrap();
        let nut = eig.iter().fold(0.0_f64, |m, l| m.max(l.im));
        close(&format!("ω_nut at θ₀ = {theta0}"), nut, want, 1e-10 * want);
        assert!(eig.iter().all(|l| l.re.abs() <= 1e-6 * want), "{eig:?}");
        assert_eq!(lin.stability().unwrap(), Stability::MarginallyStable);
    }
}

// ---------------------------------------------------------------------------------------------
// The general formula at an arbitrary state, and `equilibrium`
// ---------------------------------------------------------------------------------------------

/// A non-autonomous system with velocity-dependent M, forces and dissipation, at an arbitrary
/// (non-steady) state: −M⁻¹K and −M⁻¹C must be the Jacobians ∂q̈/∂q and ∂q̈/∂q̇ of the solved
/// accelerations. Checked against Richardson-extrapolated central differences (test-only; the
/// library uses none), to 1e-7 of the scale.
#[test]
fn linearization_is_the_jacobian_of_the_accelerations_at_any_state() {
    struct Messy;
    impl Lagrangian<2> for Messy {
        const COORDINATES: [&'static str; 2] = ["a", "b"];
        const CYCLIC: [bool; 2] = [false, false];
        const AUTONOMOUS: bool = false;
        const ENERGY_CONSERVED: bool = false;
        const MOMENTUM_CONSERVED: [bool; 2] = [false, false];
        fn lagrangian<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], t: S) -> S {
            let m11 = q[1].cos() * 0.3 + 2.0 + (v[0] * v[0]) * 0.1;
            let m22 = (q[0] * t).sin() * 0.2 + 1.5;
            v[0] * v[0] * m11 * 0.5
                + v[1] * v[1] * m22 * 0.5
                + v[0] * v[1] * q[0].sin() * 0.4
                + v[0] * q[1] * t * 0.7
                - (q[0] * q[0] * 1.3 + q[1] * q[1] * q[1] * 0.2 - q[0] * q[1] * t.cos())
        }
        fn dissipation<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], _t: S) -> S {
            (v[0] * v[0] * (q[1] * q[1] + 1.0) + v[1] * v[1] * 0.3) * 0.25
        }
        fn generalized_forces<S: Scalar>(&self, q: &[S; 2], v: &[S; 2], t: S) -> [S; 2] {
            [(t * 2.0).sin() * q[1], v[0] * q[0] * 0.1]
        }
    }
    let (q, v, t) = ([0.4, -0.7], [1.1, -0.5], 0.9);
    let lin = Messy.linearize(&q, &v, t).unwrap();
    let minv = lin.m.try_inverse().unwrap();
    let (jq, jv) = (-minv * lin.k, -minv * lin.c);
    let acc = |q: [f64; 2], v: [f64; 2]| Messy.accelerations(&q, &v, t).unwrap();
    let fd = |j: usize, wrt_q: bool| {
        let d = |h: f64| {
            let (mut qp, mut qm, mut vp, mut vm) = (q, q, v, v);
            if wrt_q {
                qp[j] += h;
                qm[j] -= h;
            } else {
                vp[j] += h;
                vm[j] -= h;
            }
            let (p, m) = (acc(qp, vp), acc(qm, vm));
            [(p[0] - m[0]) / (2.0 * h), (p[1] - m[1]) / (2.0 * h)]
        };
        let (a, b) = (d(1e-3), d(5e-4));
        [(4.0 * b[0] - a[0]) / 3.0, (4.0 * b[1] - a[1]) / 3.0]
    };
    let scale = jq.amax().max(jv.amax()).max(1.0);
    for j in 0..2 {
        let (dq, dv) = (fd(j, true), fd(j, false));
        for i in 0..2 {
            close(&format!("∂q̈{i}/∂q{j}"), jq[(i, j)], dq[i], 1e-7 * scale);
            close(&format!("∂q̈{i}/∂q̇{j}"), jv[(i, j)], dv[i], 1e-7 * scale);
        }
    }
}

/// `equilibrium` finds the pendulum's bottom from a guess (and the tilted balance with a torque,
/// sin θ = τ/mgl), to 1e-14; it fails with the typed error, no panic, where there is none: a
/// torque larger than mgl, and uniform gravity (K = 0).
#[test]
fn equilibrium_finds_the_bottom_and_reports_when_there_is_none() {
    let p = Pendulum {
        m: 1.5,
        l: 0.8,
        g: 9.81,
        torque: 0.0,
    };
    let q = equilibrium(&p, &[0.9], 0.0).unwrap();
    close("bottom", q[0], 0.0, 1e-14);
    let lin = p.linearize(&q, &[0.0], 0.0).unwrap();
    close(
        "ω²",
        lin.modes().unwrap()[0].omega_squared,
        9.81 / 0.8,
        1e-12,
    );
    let mgl = 1.5 * 9.81 * 0.8;
    let tilted = Pendulum {
        torque: 0.3 * mgl,
        ..p
    };
    close(
        "tilted",
        equilibrium(&tilted, &[0.0], 0.0).unwrap()[0],
        0.3_f64.asin(),
        1e-14,
    );

    let pushed = Pendulum {
        torque: 1.5 * mgl,
        ..tilted
    };
    match equilibrium(&pushed, &[0.2], 0.0) {
        Err(e @ LinearizationError::NoEquilibrium { .. }) => {
            assert!(!e.to_string().is_empty());
        }
        other => panic!("expected NoEquilibrium, got {other:?}"),
    }
    match equilibrium(&Falling, &[1.0], 0.0) {
        Err(LinearizationError::NoEquilibrium { message, .. }) => {
            assert!(message.contains("K is singular"), "{message}")
        }
        other => panic!("expected NoEquilibrium, got {other:?}"),
    }
}

/// `Linearization` built by hand: the gyroscopic case goes through λ²M + λC + K, not M⁻¹K: a
/// spinning-shaft model M = I, C = [[0, −g], [g, 0]], K = diag(−k, −k) is unstable without the
/// gyroscopic coupling and stable with g² > 4k (λ = ±i(g ± √(g² − 4k))/2).
#[test]
fn gyroscopic_stabilization_needs_the_quadratic_eigenproblem() {
    let (gy, k) = (3.0, 1.0);
    let m = SMatrix::<f64, 2, 2>::identity();
    let cmat = SMatrix::<f64, 2, 2>::new(0.0, -gy, gy, 0.0);
    let kmat = SMatrix::<f64, 2, 2>::new(-k, 0.0, 0.0, -k);
    let lin = Linearization::new(m, cmat, kmat);
    let r = (gy * gy - 4.0 * k).sqrt();
    let (hi, lo) = ((gy + r) / 2.0, (gy - r) / 2.0);
    assert_spectrum(
        &lin.eigenvalues().unwrap(),
        &[c(0.0, hi), c(0.0, -hi), c(0.0, lo), c(0.0, -lo)],
        1e-13,
    );
    assert!(lin.is_stable());
    let bare = Linearization::new(m, SMatrix::zeros(), kmat);
    assert!(!bare.is_stable());
}
