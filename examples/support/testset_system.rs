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
