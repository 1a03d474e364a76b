//! Problems of the Bari test set for IVP solvers (F. Mazzia and C. Magherini, *Test Set for
//! Initial Value Problem Solvers*, release 2.4, University of Bari, 2008), written as a user
//! writes them — a Lagrangian, its constraints and forces, no index hints, no choice of state —
//! with the test set's reference solutions (published figures, quoted with their source) and its
//! measure of accuracy, the significant correct digits.

use lagrange::prelude::*;

/// The car axis (test set problem "caraxis", after Schneider and Hairer & Wanner, *Solving ODEs
/// II*, VII.1): two wheels of mass k = Mε²/2 at (x_l, y_l) and (x_r, y_r), each on a spring of
/// stiffness 1 and rest length L₀ — the left one from the origin, the right one from the point
/// (x_b, y_b) = (√(L² − y_b²), r sin ωt) that a bump in the road moves up and down — the axle a
/// rod of length L between them, the left wheel held on the line through the origin
/// perpendicular to (x_b, y_b): x_b x_l + y_b y_l = 0 (a moving constraint), gravity g. Stiff
/// (the wheels' springs at ω = 1/√k ≈ 45 rad/s against the slow motion), index 3 as a DAE.
///
/// The test set writes k q̈ = f(q, t) + Gᵀλ with these f, g: its λ₁, λ₂ are ours (the same sign).
#[derive(Clone, Copy, Debug)]
pub struct CarAxis {
    /// ε.
    pub eps: f64,
    /// M (the wheels' mass is Mε²/2).
    pub m: f64,
    /// The axle's length L.
    pub l: f64,
    /// The springs' rest length L₀.
    pub l0: f64,
    /// The bump's amplitude r.
    pub r: f64,
    /// The bump's angular frequency ω.
    pub w: f64,
    /// Gravity g.
    pub g: f64,
}

#[lagrangian]
impl CarAxis {
    fn lagrangian(
        &self,
        (xl, xl_dot): Coord,
        (yl, yl_dot): Coord,
        (xr, xr_dot): Coord,
        (yr, yr_dot): Coord,
        t: Time,
    ) -> Scalar {
        let k = 0.5 * self.m * self.eps * self.eps;
        let yb = self.r * (self.w * t).sin();
        let xb = (self.l * self.l - yb * yb).sqrt();
        let left = (xl * xl + yl * yl).sqrt() - self.l0;
        let right = ((xr - xb).powi(2) + (yr - yb).powi(2)).sqrt() - self.l0;
        0.5 * k * (xl_dot.powi(2) + yl_dot.powi(2) + xr_dot.powi(2) + yr_dot.powi(2))
            - 0.5 * (left * left + right * right)
            - k * self.g * (yl + yr)
    }
    fn constraints(
        &self,
        (xl, _): Coord,
        (yl, _): Coord,
        (xr, _): Coord,
        (yr, _): Coord,
        t: Time,
    ) -> [Scalar; 2] {
        let yb = self.r * (self.w * t).sin();
        let xb = (self.l * self.l - yb * yb).sqrt();
        [
            xb * xl + yb * yl,
            (xl - xr).powi(2) + (yl - yr).powi(2) - self.l * self.l,
        ]
    }
}

impl CarAxis {
    /// The test set's parameters: ε = 10⁻², M = 10, L = 1, L₀ = ½, r = 0.1, ω = 10, g = 1.
    pub const TESTSET: CarAxis = CarAxis {
        eps: 1e-2,
        m: 10.0,
        l: 1.0,
        l0: 0.5,
        r: 0.1,
        w: 10.0,
        g: 1.0,
    };

    /// The end of the test set's interval, t = 3.
    pub const END: f64 = 3.0;

    /// The test set's initial state: (x_l, y_l, x_r, y_r) = (0, L₀, L, L₀), both wheels moving at
    /// −L₀/L along x.
    pub fn start(&self) -> ([f64; 4], [f64; 4]) {
        let v = -self.l0 / self.l;
        ([0.0, self.l0, self.l, self.l0], [v, 0.0, v, 0.0])
    }

    /// The reference solution at t = 3 that the test set's later releases and R's `deTestSet`
    /// give (GAMD in quadruple precision): positions, velocities, then λ₁, λ₂. (The
    /// double-precision one of the test set's `carsoln`, 0.4934557842755629e-1, …, differs from
    /// it by 1e-11 in the velocities and 3.4e-8 in λ₁, relative.) Quoted with every digit
    /// published, beyond f64's.
    #[allow(clippy::excessive_precision)]
    pub const REFERENCE: [f64; 10] = [
        0.493_455_784_275_402_809_122e-1,
        0.496_989_460_230_171_153_861,
        0.104_174_252_488_542_151_681e1,
        0.373_911_027_265_361_256_927,
        -0.770_583_684_040_972_357_970e-1,
        0.744_686_658_723_778_553_466e-2,
        0.175_568_157_537_232_222_276e-1,
        0.770_341_043_779_251_976_443,
        -0.473_688_659_084_893_324_729e-2,
        -0.110_468_033_125_734_368_808e-2,
    ];
}

/// The significant correct digits of `y` against `reference` as the test set defines them:
/// −log₁₀ of the largest relative error |yᵢ − refᵢ| / |refᵢ| over the components.
pub fn scd(y: &[f64], reference: &[f64]) -> f64 {
    let worst = y
        .iter()
        .zip(reference)
        .map(|(a, b)| ((a - b) / b).abs())
        .fold(0.0_f64, f64::max);
    -worst.log10()
}

/// Andrews' squeezing mechanism (test set problem "andrews"; Andrews & Hairer, *Solving ODEs
/// II*, VII.7; Schiehlen's benchmark): seven rigid bodies in a plane joined by frictionless
/// hinges, driven by a constant torque on the crank and held by a spring; its coordinates the
/// seven angles (β, Θ, γ, Φ, δ, Ω, ε), its six constraints the closures of three loops. Written
/// as the test set gives it: the kinetic energy ½ q̇ᵀ M(q) q̇ with the test set's mass matrix,
/// the spring's energy ½ c₀ (ℓ − ℓ₀)², the torque as a generalized force on β; the Coriolis
/// terms that the test set writes out by hand are derived from L here.
///
/// The test set writes M q̈ = f − Gᵀλ: its λ is ours negated.
#[derive(Clone, Copy, Debug)]
pub struct Andrews {
    pub m1: f64,
    pub m2: f64,
    pub m3: f64,
    pub m4: f64,
    pub m5: f64,
    pub m6: f64,
    pub m7: f64,
    pub xa: f64,
    pub ya: f64,
    pub xb: f64,
    pub yb: f64,
    pub xc: f64,
    pub yc: f64,
    pub c0: f64,
    pub i1: f64,
    pub i2: f64,
    pub i3: f64,
    pub i4: f64,
    pub i5: f64,
    pub i6: f64,
    pub i7: f64,
    pub d: f64,
    pub da: f64,
    pub e: f64,
    pub ea: f64,
    pub rr: f64,
    pub ra: f64,
    pub l0: f64,
    pub ss: f64,
    pub sa: f64,
    pub sb: f64,
    pub sc: f64,
    pub sd: f64,
    pub ta: f64,
    pub tb: f64,
    pub u: f64,
    pub ua: f64,
    pub ub: f64,
    pub zf: f64,
    pub zt: f64,
    pub fa: f64,
    pub mom: f64,
}

#[lagrangian]
impl Andrews {
    #[allow(clippy::too_many_arguments)]
    fn lagrangian(
        &self,
        (_be, be_dot): Coord,
        (th, th_dot): Coord,
        (ga, ga_dot): Coord,
        (ph, ph_dot): Coord,
        (_de, de_dot): Coord,
        (om, om_dot): Coord,
        (_ep, ep_dot): Coord,
    ) -> Scalar {
        let ee = self.e - self.ea;
        let zz = self.zf - self.fa;
        // The test set's mass matrix (its entries (1,1) … (7,7); (2,1), (5,4), (7,6) the only
        // couplings).
        let m11 = self.m1 * self.ra * self.ra
            + self.m2
                * (self.rr * self.rr - 2.0 * self.da * self.rr * th.cos() + self.da * self.da)
            + self.i1
            + self.i2;
        let m21 = self.m2 * (self.da * self.da - self.da * self.rr * th.cos()) + self.i2;
        let m22 = self.m2 * self.da * self.da + self.i2;
        let m33 = self.m3 * (self.sa * self.sa + self.sb * self.sb) + self.i3;
        let m44 = self.m4 * ee * ee + self.i4;
        let m54 = self.m4 * (ee * ee + self.zt * ee * ph.sin()) + self.i4;
        let m55 = self.m4 * (self.zt * self.zt + 2.0 * self.zt * ee * ph.sin() + ee * ee)
            + self.m5 * (self.ta * self.ta + self.tb * self.tb)
            + self.i4
            + self.i5;
        let m66 = self.m6 * zz * zz + self.i6;
        let m76 = self.m6 * (zz * zz - self.u * zz * om.sin()) + self.i6;
        let m77 = self.m6 * (zz * zz - 2.0 * self.u * zz * om.sin() + self.u * self.u)
            + self.m7 * (self.ua * self.ua + self.ub * self.ub)
            + self.i6
            + self.i7;
        let kinetic = 0.5 * (m11 * be_dot * be_dot + m22 * th_dot * th_dot)
            + m21 * be_dot * th_dot
            + 0.5 * m33 * ga_dot * ga_dot
            + 0.5 * (m44 * ph_dot * ph_dot + m55 * de_dot * de_dot)
            + m54 * ph_dot * de_dot
            + 0.5 * (m66 * om_dot * om_dot + m77 * ep_dot * ep_dot)
            + m76 * om_dot * ep_dot;
        // The spring from the point D of body 3 to the fixed point C.
        let xd = self.sd * ga.cos() + self.sc * ga.sin() + self.xb;
        let yd = self.sd * ga.sin() - self.sc * ga.cos() + self.yb;
        let length = ((xd - self.xc).powi(2) + (yd - self.yc).powi(2)).sqrt();
        kinetic - 0.5 * self.c0 * (length - self.l0).powi(2)
    }
    /// The driving torque on the crank β.
    #[allow(clippy::too_many_arguments)]
    fn forces(
        &self,
        (_be, _): Coord,
        (_th, _): Coord,
        (_ga, _): Coord,
        (_ph, _): Coord,
        (_de, _): Coord,
        (_om, _): Coord,
        (_ep, _): Coord,
    ) -> [Scalar; 7] {
        [self.mom, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    }
    /// The closures of the three loops (the test set's g).
    #[allow(clippy::too_many_arguments)]
    fn constraints(
        &self,
        (be, _): Coord,
        (th, _): Coord,
        (ga, _): Coord,
        (ph, _): Coord,
        (de, _): Coord,
        (om, _): Coord,
        (ep, _): Coord,
    ) -> [Scalar; 6] {
        let x = self.rr * be.cos() - self.d * (be + th).cos();
        let y = self.rr * be.sin() - self.d * (be + th).sin();
        [
            x - self.ss * ga.sin() - self.xb,
            y + self.ss * ga.cos() - self.yb,
            x - self.e * (ph + de).sin() - self.zt * de.cos() - self.xa,
            y + self.e * (ph + de).cos() - self.zt * de.sin() - self.ya,
            x - self.zf * (om + ep).cos() - self.u * ep.sin() - self.xa,
            y - self.zf * (om + ep).sin() + self.u * ep.cos() - self.ya,
        ]
    }
}

impl Andrews {
    /// The test set's parameters (its `andpar`).
    pub const TESTSET: Andrews = Andrews {
        m1: 0.04325,
        m2: 0.00365,
        m3: 0.02373,
        m4: 0.00706,
        m5: 0.07050,
        m6: 0.00706,
        m7: 0.05498,
        xa: -0.06934,
        ya: -0.00227,
        xb: -0.03635,
        yb: 0.03273,
        xc: 0.014,
        yc: 0.072,
        c0: 4530.0,
        i1: 2.194e-6,
        i2: 4.410e-7,
        i3: 5.255e-6,
        i4: 5.667e-7,
        i5: 1.169e-5,
        i6: 5.667e-7,
        i7: 1.912e-5,
        d: 28e-3,
        da: 115e-4,
        e: 2e-2,
        ea: 1421e-5,
        rr: 7e-3,
        ra: 92e-5,
        l0: 7785e-5,
        ss: 35e-3,
        sa: 1874e-5,
        sb: 1043e-5,
        sc: 18e-3,
        sd: 2e-2,
        ta: 2308e-5,
        tb: 916e-5,
        u: 4e-2,
        ua: 1228e-5,
        ub: 449e-5,
        zf: 2e-2,
        zt: 4e-2,
        fa: 1421e-5,
        mom: 33e-3,
    };

    /// The end of the test set's interval, t = 0.03.
    pub const END: f64 = 0.03;

    /// The test set's initial state: the angles of its `andinit` (to 18 of its 30 digits), at
    /// rest.
    #[allow(clippy::excessive_precision)]
    pub fn start(&self) -> ([f64; 7], [f64; 7]) {
        (
            [
                -0.061_713_890_014_276_449_6,
                0.0,
                0.455_279_819_163_070_380,
                0.222_668_390_165_885_885,
                0.487_364_979_543_842_550,
                -0.222_668_390_165_885_885,
                1.230_547_444_549_821_19,
            ],
            [0.0; 7],
        )
    }

    /// The test set's reference solution at t = 0.03 (its `andsoln`: PSIDE at tolerance 1e-14 in
    /// Cray double precision): the angles, their rates, then the multipliers in our sign (the
    /// test set's negated), every digit as published.
    #[allow(clippy::excessive_precision)]
    pub const REFERENCE: [f64; 20] = [
        0.158_107_711_962_990_4e2,
        -0.157_563_710_598_429_8e2,
        0.408_222_401_307_310_1e-1,
        -0.534_730_116_322_694_8,
        0.524_409_965_880_530_4,
        0.534_730_116_322_694_8,
        0.104_808_074_104_226_3e1,
        0.113_992_030_215_120_8e4,
        -0.142_437_929_499_411_1e4,
        0.110_329_122_193_713_4e2,
        0.192_933_746_442_138_5e2,
        0.573_569_928_479_080_8,
        -0.192_933_746_442_138_5e2,
        0.323_179_165_802_695_5,
        -0.199_175_333_373_191_0e3,
        0.297_553_122_801_505_2e2,
        -0.230_665_411_909_839_9e2,
        -0.314_527_136_547_592_7e2,
        -0.226_424_923_208_273_9e2,
        -0.116_174_070_001_967_3e2,
    ];
}

/// The flexible slider crank (test set problem "crank", after Simeon, *Numerische Simulation
/// gekoppelter Systeme von partiellen und differential-algebraischen Gleichungen in der
/// Mehrkörperdynamik*, 1994): a rigid crank of length l₁ driven at constant speed Ω, an elastic
/// connecting rod of length l₂ (two lateral modes sin(πx/l₂), sin(2πx/l₂) and two longitudinal
/// displacements, at the midpoint and the end: q = (q₁, q₂, q₃, q₄)), a sliding block at x₃. Its
/// coordinates p = (φ₁, φ₂, x₃), q: seven, three constraints — the two closures of the loop
/// crank–rod–block and the drive φ₁ = Ω t (a moving constraint). Stiff: the rod's elastic modes
/// at ω = 1277, 5107, 6841 and 24 613 rad/s next to the crank's 150 rad/s.
///
/// Written as the test set gives it (its Fortran `RESMBS`, crank.F rev. 1.2 of 2006-10-02,
/// which is the ground truth here): the kinetic energy ½ [ṗ; q̇]ᵀ M(p, q) [ṗ; q̇] with the test
/// set's mass matrix M = [[M_r + M_e, Cᵀ], [C, M_Δ]], the rod's strain energy ½ qᵀ K_Δ q (the
/// linear elastic model, its default), no gravity (γ = 0) and no damping (its defaults). The
/// quadratic-velocity terms f_r, f_e, f_Δ that the test set writes out by hand are derived from
/// L here (exactly the test set's: its B is antisymmetric, so its −ρ q̇ᵀBq̇ is zero and its
/// 2ρφ̇₂Bq̇ is ρφ̇₂(B − Bᵀ)q̇).
///
/// π is the Fortran's `PI = 3.1415927D0` (in K_Δ, B, c₂, c₂₁), not f64's: the reference was
/// computed with it. The test set writes M a = f − Gᵀλ with the same g: its λ is ours negated.
#[derive(Clone, Copy, Debug)]
pub struct SliderCrank {
    /// The crank's length l₁.
    pub l1: f64,
    /// The rod's length l₂.
    pub l2: f64,
    /// The rod's mass m₂.
    pub m2: f64,
    /// The block's mass m₃.
    pub m3: f64,
    /// The crank's moment of inertia J₁.
    pub j1: f64,
    /// The rod's moment of inertia J₂.
    pub j2: f64,
    /// The rod's cross-section: thickness d (the test set's `BB`) …
    pub d: f64,
    /// … and height h (`HH`, the direction of the lateral modes).
    pub h: f64,
    /// The rod's density ρ.
    pub rho: f64,
    /// The rod's Young's modulus E.
    pub e: f64,
    /// The crank's angular speed Ω.
    pub omega: f64,
    /// π as the test set's Fortran has it.
    pub pi: f64,
}

#[lagrangian]
impl SliderCrank {
    #[allow(clippy::too_many_arguments)]
    fn lagrangian(
        &self,
        (phi1, phi1_dot): Coord,
        (phi2, phi2_dot): Coord,
        (_x3, x3_dot): Coord,
        (q1, q1_dot): Coord,
        (q2, q2_dot): Coord,
        (q3, q3_dot): Coord,
        (q4, q4_dot): Coord,
    ) -> Scalar {
        let pi = self.pi;
        // The test set's FACB, FACM, FACK: c₁ = fb (0, 0, 2/3, 1/6), c₂ = fb (2/π, 0, 0, 0),
        // c₁₂ = l₂ fb (0, 0, 1/3, 1/6), c₂₁ = l₂ fb (1/π, −1/(2π), 0, 0), B = fb [...],
        // M_Δ = fm [[½, 0, 0, 0], [0, ½, 0, 0], [0, 0, 8, 1], [0, 0, 1, 2]], K_Δ = fk [...].
        let fb = self.d * self.h * self.l2;
        let fm = self.rho * fb;
        let fk = self.e * self.d * self.h / self.l2;
        let hl2 = (self.h / self.l2) * (self.h / self.l2);
        let (s, c) = (phi1 - phi2).sin_cos();
        let c1_q = fb * (2.0 / 3.0 * q3 + q4 / 6.0);
        let c2_q = fb * 2.0 / pi * q1;
        let c12_q = self.l2 * fb * (q3 / 3.0 + q4 / 6.0);
        let c1_v = fb * (2.0 / 3.0 * q3_dot + q4_dot / 6.0);
        let c2_v = fb * 2.0 / pi * q1_dot;
        let c21_v = self.l2 * fb * (q1_dot / pi - q2_dot / (2.0 * pi));
        // qᵀ B q̇, B antisymmetric: B₁₃ = −b13, B₁₄ = b14, B₂₄ = b24.
        let b13 = 16.0 / (pi * pi * pi);
        let b14 = 8.0 / (pi * pi * pi) - 1.0 / pi;
        let b24 = 0.5 / pi;
        let q_b_v = fb
            * (b13 * (q3 * q1_dot - q1 * q3_dot)
                + b14 * (q1 * q4_dot - q4 * q1_dot)
                + b24 * (q2 * q4_dot - q4 * q2_dot));
        let q_m_q =
            fm * (0.5 * q1 * q1 + 0.5 * q2 * q2 + 8.0 * q3 * q3 + 2.0 * q3 * q4 + 2.0 * q4 * q4);
        let v_m_v = fm
            * (0.5 * q1_dot * q1_dot
                + 0.5 * q2_dot * q2_dot
                + 8.0 * q3_dot * q3_dot
                + 2.0 * q3_dot * q4_dot
                + 2.0 * q4_dot * q4_dot);
        // M's rigid-and-coupled entries (M_r + M_e), and C q̇ by rows φ₁, φ₂.
        let m11 = self.j1 + self.m2 * self.l1 * self.l1;
        let m12 =
            0.5 * self.l1 * self.l2 * self.m2 * c + self.rho * self.l1 * (s * c2_q + c * c1_q);
        let m22 = self.j2 + q_m_q + 2.0 * self.rho * c12_q;
        let c_v1 = self.rho * self.l1 * (c * c2_v - s * c1_v);
        let c_v2 = self.rho * (c21_v + q_b_v);
        let kinetic = 0.5 * (m11 * phi1_dot * phi1_dot + m22 * phi2_dot * phi2_dot)
            + m12 * phi1_dot * phi2_dot
            + 0.5 * self.m3 * x3_dot * x3_dot
            + phi1_dot * c_v1
            + phi2_dot * c_v2
            + 0.5 * v_m_v;
        let pi4 = pi * pi * pi * pi;
        let strain = 0.5
            * fk
            * (pi4 / 24.0 * hl2 * q1 * q1 + pi4 * 2.0 / 3.0 * hl2 * q2 * q2 + 16.0 / 3.0 * q3 * q3
                - 16.0 / 3.0 * q3 * q4
                + 7.0 / 3.0 * q4 * q4);
        kinetic - strain
    }
    /// The loop's two closures (the rod's end, lengthened by q₄, on the block) and the drive.
    #[allow(clippy::too_many_arguments)]
    fn constraints(
        &self,
        (phi1, _): Coord,
        (phi2, _): Coord,
        (x3, _): Coord,
        (_, _): Coord,
        (_, _): Coord,
        (_, _): Coord,
        (q4, _): Coord,
        t: Time,
    ) -> [Scalar; 3] {
        let rod = self.l2 + q4;
        [
            self.l1 * phi1.sin() + rod * phi2.sin(),
            x3 - self.l1 * phi1.cos() - rod * phi2.cos(),
            phi1 - self.omega * t,
        ]
    }
}

impl SliderCrank {
    /// The test set's parameters (its `RESMBS` data statement): l₁ = 0.15, l₂ = 0.30 m;
    /// m₂ = 0.151104, m₃ = 0.075552 kg (the crank's m₁ = 0.36 enters only with gravity);
    /// J₁ = 0.002727, J₂ = 0.0045339259 kg m²; d = h = 0.008 m; ρ = 7870 kg/m³; E = 2·10¹¹ N/m²;
    /// Ω = 150 rad/s; π = 3.1415927.
    #[allow(clippy::approx_constant)]
    pub const TESTSET: SliderCrank = SliderCrank {
        l1: 0.15,
        l2: 0.30,
        m2: 0.151104,
        m3: 0.075552,
        j1: 0.002727,
        j2: 0.0045339259,
        d: 0.008,
        h: 0.008,
        rho: 7870.0,
        e: 0.20e12,
        omega: 150.0,
        pi: 3.1415927,
    };

    /// The end of the test set's interval, t = 0.1.
    pub const END: f64 = 0.1;

    /// The test set's initial state (release 2.4, p. II-19-2: "close to smooth motion"),
    /// (φ₁, φ₂, x₃, q₁, q₂, q₃, q₄) and their rates, except x₃: the published
    /// x₃ = 0.450016933 misses the second closure x₃ = l₁ + l₂ + q₄ = 0.4500169327969 by
    /// 2.03·10⁻¹⁰ (the test set's index-2 formulation keeps only the velocity constraints, so
    /// this offset stays, and as x₃ enters nothing else it shifts x₃ alone:
    /// [`X3_OFFSET`](Self::X3_OFFSET)). Here x₃ is put on the constraint. The rates satisfy
    /// the velocity constraints exactly.
    #[allow(clippy::excessive_precision)]
    pub fn start(&self) -> ([f64; 7], [f64; 7]) {
        let q4 = 0.169_327_969e-4;
        (
            [
                0.0,
                0.0,
                self.l1 + self.l2 + q4,
                0.0,
                0.0,
                0.103_339_863e-4,
                q4,
            ],
            [
                0.150_000_000e3,
                -0.749_957_670_396_945_3e2,
                -0.268_938_671_997_904_0e-5,
                0.444_896_112_581_599_0,
                0.463_433_931_923_867_0e-2,
                -0.178_591_076_000_055_0e-5,
                -0.268_938_671_997_904_0e-5,
            ],
        )
    }

    /// The published x₃(0) less the consistent one: 0.450016933 − (l₁ + l₂ + q₄(0)) =
    /// 2.031·10⁻¹⁰, the constant by which the test set's x₃(t) (and its reference's) exceeds ours.
    pub const X3_OFFSET: f64 = 2.031e-10;

    /// The test set's consistent initial accelerations (y₁₅ … y₂₁, release 2.4, p. II-19-2),
    /// the same coordinates' order as [`start`](Self::start).
    #[allow(clippy::excessive_precision)]
    pub const START_ACCELERATIONS: [f64; 7] = [
        0.0,
        -1.344_541_576_709_835e-3,
        -5.062_194_924_490_193e3,
        -6.829_725_665_986_310e-5,
        1.813_207_639_590_617e-20,
        -4.268_463_266_810_281,
        2.098_339_029_337_557e-1,
    ];

    /// The test set's consistent initial multipliers (y₂₂ … y₂₄, release 2.4, p. II-19-2) in
    /// our sign: the published ones negated.
    #[allow(clippy::excessive_precision)]
    pub const START_MULTIPLIERS: [f64; 3] = [
        6.552_727_150_584_648e-8,
        -3.824_589_509_350_831e2,
        4.635_908_708_561_371e-9,
    ];

    /// Our state (q, q̇, λ, …) as the test set's: x₃ + [`X3_OFFSET`](Self::X3_OFFSET), the
    /// offset of the published start that its index-2 formulation carries along.
    pub fn to_testset(y: &mut [f64]) {
        y[2] += Self::X3_OFFSET;
    }

    /// The reference's accelerations at t = 0.1 (y₁₅ … y₂₁ of `cranksoln`, release 2.4; y₁₅ = φ̈₁
    /// = 0), the same coordinates' order as [`start`](Self::start).
    #[allow(clippy::excessive_precision)]
    pub const REFERENCE_ACCELERATIONS: [f64; 7] = [
        0.0,
        0.648_873_754_127_695_7e4,
        0.216_793_862_950_988_4e4,
        0.339_113_706_028_652_3e2,
        0.171_513_477_221_648_8,
        -0.142_244_940_891_251_2e1,
        0.100_394_642_812_481_0e1,
    ];

    /// The test set's reference solution at t = 0.1, release 2.4 (its `cranksoln`, Table
    /// II.19.2: MEBDFI at rtol = atol = 10⁻¹⁴, h₀ = 10⁻¹²): positions y₁ … y₇, velocities
    /// y₈ … y₁₄, then the multipliers y₂₂ … y₂₄ in our sign (negated); the accelerations
    /// y₁₅ … y₂₁ are left out (our state does not hold them). Its x₃ carries the start's offset
    /// [`X3_OFFSET`](Self::X3_OFFSET).
    #[allow(clippy::excessive_precision)]
    pub const REFERENCE: [f64; 17] = [
        0.150_000_000_000_010_4e2,
        -0.331_173_498_825_626_0,
        0.169_737_332_842_786_0,
        0.189_319_289_961_350_9e-3,
        0.237_575_124_987_917_4e-4,
        -0.532_389_677_056_970_2e-5,
        -0.836_331_327_911_212_9e-5,
        0.150_000_000_000_000_0e3,
        0.602_534_675_513_836_9e2,
        -0.875_311_632_667_052_7e1,
        -0.300_554_140_028_973_8e-1,
        -0.550_043_181_257_169_6e-2,
        0.497_411_173_426_698_9e-3,
        0.110_556_000_362_664_5e-2,
        0.623_293_583_328_791_6e2,
        0.163_792_099_336_730_6e3,
        -0.252_985_794_706_687_8e2,
    ];
}
