//! [`Lanes`]: W numbers side by side, one per ensemble member, so that one pass of straight-line
//! code (the generated accelerations, the stages of DOP853) advances W members at once.
//!
//! Every operation is the `f64` operation applied lane by lane, in the same order: a lane's
//! result is bit for bit what the scalar code computes for that member (the lane-vs-scalar tests
//! rely on it) — but for two things. The elementary functions (`exp`, `ln`, …) call the scalar
//! `f64` method per lane, so they round exactly as the scalar run does, but for sin and cos, a
//! vector polynomial within 1 ulp of the `f64` methods ([`Lanes::sin_cos`]). And `Lanes<W, true>`
//! (fused) rounds each [`madd`](Lanes::madd) once, as a fused multiply-add, where the single run
//! rounds twice: the ensemble engines' paths for CPUs with FMA, within round-off of the exact
//! ones. Arithmetic is written as loops over a fixed-size array, which LLVM turns into vector
//! instructions (the engines compile them for AVX2 and for AVX2 with FMA, chosen at run time:
//! [`Simd`](crate::ensemble::Simd)).
//!
//! ```
//! use lagrange_runtime::{lanes::Lanes, real::Real};
//! let x: Lanes<4> = Lanes::from([1.0, 2.0, 3.0, 4.0]);
//! let y = 2.0 * x + x * x;
//! assert_eq!(y.0, [3.0, 8.0, 15.0, 24.0]);
//! assert_eq!(x.sqrt().0[3], 2.0);
//! ```

use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

/// W `f64`s operated on lane by lane (see the module docs). `FUSED`: whether
/// [`madd`](Lanes::madd) (x · a + b) rounds once, as a fused multiply-add (the ensemble engines'
/// paths for CPUs with FMA), or twice, as the single run computes it (`false`, the default).
/// Aligned to 32 bytes, an AVX2 vector, wherever it is stored: no load of a buffer of them
/// straddles two cache lines.
///
/// ```
/// # use lagrange_runtime::lanes::Lanes;
/// assert_eq!(Lanes::<2>::splat(1.5).0, [1.5, 1.5]);
/// let series = vec![Lanes::<8>::splat(0.0); 21];
/// assert_eq!((core::mem::align_of::<Lanes<8>>(), series.as_ptr() as usize % 32), (32, 0));
/// let x = 1.0 + f64::EPSILON;
/// // (1 + ε)(1 + ε) − (1 + 2ε) = ε²: lost to the rounding of the product unless it is fused.
/// assert_eq!(Lanes::<1>::splat(x).madd(Lanes::<1>([x]), Lanes::<1>([-1.0 - 2.0 * f64::EPSILON])).0, [0.0]);
/// let fused: Lanes<1, true> = Lanes([x]);
/// assert_eq!(fused.madd(Lanes([x]), Lanes([-1.0 - 2.0 * f64::EPSILON])).0, [f64::EPSILON * f64::EPSILON]);
/// ```
// Aligned to an AVX2 vector (32 bytes): without it a buffer of them starts wherever the
// allocator puts it (16-byte aligned), and at 16 or 48 bytes into a cache line every other
// 32-byte load of the Taylor series (8 lanes: 64 bytes an entry) straddles two lines — one
// run in two slower by 10–25 % by the luck of its heap layout (BENCHMARKS.md, "Two threads at
// 1.97×: the lanes aligned").
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(align(32))]
pub struct Lanes<const W: usize, const FUSED: bool = false>(pub [f64; W]);

/// W booleans, one per lane: what a comparison of [`Lanes`] gives and [`Lanes::select`] takes.
///
/// ```
/// # use lagrange_runtime::lanes::{Lanes, Mask};
/// let m: Mask<2> = Lanes::<2>([1.0, -1.0]).ge(0.0);
/// assert_eq!(m.0, [true, false]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Mask<const W: usize>(pub [bool; W]);

impl<const W: usize> core::ops::BitAnd for Mask<W> {
    type Output = Self;
    #[inline(always)]
    fn bitand(self, rhs: Self) -> Self {
        Mask(core::array::from_fn(|l| self.0[l] & rhs.0[l]))
    }
}

impl<const W: usize> Mask<W> {
    /// `b` in every lane.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Mask;
    /// assert_eq!(Mask::<2>::splat(true).0, [true, true]);
    /// ```
    #[inline(always)]
    pub fn splat(b: bool) -> Self {
        Mask([b; W])
    }

    /// Whether every lane is set.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Mask;
    /// assert!(Mask([true, true]).all() && !Mask([true, false]).all());
    /// ```
    #[inline(always)]
    pub fn all(self) -> bool {
        self.0.iter().fold(true, |a, &b| a & b)
    }

    /// The mask with lane l = `f(l)`.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Mask;
    /// assert_eq!(Mask::<3>::from_fn(|l| l == 1).0, [false, true, false]);
    /// ```
    #[inline(always)]
    pub fn from_fn(f: impl FnMut(usize) -> bool) -> Self {
        Mask(core::array::from_fn(f))
    }
}

impl<const W: usize, const F: bool> From<[f64; W]> for Lanes<W, F> {
    #[inline(always)]
    fn from(a: [f64; W]) -> Self {
        Lanes(a)
    }
}

impl<const W: usize, const F: bool> From<f64> for Lanes<W, F> {
    #[inline(always)]
    fn from(x: f64) -> Self {
        Lanes([x; W])
    }
}

impl<const W: usize, const F: bool> Default for Lanes<W, F> {
    #[inline(always)]
    fn default() -> Self {
        Lanes([0.0; W])
    }
}

impl<const W: usize, const F: bool> Lanes<W, F> {
    /// Not a number in every lane.
    pub const NAN: Self = Lanes([f64::NAN; W]);
    /// +∞ in every lane.
    pub const INFINITY: Self = Lanes([f64::INFINITY; W]);
    /// −∞ in every lane.
    pub const NEG_INFINITY: Self = Lanes([f64::NEG_INFINITY; W]);
    /// Zero in every lane.
    pub const ZERO: Self = Lanes([0.0; W]);

    /// `x` in every lane.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes::<3>::splat(2.0).0, [2.0; 3]);
    /// ```
    #[inline(always)]
    pub fn splat(x: f64) -> Self {
        Lanes([x; W])
    }

    /// The lanes l ↦ `f(l)`.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes::<3>::from_fn(|l| l as f64).0, [0.0, 1.0, 2.0]);
    /// ```
    #[inline(always)]
    pub fn from_fn(f: impl FnMut(usize) -> f64) -> Self {
        Lanes(core::array::from_fn(f))
    }

    /// `f` applied to every lane.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes::<2>([1.0, 4.0]).map(|x| x + 1.0).0, [2.0, 5.0]);
    /// ```
    #[inline(always)]
    pub fn map(self, mut f: impl FnMut(f64) -> f64) -> Self {
        let mut out = self.0;
        for x in &mut out {
            *x = f(*x);
        }
        Lanes(out)
    }

    /// `f` applied lane by lane to `self` and `other`.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes::<2>([1.0, 4.0]).zip(Lanes::<2>([2.0, 3.0]), f64::max).0, [2.0, 4.0]);
    /// ```
    #[inline(always)]
    pub fn zip(self, other: Self, mut f: impl FnMut(f64, f64) -> f64) -> Self {
        let mut out = self.0;
        for l in 0..W {
            out[l] = f(out[l], other.0[l]);
        }
        Lanes(out)
    }

    /// Lane l of `a` where `mask` is set, else lane l of `b`.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::{Lanes, Mask};
    /// let s = Lanes::select(Mask([true, false]), 1.0, Lanes::<2>([5.0, 6.0]));
    /// assert_eq!(s.0, [1.0, 6.0]);
    /// ```
    #[inline(always)]
    pub fn select(mask: Mask<W>, a: impl Into<Self>, b: impl Into<Self>) -> Self {
        let (a, b) = (a.into(), b.into());
        Lanes(core::array::from_fn(|l| {
            if mask.0[l] { a.0[l] } else { b.0[l] }
        }))
    }

    /// `self · a + b` lane by lane, rounded once (a fused multiply-add) where `FUSED`, else
    /// twice (the product, then the sum: the single run's arithmetic).
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes::<2>([2.0, 3.0]).madd(Lanes::<2>([4.0, 0.5]), Lanes::<2>([1.0, -1.0])).0, [9.0, 0.5]);
    /// ```
    #[inline(always)]
    pub fn madd(self, a: Self, b: Self) -> Self {
        Lanes(core::array::from_fn(|l| {
            if F {
                self.0[l].mul_add(a.0[l], b.0[l])
            } else {
                self.0[l] * a.0[l] + b.0[l]
            }
        }))
    }

    /// The lanes where `self ≥ x`.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes::<2>([0.0, -0.5]).ge(0.0).0, [true, false]);
    /// ```
    #[inline(always)]
    pub fn ge(self, x: impl Into<Self>) -> Mask<W> {
        let x = x.into();
        Mask(core::array::from_fn(|l| self.0[l] >= x.0[l]))
    }

    /// The lanes where `self > x` (not where either is NaN): the generated solve's pivot test,
    /// per lane.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes::<2>([1.0, f64::NAN]).gt(0.5).0, [true, false]);
    /// ```
    #[inline(always)]
    pub fn gt(self, x: impl Into<Self>) -> Mask<W> {
        let x = x.into();
        Mask(core::array::from_fn(|l| self.0[l] > x.0[l]))
    }

    /// The finite lanes.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes::<2>([1.0, f64::INFINITY]).finite().0, [true, false]);
    /// ```
    #[inline(always)]
    pub fn finite(self) -> Mask<W> {
        Mask(core::array::from_fn(|l| self.0[l].is_finite()))
    }

    /// Whether `self > x` in every lane (false if any lane is NaN).
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert!(Lanes::<2>([1.0, 2.0]).all_gt(0.5));
    /// assert!(!Lanes::<2>([1.0, f64::NAN]).all_gt(0.5));
    /// ```
    #[inline(always)]
    pub fn all_gt(self, x: impl Into<Self>) -> bool {
        let x = x.into();
        // Non-short-circuit `&`: one vector compare, no branch per lane.
        (0..W).fold(true, |ok, l| ok & (self.0[l] > x.0[l]))
    }

    /// Whether every lane is finite.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert!(Lanes::<2>([1.0, 2.0]).all_finite());
    /// assert!(!Lanes::<2>([1.0, f64::INFINITY]).all_finite());
    /// ```
    #[inline(always)]
    pub fn all_finite(self) -> bool {
        (0..W).fold(true, |ok, l| ok & self.0[l].is_finite())
    }

    /// The Heaviside step lane by lane: 1 where `self ≥ 0`, else 0.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// assert_eq!(Lanes::<2>([0.0, -1.0]).step().0, [1.0, 0.0]);
    /// ```
    #[inline(always)]
    pub fn step(self) -> Self {
        self.map(|x| if x >= 0.0 { 1.0 } else { 0.0 })
    }

    /// (sin, cos) of every lane, as one vector computation: the argument reduced by π/2 in three
    /// parts (Cody–Waite), the minimax polynomials of sin and cos of degree 13 and 14 on
    /// [−π/4, π/4] (fdlibm's), the quadrant applied with sign and swap masks. Within 1 ulp of the `f64`
    /// methods (tested against them on 10⁶ arguments), so a lane differs from the scalar run by
    /// round-off; a lane with |x| > 10⁵ (or not finite) takes the `f64` method.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// let (s, c) = Lanes::<4>([0.0, 1.0, -2.5, 30.0]).sin_cos();
    /// for (l, x) in [0.0_f64, 1.0, -2.5, 30.0].iter().enumerate() {
    ///     assert!((s.0[l] - x.sin()).abs() <= 2.3e-16 && (c.0[l] - x.cos()).abs() <= 2.3e-16);
    /// }
    /// ```
    #[inline(always)]
    pub fn sin_cos(self) -> (Self, Self) {
        let (mut s, mut c) = sin_cos_reduced(self);
        if !self.all_le_abs(1e5) {
            // Lane by lane, so a lane's value never depends on the other lanes.
            for l in 0..W {
                let reduced = self.0[l].abs() <= 1e5;
                if !reduced {
                    (s.0[l], c.0[l]) = self.0[l].sin_cos();
                }
            }
        }
        (s, c)
    }

    /// ln of every lane as one vector computation: x = 2ᵏ (1 + f) with √2/2 ≤ 1 + f < √2 from the
    /// bits, s = f / (2 + f), ln(1 + f) = f − f²/2 + s (f²/2 + R(s²)) with the minimax polynomial R
    /// of fdlibm's `__ieee754_log`, k ln 2 in two parts. Within 1 ulp of `f64::ln` (tested on 10⁶
    /// arguments over 600 binades); a lane that is not a positive normal number (0, subnormal,
    /// negative, ∞, NaN) takes `f64::ln`. What the fused lanes' [`Real::ln`](crate::real::Real::ln)
    /// computes; the exact lanes call `f64::ln` per lane.
    ///
    /// ```
    /// # use lagrange_runtime::lanes::Lanes;
    /// let x = Lanes::<4>([1.0, 0.5, 10.0, 1e-300]);
    /// let y = x.ln_vector();
    /// for l in 0..4 {
    ///     assert!((y.0[l] - x.0[l].ln()).abs() <= 2.0 * f64::EPSILON * x.0[l].ln().abs());
    /// }
    /// assert_eq!(Lanes::<2>([0.0, -1.0]).ln_vector().0[0], f64::NEG_INFINITY);
    /// ```
    #[inline(always)]
    pub fn ln_vector(self) -> Self {
        if !(0..W).fold(true, |ok, l| {
            ok & (self.0[l] >= f64::MIN_POSITIVE) & (self.0[l] < f64::INFINITY)
        }) {
            // Lane by lane, so a lane's value never depends on the other lanes.
            return self.map(f64::ln);
        }
        ln_normal(self)
    }

    /// Whether |x| ≤ `bound` in every lane (false for NaN).
    #[inline(always)]
    fn all_le_abs(self, bound: f64) -> bool {
        (0..W).fold(true, |ok, l| ok & (self.0[l].abs() <= bound))
    }
}

/// π/2 in three parts: the first two of 33 significant bits (so n·P1 and n·P2 are exact for
/// |n| < 2²⁰), the third the rest rounded.
const PIO2_1: f64 = 1.570_796_326_734_125_6;
const PIO2_2: f64 = 6.077_100_506_303_966e-11;
const PIO2_3: f64 = 2.022_266_248_795_950_6e-21;
/// 1.5 · 2⁵²: v + M − M rounds v (|v| < 2⁵¹) to the nearest integer, and the low bits of v + M
/// are that integer modulo 2⁵².
const ROUND: f64 = 6_755_399_441_055_744.0;
/// sin r = r + r³ Σ S_k r²ᵏ on |r| ≤ π/4: fdlibm's minimax coefficients (`__kernel_sin`).
const SIN: [f64; 6] = [
    -1.666_666_666_666_663_2e-1,
    8.333_333_333_322_49e-3,
    -1.984_126_982_985_795e-4,
    2.755_731_370_707_006_8e-6,
    -2.505_076_025_340_686_3e-8,
    1.589_690_995_211_55e-10,
];
/// cos r = 1 − r²/2 + r⁴ Σ C_k r²ᵏ on |r| ≤ π/4: fdlibm's minimax coefficients
/// (`__kernel_cos`).
const COS: [f64; 6] = [
    4.166_666_666_666_66e-2,
    -1.388_888_888_887_411e-3,
    2.480_158_728_947_673e-5,
    -2.755_731_435_139_066_3e-7,
    2.087_572_321_298_175e-9,
    -1.135_964_755_778_819_5e-11,
];

/// (sin x, cos x) of every lane for |x| ≤ 10⁵, without branches or calls, each operation a
/// loop over the lanes (vector code): x = n π/2 + r with |r| ≤ π/4, the polynomials at r, and
/// the quadrant n mod 4 applied by swapping and negating through the bits.
#[inline(always)]
fn sin_cos_reduced<const W: usize, const F: bool>(x: Lanes<W, F>) -> (Lanes<W, F>, Lanes<W, F>) {
    let shifted = x * core::f64::consts::FRAC_2_PI + ROUND;
    let n = shifted - ROUND;
    // r + r_lo = x − n π/2 to about 2⁻¹⁰⁶ relative: x − n·P1 is exact (Sterbenz), n·P2 too,
    // and the rounding errors of the two subtractions are carried in r_lo (Fast2Sum).
    let a = x - n * PIO2_1;
    let b = n * PIO2_2;
    let r0 = a - b;
    let lo0 = (a - r0) - b;
    let c3 = n * PIO2_3;
    let r = r0 - c3;
    let r_lo = ((r0 - r) - c3) + lo0;
    let z = r * r;
    let mut ps = Lanes::splat(SIN[5]);
    let mut pc = Lanes::splat(COS[5]);
    for k in (0..5).rev() {
        ps = ps.madd(z, Lanes::splat(SIN[k]));
        pc = pc.madd(z, Lanes::splat(COS[k]));
    }
    // sin(r + r_lo) ≈ sin r + r_lo cos r and cos(r + r_lo) ≈ cos r − r_lo sin r, with
    // 1 − z/2 carrying its rounding error (fdlibm's kernels).
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    let sin_r = r + (r * z * ps + r_lo * w);
    let cos_r = w + (((1.0 - w) - hz) + (z * z * pc - r * r_lo));
    // Quadrant: odd n swaps sin and cos; sin is negated for n mod 4 ∈ {2, 3}, cos for {1, 2}.
    let mut s = [0.0; W];
    let mut c = [0.0; W];
    for l in 0..W {
        let q = shifted.0[l].to_bits();
        let swap = 0u64.wrapping_sub(q & 1);
        let (sb, cb) = (sin_r.0[l].to_bits(), cos_r.0[l].to_bits());
        let sl = ((cb & swap) | (sb & !swap)) ^ ((q & 2) << 62);
        let cl = ((sb & swap) | (cb & !swap)) ^ ((q.wrapping_add(1) & 2) << 62);
        s[l] = f64::from_bits(sl);
        c[l] = f64::from_bits(cl);
    }
    (Lanes(s), Lanes(c))
}

/// ln 2 in two parts: the first with its low 32 bits zero (so k · LN2_HI is exact for |k| < 2¹¹),
/// the second the rest.
const LN2_HI: f64 = 6.931_471_803_691_238e-1;
const LN2_LO: f64 = 1.908_214_929_270_587_7e-10;
/// R(z) = Σ Lg_k zᵏ (k = 1..7) ≈ (ln((1 + s)/(1 − s)) − 2s) / s on z = s² ≤ 0.0295: fdlibm's
/// minimax coefficients (`__ieee754_log`).
const LG: [f64; 7] = [
    6.666_666_666_666_735e-1,
    3.999_999_999_940_942e-1,
    2.857_142_874_366_239e-1,
    2.222_219_843_214_978_4e-1,
    1.818_357_216_161_805e-1,
    1.531_383_769_920_937_3e-1,
    1.479_819_860_511_658_6e-1,
];

/// ln x of every lane for positive normal x, without branches or calls (see
/// [`Lanes::ln_vector`]).
#[inline(always)]
fn ln_normal<const W: usize, const F: bool>(x: Lanes<W, F>) -> Lanes<W, F> {
    // x = 2ᵏ m with m ∈ [1, 2) from the bits; m ≥ √2 halved (k + 1) so 1 + f = m ∈ [√2/2, √2).
    const MANT: u64 = (1 << 52) - 1;
    const SQRT2_MANT: u64 = 0x6_a09e_667f_3bcd; // the mantissa bits of √2
    let mut k = [0.0; W];
    let mut m = [0.0; W];
    for l in 0..W {
        let b = x.0[l].to_bits();
        let big = u64::from((b & MANT) >= SQRT2_MANT);
        // The exponent field minus 1023, plus one where m is halved.
        k[l] = ((b >> 52) as i64 - 1023 + big as i64) as f64;
        m[l] = f64::from_bits((b & MANT) | ((1023 - big) << 52));
    }
    let (k, m) = (Lanes::<W, F>(k), Lanes::<W, F>(m));
    let f = m - 1.0;
    let s = f / (f + 2.0);
    let z = s * s;
    let w = z * z;
    // R split into its odd and even powers of z (fdlibm's t1, t2): two shorter chains.
    let t1 = w.madd(
        w.madd(
            w.madd(Lanes::splat(LG[6]), Lanes::splat(LG[4])),
            Lanes::splat(LG[2]),
        ),
        Lanes::splat(LG[0]),
    ) * z;
    let t2 = w.madd(
        w.madd(Lanes::splat(LG[5]), Lanes::splat(LG[3])),
        Lanes::splat(LG[1]),
    ) * w;
    let r = t1 + t2;
    let hfsq = 0.5 * f * f;
    // k ln2_hi + (f − (hfsq − (s (hfsq + R) + k ln2_lo))).
    k * LN2_HI + (f - (hfsq - (s * (hfsq + r) + k * LN2_LO)))
}

/// `Lanes ∘ Lanes`, `Lanes ∘ f64` and `f64 ∘ Lanes` for one binary operator, lane by lane.
macro_rules! binary {
    ($($trait:ident $method:ident $assign:ident $assign_method:ident $op:tt;)*) => {$(
        impl<const W: usize, const F: bool> $trait for Lanes<W, F> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: Self) -> Self {
                let a = self.0;
                Lanes(core::array::from_fn(|l| a[l] $op rhs.0[l]))
            }
        }
        impl<const W: usize, const F: bool> $trait<f64> for Lanes<W, F> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: f64) -> Self {
                self $op Lanes::splat(rhs)
            }
        }
        impl<const W: usize, const F: bool> $trait<Lanes<W, F>> for f64 {
            type Output = Lanes<W, F>;
            #[inline(always)]
            fn $method(self, rhs: Lanes<W, F>) -> Lanes<W, F> {
                Lanes::splat(self) $op rhs
            }
        }
        impl<const W: usize, const F: bool> $assign for Lanes<W, F> {
            #[inline(always)]
            fn $assign_method(&mut self, rhs: Self) {
                *self = *self $op rhs;
            }
        }
        impl<const W: usize, const F: bool> $assign<f64> for Lanes<W, F> {
            #[inline(always)]
            fn $assign_method(&mut self, rhs: f64) {
                *self = *self $op rhs;
            }
        }
    )*};
}

binary! {
    Add add AddAssign add_assign +;
    Sub sub SubAssign sub_assign -;
    Mul mul MulAssign mul_assign *;
    Div div DivAssign div_assign /;
}

impl<const W: usize, const F: bool> Neg for Lanes<W, F> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|x| -x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::real::Real;

    /// Every operation is the f64 operation per lane, bit for bit.
    #[test]
    fn lanes_are_the_scalar_operations() {
        let a = Lanes::<4>([0.3, -1.7, 2.5, 1e-300]);
        let b = Lanes::<4>([1.1, 0.2, -3.0, 7.0]);
        for l in 0..4 {
            let (x, y) = (a.0[l], b.0[l]);
            assert_eq!((a + b).0[l].to_bits(), (x + y).to_bits());
            assert_eq!((a - b).0[l].to_bits(), (x - y).to_bits());
            assert_eq!((a * b).0[l].to_bits(), (x * y).to_bits());
            assert_eq!((a / b).0[l].to_bits(), (x / y).to_bits());
            assert_eq!((2.5 * a).0[l].to_bits(), (2.5 * x).to_bits());
            assert_eq!((a / 3.0).0[l].to_bits(), (x / 3.0).to_bits());
            assert_eq!((1.0 / b).0[l].to_bits(), (1.0 / y).to_bits());
            assert_eq!((-a).0[l].to_bits(), (-x).to_bits());
            assert_eq!(a.exp().0[l].to_bits(), x.exp().to_bits());
            assert_eq!(b.powi(3).0[l].to_bits(), y.powi(3).to_bits());
            assert_eq!(a.atan2(b).0[l].to_bits(), x.atan2(y).to_bits());
            assert_eq!(b.abs().sqrt().0[l].to_bits(), y.abs().sqrt().to_bits());
        }
        let mut c = a;
        c += b;
        c *= b;
        c -= a;
        c /= b;
        assert_eq!(c.0[1], ((-1.7 + 0.2) * 0.2 - -1.7) / 0.2);
        assert!(!Lanes::<2>([1.0, f64::NAN]).all_finite());
        assert!(!Lanes::<2>([1.0, 1.0]).all_gt(Lanes([0.5, 1.0])));
    }

    /// The ulps between two numbers of the same sign (0 for equal ones).
    /// Uniform numbers in [lo, hi) from a xorshift sequence seeded with `seed`.
    fn uniform(mut seed: u64) -> impl FnMut(f64, f64) -> f64 {
        move |lo, hi| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            lo + (hi - lo) * ((seed >> 11) as f64 / (1u64 << 53) as f64)
        }
    }

    fn ulps(a: f64, b: f64) -> u64 {
        if a == b {
            return 0;
        }
        if a.signum() != b.signum() {
            return u64::MAX;
        }
        a.abs().to_bits().abs_diff(b.abs().to_bits())
    }

    /// The vector sin and cos against the f64 methods: at most 1 ulp apart on 10⁶ arguments in
    /// [−50, 50] and 10⁵ in [−10⁵, 10⁵], where the result is not tiny (near a zero, within
    /// 2⁻⁵³ absolute: the reduced argument's own rounding); equal beyond 10⁵ and for the
    /// non-finite.
    #[test]
    fn vector_sin_cos_is_within_one_ulp_of_the_f64_methods() {
        within_one_ulp::<false>();
        // With the polynomials' multiply-adds fused (the engines' FMA paths) too.
        within_one_ulp::<true>();
        let big = Lanes::<4>([1e6, -3e7, f64::INFINITY, f64::NAN]);
        let (s, c) = big.sin_cos();
        assert_eq!((s.0[0], c.0[1]), (1e6_f64.sin(), (-3e7_f64).cos()));
        assert!(s.0[2].is_nan() && c.0[3].is_nan());
        let (s, c) = Lanes::<4>([0.0, -0.0, 1e-300, 3.0]).sin_cos();
        assert_eq!((s.0[0], c.0[0], s.0[2]), (0.0, 1.0, 1e-300));
        assert_eq!(c.0[1], 1.0);
        assert!((s.0[3] - 3.0_f64.sin()).abs() <= f64::EPSILON);
    }

    fn within_one_ulp<const F: bool>() {
        let mut next = uniform(0x2545_f491_4f6c_dd1d);
        let mut worst = 0;
        for (count, bound) in [(1_000_000, 50.0), (100_000, 1e5), (100_000, 1e-3)] {
            for _ in 0..count / 4 {
                let x = Lanes::<4, F>::from_fn(|_| next(-bound, bound));
                let (s, c) = x.sin_cos();
                for l in 0..4 {
                    let (ws, wc) = x.0[l].sin_cos();
                    for (got, want) in [(s.0[l], ws), (c.0[l], wc)] {
                        if want.abs() < 1e-3 {
                            assert!((got - want).abs() <= 1.2e-16, "{} {got} {want}", x.0[l]);
                        } else {
                            let u = ulps(got, want);
                            assert!(u <= 1, "x = {}: {got} vs {want}", x.0[l]);
                            worst = worst.max(u);
                        }
                    }
                }
            }
        }
        assert_eq!(worst, 1, "some argument rounds differently");
    }

    /// The vector ln against `f64::ln`: at most 1 ulp apart on 10⁶ arguments spread over
    /// 2⁻¹⁰⁰⁰ … 2¹⁰⁰⁰ and 10⁶ in [0.5, 2] (around ln's zero), with and without fused
    /// multiply-adds; the lanes that are not positive normal numbers equal `f64::ln`.
    #[test]
    fn vector_ln_is_within_one_ulp_of_f64_ln() {
        ln_within_one_ulp::<false>();
        ln_within_one_ulp::<true>();
        let odd = Lanes::<4>([0.0, -1.0, f64::INFINITY, 4.9e-320]).ln_vector();
        assert_eq!(odd.0[0], f64::NEG_INFINITY);
        assert!(odd.0[1].is_nan());
        assert_eq!(odd.0[2], f64::INFINITY);
        assert_eq!(odd.0[3], 4.9e-320_f64.ln());
        assert!(Lanes::<2>([f64::NAN, 1.0]).ln_vector().0[0].is_nan());
        assert_eq!(Lanes::<2>([1.0, 2.0]).ln_vector().0, [0.0, 2.0_f64.ln()]);
    }

    fn ln_within_one_ulp<const F: bool>() {
        let mut next = uniform(0x9e37_79b9_7f4a_7c15);
        for wide in [true, false] {
            for _ in 0..250_000 {
                let x = Lanes::<4, F>::from_fn(|_| {
                    if wide {
                        next(1.0, 2.0) * next(-1000.0, 1000.0).round().exp2()
                    } else {
                        next(0.5, 2.0)
                    }
                });
                let y = x.ln_vector();
                for l in 0..4 {
                    let want = x.0[l].ln();
                    let u = ulps(y.0[l], want);
                    assert!(u <= 1, "x = {}: {} vs {want}", x.0[l], y.0[l]);
                }
            }
        }
    }
}
