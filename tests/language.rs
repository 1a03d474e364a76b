//! What a physicist writes, in the default (symbolic) mode: parameter-only code evaluated as
//! written (`Self::K`, `as` casts, `match` on a parameter, indexing an array field, a function of
//! parameters), `std`/`core` constants and `f64::EPSILON`, the piecewise functions `max`, `min`,
//! `clamp`, `abs`, `signum` (with the jets' one-sided rule at a tie, also at −0), `cbrt`,
//! `ln_1p`, `exp_m1`, `log10`, `log2`, `asinh`, `acosh`, `atanh`, `exp2`, `hypot`, `atan2`, `v.norm().powi(2)` at rest, and `powi` with a constant exponent. Each
//! system is declared in both modes from one body and compared at random states to 1e-12.

use lagrange::prelude::*;
use lagrange_examples::twins;

use crate::support::Rng;

/// Mode of a spring, matched on in the body.
#[derive(Debug, Clone, Copy)]
pub enum Stiffness {
    Soft,
    Hard,
}

fn doubled(a: f64) -> f64 {
    2.0 * a
}

twins! {
    /// Parameter-only code of every kind.
    Params, ParamsJets { m: f64, n: usize, k: [f64; 3], g: Vector3<f64>, kind: Stiffness }
    const K: f64 = 1.5;
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        let stiff = match self.kind {
            Stiffness::Soft => 1.0,
            Stiffness::Hard => 10.0,
        };
        let a = f64::EPSILON * x + std::f64::consts::PI * y + core::f64::consts::E * x * y;
        let b = Self::K * x * x + (self.n as f64) * y * y + self.k[1] * x + self.g[2] * y;
        0.5 * doubled(self.m) * (x_dot * x_dot + y_dot * y_dot) * (1.0 + 0.1 * x * x)
            - stiff * a
            - b
    }
}

twins! {
    /// max, min, clamp, abs and signum in the kinetic and the potential energy.
    Piecewise, PiecewiseJets { m: f64 }
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        let w = 1.0 + 0.5 * x.max(y) * x.max(y) + 0.25 * y.abs();
        let v = x.min(0.5) * y + y.clamp(-0.3, 0.4) * x + x.signum() * y * y + (x - y).abs();
        0.5 * self.m * w * (x_dot * x_dot + y_dot * y_dot) - v
    }
}

twins! {
    /// The other functions of the jets.
    Functions, FunctionsJets { m: f64 }
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        let w = 2.0 + x.hypot(y) + 0.1 * y.atan2(x);
        let v = x.cbrt() + x.ln_1p() * y + y.exp_m1() + x.log10() * y.log2()
            + (0.3 * x).asinh() * (1.0 + y).acosh() + (0.2 * y).atanh() + x.exp2();
        0.5 * self.m * w * (x_dot * x_dot + y_dot * y_dot) - v
    }
}

twins! {
    /// |ṙ|² written as `r_dot.norm().powi(2)`.
    NormSquared, NormSquaredJets { m: f64, g: f64 }
    fn lagrangian(&self, (r, r_dot): Coord3) -> Scalar {
        0.5 * self.m * r_dot.norm().powi(2) * (1.0 + 0.1 * r.norm().powi(2)) - self.m * self.g * r.z
    }
}

/// The exponent of a module-level constant.
const N3: i32 = 3;

twins! {
    /// `powi` with constant exponents: a module `const`, an associated `const`, a cast parameter.
    ConstPowers, ConstPowersJets { k: f64, n: u8 }
    const M: i32 = -2;
    fn lagrangian(&self, (x, x_dot): Coord, (y, y_dot): Coord) -> Scalar {
        0.5 * (x_dot.powi(2) + y_dot.powi(2)) * (2.0 + x.powi(N3).sin())
            - self.k * y.powi(Self::M)
            - x.powi(self.n as i32)
            - (x * y).powi(N3)
    }
}

/// max over |a|, for the comparisons.
fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    let scale = b.iter().fold(1.0_f64, |s, x| s.max(x.abs()));
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol * scale)
}

fn compare<const N: usize>(
    sym: &impl Lagrangian<N>,
    jets: &impl Lagrangian<N>,
    q: [f64; N],
    v: [f64; N],
) {
    let a = sym.accelerations(&q, &v, 0.0).expect("symbolic");
    let b = jets.accelerations(&q, &v, 0.0).expect("jets");
    assert!(close(&a, &b, 1e-12), "q = {q:?}, v = {v:?}: {a:?} vs {b:?}");
}

#[test]
fn parameter_only_code_and_constants_agree_with_the_jets() {
    let mut rng = Rng(11);
    for kind in [Stiffness::Soft, Stiffness::Hard] {
        let p = Params {
            m: 1.3,
            n: 3,
            k: [0.5, -0.7, 2.0],
            g: Vector3::new(0.1, 0.2, -9.81),
            kind,
        };
        for _ in 0..20 {
            let q = [rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0)];
            let v = [rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0)];
            compare(&p, &p.jets(), q, v);
        }
    }
    // The printed equations name the parameter-only code as written.
    assert!(
        Params::EQUATIONS.contains("(n as f64)"),
        "{}",
        Params::EQUATIONS
    );
}

/// `x.powi(N)` with a constant N (module, associated, a parameter cast) agrees with the jets,
/// also for negative x (an integer power, not a real one), and prints as written.
#[test]
fn constant_powi_exponents_agree_with_the_jets() {
    let mut rng = Rng(17);
    for n in [0, 1, 2, 5] {
        let p = ConstPowers { k: 0.7, n };
        for _ in 0..20 {
            let q = [
                rng.uniform(-2.0, 2.0),
                rng.uniform(0.5, 2.0)
                    * if rng.uniform(0.0, 1.0) < 0.5 {
                        -1.0
                    } else {
                        1.0
                    },
            ];
            let v = [rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0)];
            compare(&p, &p.jets(), q, v);
        }
        compare(&p, &p.jets(), [-1.5, -0.8], [0.3, 0.2]);
    }
    let eq = ConstPowers::EQUATIONS;
    assert!(eq.contains("N3") && eq.contains("Self::M"), "{eq}");
}

#[test]
fn piecewise_functions_agree_with_the_jets_also_at_ties_and_signed_zeros() {
    let (p, j) = (Piecewise { m: 0.8 }, Piecewise { m: 0.8 }.jets());
    let mut rng = Rng(12);
    for _ in 0..40 {
        let q = [rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)];
        let v = [rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0)];
        compare(&p, &j, q, v);
    }
    // Ties of max/min/clamp, the kinks of abs and the sign of zero: the one-sided rule of the
    // jets (the receiver wins a tie; |x| has slope +1 at ±0).
    for q in [
        [0.0, 0.0],
        [-0.0, 0.0],
        [0.0, -0.0],
        [0.3, 0.3],
        [0.5, -0.3],
        [0.5, 0.4],
        [-0.2, -0.0],
    ] {
        compare(&p, &j, q, [0.7, -0.4]);
    }
}

#[test]
fn the_other_functions_agree_with_the_jets() {
    let (p, j) = (Functions { m: 1.1 }, Functions { m: 1.1 }.jets());
    let mut rng = Rng(13);
    for _ in 0..40 {
        let q = [rng.uniform(0.2, 2.0), rng.uniform(0.2, 2.0)];
        let v = [rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0)];
        compare(&p, &j, q, v);
    }
}

#[test]
fn a_norm_squared_written_as_norm_powi_2_is_finite_at_rest() {
    let (p, j) = (
        NormSquared { m: 2.0, g: 9.81 },
        NormSquared { m: 2.0, g: 9.81 }.jets(),
    );
    for (q, v) in [
        ([0.0; 3], [0.0; 3]),
        ([1.0, -0.5, 0.2], [0.0; 3]),
        ([0.3, 0.1, -0.2], [0.5, -1.0, 0.25]),
    ] {
        let a = p.accelerations(&q, &v, 0.0).expect("finite at rest");
        assert!(a.iter().all(|x| x.is_finite()), "{a:?}");
        compare(&p, &j, q, v);
    }
    // At r = 0, ṙ = 0: M = m I, so q̈ = (0, 0, −g).
    let a = p.accelerations(&[0.0; 3], &[0.0; 3], 0.0).unwrap();
    assert_eq!(a, [0.0, 0.0, -9.81]);
}

twins! {
    /// The receiver written out, `self: &Self`.
    ExplicitSelf, ExplicitSelfJets { k: f64 }
    fn lagrangian(self: &Self, (x, x_dot): Coord) -> Scalar {
        0.5 * x_dot * x_dot - 0.5 * self.k * x * x
    }
}

#[test]
fn self_written_as_self_ref_self_is_accepted() {
    let p = ExplicitSelf { k: 4.0 };
    assert_eq!(p.accelerations(&[0.5], &[0.0], 0.0).unwrap(), [-2.0]);
    assert_eq!(p.jets().accelerations(&[0.5], &[0.0], 0.0).unwrap(), [-2.0]);
}

/// Two links named `th1`, `th2`: multi-letter names print their derivatives as d(·)/dt.
pub struct TwoLinks;

#[lagrangian]
impl TwoLinks {
    fn lagrangian(&self, (th1, th1_dot): Coord, (th2, th2_dot): Coord) -> Scalar {
        th1_dot * th1_dot
            + 0.5 * th2_dot * th2_dot
            + th1_dot * th2_dot * (th1 - th2).cos()
            + 2.0 * th1.cos()
            + th2.cos()
    }
}

#[test]
fn a_squared_velocity_of_a_long_name_does_not_read_as_a_second_derivative() {
    let eq = TwoLinks::EQUATIONS;
    assert!(eq.contains("(d(th₂)/dt)²"), "{eq}");
    assert!(!eq.contains("d(th₂)/dt²"), "{eq}");
    assert!(eq.contains("d²(th₁)/dt²"), "{eq}");
}

// ---- Coordinate arrays, loops, helpers, closures and nested functions ----

twins! {
    /// The 8-link chain of `support::systems::chain!`, written with `Coords<8>` and a loop.
    ChainArray8, ChainArray8Jets { m: f64, l: f64, g: f64 }
    fn lagrangian(&self, (q, q_dot): Coords<8>) -> Scalar {
        let (s, c) = q[0].sin_cos();
        let mut vx = self.l * c * q_dot[0];
        let mut vy = self.l * s * q_dot[0];
        let mut y = -self.l * c;
        let mut lag = 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        for k in 1..q.len() {
            let (s, c) = q[k].sin_cos();
            vx += self.l * c * q_dot[k];
            vy += self.l * s * q_dot[k];
            y -= self.l * c;
            lag += 0.5 * self.m * (vx * vx + vy * vy) - self.m * self.g * y;
        }
        lag
    }
}

/// A chain written with `Coords<8>` and a loop gives the same q̈ as the same chain written with
/// eight `Coord`s (the same operations in the same order: bit-equal), in both modes.
#[test]
fn a_chain_written_with_coords_and_a_loop_equals_the_chain_written_out() {
    use crate::support::systems::Chain8;
    let mut rng = Rng(23);
    let (m, l, g) = (0.7, 1.3, 9.81);
    let arr = ChainArray8 { m, l, g };
    let out = Chain8 { m, l, g };
    for _ in 0..20 {
        let q: [f64; 8] = std::array::from_fn(|_| rng.uniform(-2.0, 2.0));
        let v: [f64; 8] = std::array::from_fn(|_| rng.uniform(-2.0, 2.0));
        let a = arr.accelerations(&q, &v, 0.0).expect("array chain");
        let b = out.accelerations(&q, &v, 0.0).expect("chain written out");
        assert!(close(&a, &b, 1e-14), "{a:?} vs {b:?}");
        let aj = arr
            .jets()
            .accelerations(&q, &v, 0.0)
            .expect("array chain, jets");
        let bj = out
            .jets()
            .accelerations(&q, &v, 0.0)
            .expect("chain written out, jets");
        assert_eq!(aj, bj, "jets: the same operations in the same order");
        compare(&arr, &arr.jets(), q, v);
    }
    assert_eq!(ChainArray8::COORDINATES[0], "q[0]");
    assert_eq!(ChainArray8::COORDINATES[7], "q[7]");
    assert!(
        ChainArray8::EQUATIONS.contains("q̈[7]"),
        "{}",
        ChainArray8::EQUATIONS
    );
    assert!(
        ChainArray8::EQUATIONS_LATEX.contains("q_{7}"),
        "{}",
        ChainArray8::EQUATIONS_LATEX
    );
}

twins! {
    /// Beads on a line with springs between neighbours and a pendulum-like potential: every
    /// construct of the language at once (helper methods, `Self::helper`, closures, a nested
    /// `fn`, a `const` in the body, `iter`/`zip` with an array field/`map`/`sum`/`fold`/
    /// `enumerate`/`rev`, a local array written element by element, an `if` on a loop
    /// variable, `as f64` of a loop variable, associated consts as loop bounds).
    Beads, BeadsJets { m: [f64; 3], k: f64, g: f64 }
    const N: usize = 3;
    fn spring(&self, a: Scalar, b: Scalar) -> Scalar {
        let d = a - b;
        0.5 * self.k * d * d
    }
    fn kinetic(&self, m: f64, v: Scalar) -> Scalar {
        0.5 * m * v * v
    }
    fn lagrangian(&self, (q, q_dot): Coords<3>, (x, x_dot): Coord) -> Scalar {
        const HALF: f64 = 0.5;
        fn sq(v: Scalar) -> Scalar {
            v * v
        }
        let ke = |m: f64, v: Scalar| HALF * m * sq(v);
        let mut t = q_dot
            .iter()
            .zip(self.m.iter())
            .map(|(v, m)| ke(*m, *v))
            .sum::<Scalar>();
        t += self.kinetic(1.0, x_dot);
        let mut springs = [0.0; 3];
        for (i, qi) in q.iter().enumerate() {
            if i > 0 {
                springs[i] = self.spring(*qi, q[i - 1]);
            } else {
                springs[i] = Self::spring(self, *qi, x);
            }
        }
        let v = springs.iter().fold(0.0 * x, |acc, s| acc + *s);
        let mut w = 0.0;
        for i in (0..Self::N).rev() {
            w += (i as f64 + 1.0) * self.g * q[i].cos() * self.m[i];
        }
        let tilt: Scalar = q.iter().skip(1).step_by(1).take(2).map(|a| a.sin()).product();
        t - v - w - x.powi(2) - tilt
    }
    fn dissipation(&self, (_, q_dot): Coords<3>, (_, x_dot): Coord) -> Scalar {
        let mut d = 0.05 * x_dot * x_dot;
        for v in q_dot {
            d += 0.1 * v * v;
        }
        d
    }
    fn forces(&self, (q, _): Coords<3>, _: Coord, t: Time) -> [Scalar; 4] {
        let drive = (2.0 * t).cos();
        [drive * q[0].cos(), 0.0 * q[1], -drive, 0.3 * drive]
    }
}

/// Every construct of the language, both modes, at random states (1e-12); the helper methods
/// stay ordinary methods, callable with `f64`; the equations name the array slots `q[i]` and
/// the array field's elements `m[i]`.
#[test]
fn arrays_loops_helpers_closures_and_nested_functions_agree_with_the_jets() {
    let mut rng = Rng(29);
    let p = Beads {
        m: [1.0, 2.0, 0.5],
        k: 3.0,
        g: 9.81,
    };
    for _ in 0..30 {
        let q: [f64; 4] = std::array::from_fn(|_| rng.uniform(-2.0, 2.0));
        let v: [f64; 4] = std::array::from_fn(|_| rng.uniform(-2.0, 2.0));
        let t = rng.uniform(0.0, 10.0);
        let a = p.accelerations(&q, &v, t).expect("symbolic");
        let b = p.jets().accelerations(&q, &v, t).expect("jets");
        assert!(close(&a, &b, 1e-12), "q = {q:?}, v = {v:?}: {a:?} vs {b:?}");
    }
    assert_eq!(p.kinetic(2.0, 3.0_f64), 9.0);
    assert_eq!(p.jets().spring(1.0_f64, 0.5), 0.375);
    assert_eq!(Beads::COORDINATES, ["q[0]", "q[1]", "q[2]", "x"]);
    // x: ẍ = k q[0] − (2 + k) x − drive·0.3 … the spring to q[0] and the x² term.
    let eqs = Beads::EQUATIONS;
    assert!(eqs.contains("m[0] q̈[0]"), "{eqs}");
    assert!(eqs.contains("k q[0]"), "{eqs}");
}

twins! {
    /// `Coord`, `Coord3` and `Coords<K>` mixed in one signature.
    Mixed, MixedJets { m: f64 }
    fn lagrangian(&self, (a, a_dot): Coord, (r, r_dot): Coord3, (q, q_dot): Coords<2>) -> Scalar {
        let mut t = 0.5 * self.m * (a_dot * a_dot + r_dot.norm_squared());
        for (qi, vi) in q.iter().zip(q_dot.iter()) {
            t += 0.5 * vi * vi - qi.cos() * a.sin();
        }
        t - r.norm_squared() * (1.0 + q[1] * q[1])
    }
}

#[test]
fn coord_coord3_and_coords_mix_in_one_signature() {
    let mut rng = Rng(31);
    let p = Mixed { m: 1.5 };
    for _ in 0..20 {
        let q: [f64; 6] = std::array::from_fn(|_| rng.uniform(-2.0, 2.0));
        let v: [f64; 6] = std::array::from_fn(|_| rng.uniform(-2.0, 2.0));
        compare(&p, &p.jets(), q, v);
    }
    assert_eq!(
        Mixed::COORDINATES,
        ["a", "r.x", "r.y", "r.z", "q[0]", "q[1]"]
    );
}

twins! {
    /// 40 beads joined by springs, fixed ends: above 32 coordinates the accelerations take the
    /// runtime's loop-based LDLᵀ and `mass_matrix`, `momenta` and `energy` come from
    /// `pieces` and `energy_and_momenta`.
    Beads40, Beads40Jets { m: f64, k: f64 }
    fn lagrangian(&self, (x, x_dot): Coords<40>) -> Scalar {
        let mut l = 0.5 * self.k * (x[0] * x[0] + x[39] * x[39]);
        for i in 0..39 {
            l += 0.5 * self.k * (x[i + 1] - x[i]).powi(2);
        }
        let mut t = 0.0;
        for v in x_dot {
            t += 0.5 * self.m * v * v;
        }
        t - l
    }
}

/// The large-system path against the closed form m ẍᵢ = k (xᵢ₊₁ − 2xᵢ + xᵢ₋₁) and against the
/// jets (M, momenta, energy).
#[test]
fn above_32_coordinates_the_loop_solve_gives_the_closed_form() {
    let mut rng = Rng(37);
    let p = Beads40 { m: 0.5, k: 3.0 };
    let q: [f64; 40] = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
    let v: [f64; 40] = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
    let a = p.accelerations(&q, &v, 0.0).expect("symbolic");
    for i in 0..40 {
        let left = if i > 0 { q[i - 1] } else { 0.0 };
        let right = if i < 39 { q[i + 1] } else { 0.0 };
        let want = p.k * (right - 2.0 * q[i] + left) / p.m;
        assert!(
            (a[i] - want).abs() <= 1e-13 * want.abs().max(1.0),
            "{i}: {} vs {want}",
            a[i]
        );
    }
    let (mass, energy, momenta) = (
        p.mass_matrix(&q, &v, 0.0),
        p.energy(&q, &v, 0.0),
        p.momenta(&q, &v, 0.0),
    );
    // The jets of 40 coordinates carry 40×40 second derivatives per number: their evaluation
    // wants more than a test thread's 2 MiB of stack.
    let j = p.jets();
    std::thread::Builder::new()
        .stack_size(256 << 20)
        .spawn(move || {
            compare(&p, &j, q, v);
            assert_eq!(mass, j.mass_matrix(&q, &v, 0.0));
            let m = j.energy(&q, &v, 0.0);
            assert!((energy - m).abs() <= 1e-13 * m.abs(), "{energy} vs {m}");
            assert!(close(&momenta, &j.momenta(&q, &v, 0.0), 1e-14));
        })
        .expect("a thread")
        .join()
        .expect("the jets agree");
}

twins! {
    /// 33 beads and a particle in space (36 coordinates: the code of M, of the right-hand side
    /// and of the energy goes into modules next to the impl) with every kind of input those
    /// modules take: `f64` and `Vector3` fields, an array field, parameter-only code, a
    /// constant `match`, and a dissipation (applied forces).
    Large36, Large36Jets { m: f64, k: [f64; 2], n: usize, g: Vector3<f64>, kind: Stiffness, c: f64 }
    fn lagrangian(&self, (x, x_dot): Coords<33>, (r, r_dot): Coord3) -> Scalar {
        let stiff = match self.kind {
            Stiffness::Soft => self.k[0],
            Stiffness::Hard => self.k[1],
        };
        let mut l = 0.5 * self.m * r_dot.norm_squared() + self.m * self.g.dot(&r);
        for i in 0..33 {
            l += 0.5 * self.m * x_dot[i] * x_dot[i] * (1.0 + 0.1 * x[i].cos());
        }
        for i in 0..32 {
            l -= 0.5 * stiff * (self.n as f64) * (x[i + 1] - x[i]).powi(2) * (1.0 + r.z * r.z);
        }
        l
    }
    fn dissipation(&self, (_, x_dot): Coords<33>, (_, r_dot): Coord3) -> Scalar {
        let mut d = 0.5 * self.c * r_dot.norm_squared();
        for v in x_dot {
            d += 0.1 * self.c * v * v;
        }
        d
    }
}

/// The out-of-line modules of a large system get every input right: both modes agree, with the
/// constant `match` taking either arm.
#[test]
fn large_system_modules_take_every_kind_of_input() {
    let mut rng = Rng(43);
    for kind in [Stiffness::Soft, Stiffness::Hard] {
        let p = Large36 {
            m: 0.7,
            k: [1.5, 4.0],
            n: 3,
            g: Vector3::new(0.1, -0.2, -9.81),
            kind,
            c: 0.3,
        };
        let q: [f64; 36] = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
        let v: [f64; 36] = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
        let (e, m) = (p.energy(&q, &v, 0.0), p.momenta(&q, &v, 0.0));
        let pieces = p.pieces(&q, &v, 0.0);
        let j = p.jets();
        std::thread::Builder::new()
            .stack_size(256 << 20)
            .spawn(move || {
                compare(&p, &j, q, v);
                let je = j.energy(&q, &v, 0.0);
                assert!((e - je).abs() <= 1e-13 * je.abs().max(1.0), "{e} vs {je}");
                assert!(close(&m, &j.momenta(&q, &v, 0.0), 1e-13));
                let jp = j.pieces(&q, &v, 0.0);
                assert!(close(&pieces.applied, &jp.applied, 1e-13));
                assert!(close(&pieces.lagrangian_force, &jp.lagrangian_force, 1e-12));
            })
            .expect("a thread")
            .join()
            .expect("the jets agree");
    }
}

twins! {
    /// Four particles on a line, every pair joined by a spring: nested loops, the inner bound a
    /// loop variable.
    AllPairs, AllPairsJets { m: f64, k: f64 }
    fn lagrangian(&self, (x, x_dot): Coords<4>) -> Scalar {
        let mut v = 0.0;
        for i in 0..4 {
            for j in 0..i {
                v += 0.5 * self.k * (x[i] - x[j]).powi(2);
            }
        }
        let t: Scalar = x_dot.iter().map(|u| 0.5 * self.m * u * u).sum();
        t - v
    }
}

/// m ẍᵢ = −k Σⱼ (xᵢ − xⱼ) = −k (4 xᵢ − Σⱼ xⱼ), in both modes.
#[test]
fn nested_loops_with_a_loop_variable_bound() {
    let mut rng = Rng(41);
    let p = AllPairs { m: 2.0, k: 0.5 };
    for _ in 0..10 {
        let q: [f64; 4] = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
        let v: [f64; 4] = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
        let a = p.accelerations(&q, &v, 0.0).expect("symbolic");
        let sum: f64 = q.iter().sum();
        for i in 0..4 {
            let want = -p.k * (4.0 * q[i] - sum) / p.m;
            assert!((a[i] - want).abs() <= 1e-14, "{i}: {} vs {want}", a[i]);
        }
        compare(&p, &p.jets(), q, v);
    }
}

twins! {
    /// `*` on references and on iterator elements, as Rust code on `f64` would write it.
    Derefs, DerefsJets { m: [f64; 2] }
    fn lagrangian(&self, (x, x_dot): Coords<2>) -> Scalar {
        let first = &x[0];
        let mut t = 0.0;
        for (v, m) in x_dot.iter().zip(self.m.iter()) {
            t += 0.5 * *m * *v * *v;
        }
        let sq = |u: &Scalar| *u * *u;
        t - sq(first) - (*first) * x[1]
    }
}

#[test]
fn derefs_of_references_and_elements_agree_with_the_jets() {
    let p = Derefs { m: [1.5, 0.5] };
    let mut rng = Rng(43);
    for _ in 0..10 {
        let q = [rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)];
        let v = [rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)];
        compare(&p, &p.jets(), q, v);
        // V = x0² + x0 x1: m0 ẍ0 = −(2 x0 + x1), m1 ẍ1 = −x0.
        let a = p.accelerations(&q, &v, 0.0).expect("symbolic");
        assert!((a[0] + (2.0 * q[0] + q[1]) / 1.5).abs() < 1e-14);
        assert!((a[1] + q[0] / 0.5).abs() < 1e-14);
    }
}

/// `zip` with an `f64` array field of each length against `Coords<3>`: one body per length.
macro_rules! zip_twins {
    ($($sym:ident, $jet:ident, $n:literal;)*) => {$(
        twins! {
            /// `zip` with an array field that may be shorter than the coordinates, through every
            /// consumer: `map` + `sum`, `fold`, `product`, a `for` loop with `enumerate`, the
            /// field on the left, `.rev()` (order-dependent), a zip of a zip, `skip`.
            $sym, $jet { k: [f64; $n] }
            fn lagrangian(&self, (q, q_dot): Coords<3>) -> Scalar {
                let t: Scalar = q_dot.iter().map(|v| 0.5 * v * v).sum();
                let extra = q_dot
                    .iter()
                    .zip(self.k.iter())
                    .fold(0.0 * q[0], |acc, (v, k)| acc + 0.25 * *k * *v * *v);
                let v1: Scalar = q.iter().zip(self.k.iter()).map(|(x, k)| *k * *x * *x).sum();
                let mut v2 = 0.0 * q[0];
                for (i, (k, x)) in self.k.iter().zip(q.iter()).enumerate() {
                    v2 += (i as f64 + 1.0) * *k * x.cos();
                }
                let mut v3 = 0.0 * q[0];
                for (x, k) in q.iter().zip(self.k.iter()).rev() {
                    v3 = v3 * 0.5 + *k * x.sin();
                }
                let p: Scalar = q
                    .iter()
                    .zip(self.k.iter())
                    .map(|(x, k)| 1.0 + 0.1 * *k * *x)
                    .product();
                let mut v4 = 0.0 * q[0];
                for ((x, k), v) in q.iter().skip(1).zip(self.k.iter()).zip(q_dot.iter()) {
                    v4 += *k * *x * *v;
                }
                t + extra - v1 - v2 - v3 - p - v4
            }
        }
    )*};
}

zip_twins! {
    ZipShort, ZipShortJets, 2;
    ZipEqual, ZipEqualJets, 3;
    ZipLong, ZipLongJets, 4;
}

#[test]
fn zip_with_an_array_field_stops_at_the_shorter_side_like_the_jets() {
    // Symbolic mode used to unroll to the coordinates' length and index `self.k[2]` of a
    // 2-element field: an out-of-bounds panic at run time.
    let mut rng = Rng(47);
    let short = ZipShort { k: [0.7, -1.3] };
    let equal = ZipEqual {
        k: [0.7, -1.3, 0.4],
    };
    let long = ZipLong {
        k: [0.7, -1.3, 0.4, 2.5],
    };
    for _ in 0..10 {
        let q: [f64; 3] = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
        let v: [f64; 3] = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
        compare(&short, &short.jets(), q, v);
        compare(&equal, &equal.jets(), q, v);
        compare(&long, &long.jets(), q, v);
        // The 2-element field reaches q[2] only through `q.iter().skip(1).zip(self.k)`: L's
        // q[2] part is ½ q̇2² − k1 q2 q̇1, so q̈2 = −k1 q̇1.
        let a = short.accelerations(&q, &v, 0.0).expect("symbolic");
        assert!((a[2] + short.k[1] * v[1]).abs() < 1e-14, "{a:?}");
    }
    // The printed equations read the elements as written.
    assert!(
        ZipShort::EQUATIONS.contains("k[1]"),
        "{}",
        ZipShort::EQUATIONS
    );
    assert!(
        !ZipShort::EQUATIONS.contains("len"),
        "{}",
        ZipShort::EQUATIONS
    );
}

/// The jets-only iterator words on values of the motion: `.filter()`, `.any()`, `.all()` and
/// `.for_each()` take their closures as written (they were lifted into scalars, a type error in
/// the generated code, until the front end's vocabulary named them).
pub struct OneSided {
    pub k: f64,
}

#[lagrangian(mode = "jets")]
impl OneSided {
    fn lagrangian(&self, (q, q_dot): Coords<3>) -> Scalar {
        let mut kinetic = 0.0;
        q_dot.iter().for_each(|v| kinetic += 0.5 * v * v);
        // A spring that pulls only the coordinates above zero.
        let stretched: Scalar = q.iter().filter(|x| **x > 0.0).map(|x| x * x).sum();
        let far = q.iter().any(|x| x.abs() > 10.0) || q.iter().all(|x| *x < -10.0);
        let k = if far { 0.0 } else { self.k };
        kinetic - 0.5 * k * stretched
    }
}

#[test]
fn jets_only_iterator_words_run_as_written() {
    let s = OneSided { k: 2.5 };
    let a = s
        .accelerations(&[0.3, -0.4, 0.0], &[0.1, 0.2, 0.3], 0.0)
        .expect("jets");
    // q̈ = −k q where q > 0, 0 elsewhere.
    assert!((a[0] + 2.5 * 0.3).abs() < 1e-14, "{a:?}");
    assert_eq!(a[1], 0.0);
    assert_eq!(a[2], 0.0);
    let far = s
        .accelerations(&[11.0, 0.5, 0.0], &[0.0; 3], 0.0)
        .expect("jets");
    assert_eq!(far, [0.0; 3]);
}
