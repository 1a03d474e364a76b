//! Geometry in a Lagrangian body: velocities of positions, rotations, angular velocities.
//!
//! In a `#[lagrangian]` body (both modes) a position written from the coordinates gives its
//! velocity with [`velocity`], and a rigid body's orientation is a [`Rotation`] built from
//! elementary rotations (or a unit quaternion), whose angular velocity in space axes
//! ([`angular_velocity`], Ṙ Rᵀ = ω̂) or body axes ([`body_angular_velocity`], Rᵀ Ṙ = ω̂) follows
//! from the rotation itself (the facade crate's docs show a heavy top written this way).
//!
//! Outside such a body (plain `f64`s, the jets) a number carries no rate and [`velocity`] is
//! NaN; the macro evaluates a body that names these functions in [`Timed`](crate::jet::Timed)
//! numbers, which do.

use core::ops::Mul;

use nalgebra::{Matrix3, Vector3};

use crate::mix::{ConstMul, Lift, MulConst};
use crate::scalar::{Scalar, Velocity};

/// The total time derivative d/dt x(q, t) = Σ ∂x/∂qᵢ q̇ᵢ + ∂x/∂t of a `Scalar` or a
/// `Vector3<Scalar>` computed from the coordinates (and time), of the same type.
///
/// ```
/// use lagrange_runtime::{geometry::velocity, jet::Timed};
/// use nalgebra::ComplexField;
/// let th = Timed::new(0.3_f64, 2.0); // θ = 0.3, θ̇ = 2
/// let x = th.sin() * 1.5; // x = l sin θ
/// assert!((velocity(x).value() - 1.5 * 0.3_f64.cos() * 2.0).abs() < 1e-15);
/// ```
#[inline(always)]
pub fn velocity<V: Velocity>(x: V) -> V {
    x.velocity()
}

/// A rotation matrix R (a proper orthogonal 3×3 matrix) whose entries are numbers of the body:
/// `R v` turns body components into space components.
///
/// ```
/// use lagrange_runtime::geometry::Rotation;
/// use nalgebra::Vector3;
/// let r = Rotation::about_z(core::f64::consts::FRAC_PI_2);
/// let v = r * Vector3::new(1.0, 0.0, 0.0);
/// assert!((v - Vector3::new(0.0, 1.0, 0.0)).norm() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rotation<S> {
    m: [[S; 3]; 3],
    /// The entries that are structurally 0 (bit 3i + j) and 1: an elementary rotation has five
    /// of them, and products skip them (in the jets mode each skipped product is a jet product).
    zero: u16,
    one: u16,
}

/// The bit of entry (i, j).
const fn bit(i: usize, j: usize) -> u16 {
    1 << (3 * i + j)
}

/// The structural 0s and 1s of an elementary rotation about axis `k` (the axis's row and column
/// are 0 but for a 1 on the diagonal).
const fn axis_flags(k: usize) -> (u16, u16) {
    let mut zero = 0;
    let mut i = 0;
    while i < 3 {
        if i != k {
            zero |= bit(i, k) | bit(k, i);
        }
        i += 1;
    }
    (zero, bit(k, k))
}

impl<S> Rotation<S> {
    /// A rotation with no structural entries known.
    fn dense(m: [[S; 3]; 3]) -> Self {
        Rotation { m, zero: 0, one: 0 }
    }

    /// An elementary rotation about axis `k`.
    fn elementary(m: [[S; 3]; 3], k: usize) -> Self {
        let (zero, one) = axis_flags(k);
        Rotation { m, zero, one }
    }
}

impl<S: Scalar> Rotation<S> {
    /// The rotation by angle `a` about the x axis.
    ///
    /// ```
    /// let r = lagrange_runtime::geometry::Rotation::about_x(0.5_f64);
    /// assert_eq!(r.matrix()[(2, 1)], 0.5_f64.sin());
    /// ```
    pub fn about_x(a: S) -> Self {
        let (s, c) = a.sin_cos();
        let (o, z) = (S::constant(1.0), S::constant(0.0));
        Rotation::elementary([[o, z, z], [z, c, -s], [z, s, c]], 0)
    }

    /// The rotation by angle `a` about the y axis.
    ///
    /// ```
    /// let r = lagrange_runtime::geometry::Rotation::about_y(0.5_f64);
    /// assert_eq!(r.matrix()[(0, 2)], 0.5_f64.sin());
    /// ```
    pub fn about_y(a: S) -> Self {
        let (s, c) = a.sin_cos();
        let (o, z) = (S::constant(1.0), S::constant(0.0));
        Rotation::elementary([[c, z, s], [z, o, z], [-s, z, c]], 1)
    }

    /// The rotation by angle `a` about the z axis.
    ///
    /// ```
    /// let r = lagrange_runtime::geometry::Rotation::about_z(0.5_f64);
    /// assert_eq!(r.matrix()[(1, 0)], 0.5_f64.sin());
    /// ```
    pub fn about_z(a: S) -> Self {
        let (s, c) = a.sin_cos();
        let (o, z) = (S::constant(1.0), S::constant(0.0));
        Rotation::elementary([[c, -s, z], [s, c, z], [z, z, o]], 2)
    }

    /// The rotation of the unit quaternion w + x i + y j + z k, in the homogeneous form
    /// (diagonal w² + x² − y² − z², …), which is |q|² times a rotation for any quaternion.
    ///
    /// ```
    /// use lagrange_runtime::geometry::Rotation;
    /// // (cos h, 0, 0, sin h) turns by 2h about z
    /// let h = core::f64::consts::FRAC_PI_8;
    /// let q = Rotation::from_quaternion(h.cos(), 0.0, 0.0, h.sin());
    /// let z = Rotation::about_z(2.0 * h);
    /// assert!((q.matrix() - z.matrix()).norm() < 1e-15);
    /// ```
    pub fn from_quaternion(w: S, x: S, y: S, z: S) -> Self {
        let (ww, xx, yy, zz) = (w * w, x * x, y * y, z * z);
        let (xy, zw, xz, yw, yz, xw) = (x * y, z * w, x * z, y * w, y * z, x * w);
        let two = 2.0;
        Rotation::dense([
            [ww + xx - yy - zz, (xy - zw) * two, (xz + yw) * two],
            [(xy + zw) * two, ww - xx + yy - zz, (yz - xw) * two],
            [(xz - yw) * two, (yz + xw) * two, ww - xx - yy + zz],
        ])
    }

    /// The identity rotation.
    ///
    /// ```
    /// let r = lagrange_runtime::geometry::Rotation::<f64>::identity();
    /// assert_eq!(r.matrix(), nalgebra::Matrix3::identity());
    /// ```
    pub fn identity() -> Self {
        let (o, z) = (S::constant(1.0), S::constant(0.0));
        Rotation {
            m: [[o, z, z], [z, o, z], [z, z, o]],
            zero: 0x1ff & !(bit(0, 0) | bit(1, 1) | bit(2, 2)),
            one: bit(0, 0) | bit(1, 1) | bit(2, 2),
        }
    }

    /// Rᵀ, the inverse rotation.
    ///
    /// ```
    /// let r = lagrange_runtime::geometry::Rotation::about_x(0.5_f64);
    /// assert_eq!(r.transpose().matrix(), r.matrix().transpose());
    /// ```
    pub fn transpose(&self) -> Self {
        let m = &self.m;
        let flip = |f: u16| {
            (0..9).fold(0, |acc, ij| {
                let (i, j) = (ij / 3, ij % 3);
                if f & bit(j, i) != 0 {
                    acc | bit(i, j)
                } else {
                    acc
                }
            })
        };
        Rotation {
            m: core::array::from_fn(|i| core::array::from_fn(|j| m[j][i])),
            zero: flip(self.zero),
            one: flip(self.one),
        }
    }

    /// The matrix, as an nalgebra `Matrix3`.
    ///
    /// ```
    /// let r = lagrange_runtime::geometry::Rotation::about_y(0.0_f64);
    /// assert_eq!(r.matrix(), nalgebra::Matrix3::identity());
    /// ```
    pub fn matrix(&self) -> Matrix3<S> {
        Matrix3::from_fn(|i, j| self.m[i][j])
    }
}

/// How one entry of a product is formed from the two factors' entries (of types `A` and `B`):
/// their product, or one factor alone where the other is a structural 1.
trait Factors<A, B, S> {
    fn mul(a: A, b: B) -> S;
    fn from_a(a: A) -> S;
    fn from_b(b: B) -> S;
}

/// Both factors of the number type.
struct Same;
/// A constant (left) and a variable (right).
struct ConstVar;
/// A variable (left) and a constant (right).
struct VarConst;

impl<S: Scalar> Factors<S, S, S> for Same {
    fn mul(a: S, b: S) -> S {
        a * b
    }
    fn from_a(a: S) -> S {
        a
    }
    fn from_b(b: S) -> S {
        b
    }
}

impl<S: Scalar> Factors<f64, S, S> for ConstVar {
    fn mul(c: f64, x: S) -> S {
        x * c
    }
    fn from_a(c: f64) -> S {
        S::constant(c)
    }
    fn from_b(x: S) -> S {
        x
    }
}

impl<S: Scalar> Factors<S, f64, S> for VarConst {
    fn mul(x: S, c: f64) -> S {
        x * c
    }
    fn from_a(x: S) -> S {
        x
    }
    fn from_b(c: f64) -> S {
        S::constant(c)
    }
}

/// R₁ R₂, skipping the structural 0s and 1s of both.
fn compose<A: Copy, B: Copy, S: Scalar, F: Factors<A, B, S>>(
    a: &Rotation<A>,
    b: &Rotation<B>,
) -> Rotation<S> {
    let mut m = [[S::constant(0.0); 3]; 3];
    let (mut zero, mut one) = (0, 0);
    for i in 0..3 {
        for j in 0..3 {
            let mut acc: Option<S> = None;
            let mut unit = false;
            for k in 0..3 {
                if a.zero & bit(i, k) != 0 || b.zero & bit(k, j) != 0 {
                    continue;
                }
                let (ao, bo) = (a.one & bit(i, k) != 0, b.one & bit(k, j) != 0);
                let term = match (ao, bo) {
                    (true, _) => F::from_b(b.m[k][j]),
                    (false, true) => F::from_a(a.m[i][k]),
                    _ => F::mul(a.m[i][k], b.m[k][j]),
                };
                unit = acc.is_none() && ao && bo;
                acc = Some(match acc {
                    Some(x) => x + term,
                    None => term,
                });
            }
            match acc {
                None => zero |= bit(i, j),
                Some(x) => {
                    m[i][j] = x;
                    if unit {
                        one |= bit(i, j);
                    }
                }
            }
        }
    }
    Rotation { m, zero, one }
}

/// R v, skipping R's structural 0s and 1s.
fn apply<A: Copy, B: Copy, S: Scalar, F: Factors<A, B, S>>(
    a: &Rotation<A>,
    v: [B; 3],
) -> Vector3<S> {
    Vector3::from_fn(|i, _| {
        let mut acc: Option<S> = None;
        for (k, &vk) in v.iter().enumerate() {
            if a.zero & bit(i, k) != 0 {
                continue;
            }
            let term = if a.one & bit(i, k) != 0 {
                F::from_b(vk)
            } else {
                F::mul(a.m[i][k], vk)
            };
            acc = Some(match acc {
                Some(x) => x + term,
                None => term,
            });
        }
        acc.unwrap_or_else(|| S::constant(0.0))
    })
}

impl<S: Scalar> Mul for Rotation<S> {
    type Output = Rotation<S>;
    #[inline]
    fn mul(self, o: Rotation<S>) -> Rotation<S> {
        compose::<_, _, _, Same>(&self, &o)
    }
}

impl<S: Scalar> Mul<Vector3<S>> for Rotation<S> {
    type Output = Vector3<S>;
    #[inline]
    fn mul(self, v: Vector3<S>) -> Vector3<S> {
        apply::<_, _, _, Same>(&self, [v.x, v.y, v.z])
    }
}

impl<S: Scalar> Mul<&Vector3<S>> for &Rotation<S> {
    type Output = Vector3<S>;
    #[inline]
    fn mul(self, v: &Vector3<S>) -> Vector3<S> {
        apply::<_, _, _, Same>(self, [v.x, v.y, v.z])
    }
}

impl<S: Scalar> Lift<S> for Rotation<f64> {
    type Output = Rotation<S>;
    #[inline]
    fn lift(self) -> Rotation<S> {
        Rotation {
            m: self.m.map(|row| row.map(S::constant)),
            zero: self.zero,
            one: self.one,
        }
    }
}

impl<S: Scalar> ConstMul<Rotation<S>> for Rotation<f64> {
    type Output = Rotation<S>;
    #[inline]
    fn const_mul(self, r: Rotation<S>) -> Rotation<S> {
        compose::<_, _, _, ConstVar>(&self, &r)
    }
}

impl<S: Scalar> MulConst<Rotation<f64>> for Rotation<S> {
    type Output = Rotation<S>;
    #[inline]
    fn mul_const(self, r: Rotation<f64>) -> Rotation<S> {
        compose::<_, _, _, VarConst>(&self, &r)
    }
}

impl<S: Scalar> ConstMul<Vector3<S>> for Rotation<f64> {
    type Output = Vector3<S>;
    #[inline]
    fn const_mul(self, v: Vector3<S>) -> Vector3<S> {
        apply::<_, _, _, ConstVar>(&self, [v.x, v.y, v.z])
    }
}

impl<S: Scalar> MulConst<Vector3<f64>> for Rotation<S> {
    type Output = Vector3<S>;
    #[inline]
    fn mul_const(self, v: Vector3<f64>) -> Vector3<S> {
        // A constant vector's exact zeros (`Vector3::z()`) cost nothing either.
        let r = Rotation {
            m: self.m,
            zero: self.zero
                | (0..9).fold(0, |acc, ij| {
                    if v[ij % 3] == 0.0 {
                        acc | bit(ij / 3, ij % 3)
                    } else {
                        acc
                    }
                }),
            one: self.one,
        };
        apply::<_, _, _, VarConst>(&r, [v.x, v.y, v.z])
    }
}

/// Σₖ a(k) b(k) over k = 0, 1, 2.
#[inline(always)]
fn dot3<S: Scalar>(a: impl Fn(usize) -> S, b: impl Fn(usize) -> S) -> S {
    a(0) * b(0) + a(1) * b(1) + a(2) * b(2)
}

/// The angular velocity ω of a rotation R(q, t) in space axes: Ṙ Rᵀ = ω̂.
///
/// ```
/// use lagrange_runtime::{geometry::{angular_velocity, Rotation}, jet::Timed};
/// // about z at rate 3: ω = (0, 0, 3) whatever the angle
/// let r = Rotation::about_z(Timed::new(0.7_f64, 3.0));
/// let w = angular_velocity(&r);
/// assert!((w.z.value() - 3.0).abs() < 1e-15 && w.x.value().abs() < 1e-15);
/// ```
pub fn angular_velocity<S: Scalar>(r: &Rotation<S>) -> Vector3<S> {
    let m = &r.m;
    let rate = |i: usize, k: usize| m[i][k].velocity();
    Vector3::new(
        dot3(|k| rate(2, k), |k| m[1][k]),
        dot3(|k| rate(0, k), |k| m[2][k]),
        dot3(|k| rate(1, k), |k| m[0][k]),
    )
}

/// The angular velocity ω of a rotation R(q, t) in body axes: Rᵀ Ṙ = ω̂.
///
/// ```
/// use lagrange_runtime::{geometry::{body_angular_velocity, Rotation}, jet::Timed};
/// // tilted by 0.4 about x, spinning about the body's z at rate 2: ω_body = (0, 0, 2)
/// let r = Rotation::about_x(Timed::new(0.4_f64, 0.0)) * Rotation::about_z(Timed::new(1.0, 2.0));
/// let w = body_angular_velocity(&r);
/// assert!((w.z.value() - 2.0).abs() < 1e-15 && w.y.value().abs() < 1e-15);
/// ```
pub fn body_angular_velocity<S: Scalar>(r: &Rotation<S>) -> Vector3<S> {
    let m = &r.m;
    let rate = |k: usize, j: usize| m[k][j].velocity();
    Vector3::new(
        dot3(|k| m[k][2], |k| rate(k, 1)),
        dot3(|k| m[k][0], |k| rate(k, 2)),
        dot3(|k| m[k][1], |k| rate(k, 0)),
    )
}
