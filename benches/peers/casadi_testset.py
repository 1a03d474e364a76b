"""CasADi peer for benches/testset.rs: the IVP test set's three mechanical problems (Mazzia &
Magherini, "Test set for IVP solvers", release 2.4) with SUNDIALS IDAS through CasADi, the
compiled DAE solver that installs with pip.

    caraxis   the car axis to t = 3 (index 3, a moving constraint)
    andrews   Andrews' squeezing mechanism to t = 0.03 (7 bodies, 6 loop closures, index 3)
    crank     the flexible slider crank to t = 0.1 (stiff elastic modes, the drive phi1 = Omega t)

IDAS takes a semi-explicit index-1 DAE, so each problem is given in its index-1 form: the
differential states (q, q'), the algebraic ones (q'', lambda), and the equations
M(q, t) q'' = f(q, q', t) + G(q, t)^T lambda, G q'' + gamma(q, q', t) = 0, gamma the rest of g''
(from CasADi's own derivatives of g). No projection: the run drifts off g = 0 and G q' + g_t = 0
as an index-1 run does (printed at the end of each line: the largest |g| and |g'| at the end).

The physics is that of examples/support/testset_system.rs, term for term: the car axis as the
test set writes it (k q'' = spring forces + G^T lambda); Andrews and the slider crank from the
same Lagrangians as the Rust versions (the test set's mass matrices, the spring's and the rod's
strain energies, Andrews' driving torque), M = d2L/dq'2 and f = dL/dq - (d2L/dq'dq) q' - d2L/dq'dt
+ Q from CasADi's derivatives; the same parameters (the crank's pi = 3.1415927 of the test set's
Fortran), initial values and references. The multipliers are in the Rust versions' sign (the
test set's negated for Andrews and the crank); the crank's x3 is started on the constraint and
compared with the published start's offset 2.031e-10 added, as tests/testset.rs does.

Prints one line per configuration and tolerance (IDAS's defaults, then the algebraic variables
out of its error test; the tolerances each problem's TOLERANCES, rtol = atol, down to where IDAS
fails, the failure printed): the best-of-5 wall time, the significant correct digits of q, q' and
lambda at the end against the reference (each kind apart, as tests/testset.rs), IDAS's
statistics (steps, residual evaluations, Jacobians, error test failures) and the drift off the
constraints at the end. The DAE's functions are compiled (CasADi's jit, -O3) when a C compiler is
there. With --check: the model's consistent initial accelerations and multipliers against the
test set's published ones (Andrews, the crank: measured 2026-12-08, Andrews to 7.7e-15 relative,
the crank with f64's pi to 1.7e-11, with the Fortran's pi to 6.3e-6, as tests/testset.rs finds).

Install: python3 -m pip install casadi
Run:     python3 benches/peers/casadi_testset.py caraxis|andrews|crank [--check]
"""
import math
import sys
import time

import casadi as ca


def scd(y, ref):
    worst = max(abs((a - b) / b) for a, b in zip(y, ref))
    return -math.log10(worst) if worst > 0 else float("inf")


def index1(q, v, t, a, lam, mass, force, g):
    """The index-1 DAE of M q'' = f + G^T lambda, g(q, t) = 0: (x, z, ode, alg), and the
    functions of the drift g and g' = G q' + g_t."""
    gq = ca.jacobian(g, q)
    gdot = ca.mtimes(gq, v) + ca.jacobian(g, t)
    gamma = ca.mtimes(ca.jacobian(gdot, q), v) + ca.jacobian(gdot, t)
    alg = ca.vertcat(ca.mtimes(mass, a) - force - ca.mtimes(gq.T, lam), ca.mtimes(gq, a) + gamma)
    dae = {"t": t, "x": ca.vertcat(q, v), "z": ca.vertcat(a, lam), "ode": ca.vertcat(v, a), "alg": alg}
    drift = ca.Function("drift", [t, ca.vertcat(q, v)], [g, gdot])
    return dae, drift


def lagrangian_dae(lagrangian, q, v, t, a, lam, g, generalized=None):
    """The index-1 DAE of L(q, q', t) with the constraints g(q, t) = 0 and the generalized forces
    Q: M = d2L/dq'2, f = dL/dq - (d2L/dq'dq) q' - d2L/dq'dt + Q."""
    p = ca.gradient(lagrangian, v)
    mass = ca.jacobian(p, v)
    force = ca.gradient(lagrangian, q) - ca.mtimes(ca.jacobian(p, q), v) - ca.jacobian(p, t)
    if generalized is not None:
        force = force + generalized
    return index1(q, v, t, a, lam, mass, force, g)


class CarAxis:
    """examples/support/testset_system.rs's CarAxis, in the test set's own form."""

    name = "caraxis"
    n, m = 4, 2
    END = 3.0
    TOLERANCES = (1e-6, 1e-8, 1e-10, 1e-12)
    EPS, M, L, L0, R, W, G = 1e-2, 10.0, 1.0, 0.5, 0.1, 10.0, 1.0
    REFERENCE = [
        0.493455784275402809122e-1, 0.496989460230171153861, 0.104174252488542151681e1,
        0.373911027265361256927, -0.770583684040972357970e-1, 0.744686658723778553466e-2,
        0.175568157537232222276e-1, 0.770341043779251976443, -0.473688659084893324729e-2,
        -0.110468033125734368808e-2,
    ]

    def dae(self):
        EPS, M, L, L0, R, W, G = self.EPS, self.M, self.L, self.L0, self.R, self.W, self.G
        k = M * EPS * EPS / 2.0
        t = ca.SX.sym("t")
        q = ca.SX.sym("q", 4)
        v = ca.SX.sym("v", 4)
        a = ca.SX.sym("a", 4)
        lam = ca.SX.sym("lam", 2)
        xl, yl, xr, yr = q[0], q[1], q[2], q[3]
        yb = R * ca.sin(W * t)
        xb = ca.sqrt(L * L - yb * yb)
        ll = ca.sqrt(xl * xl + yl * yl)
        lr = ca.sqrt((xr - xb) ** 2 + (yr - yb) ** 2)
        g = ca.vertcat(xb * xl + yb * yl, (xl - xr) ** 2 + (yl - yr) ** 2 - L * L)
        spring = ca.vertcat(
            (L0 - ll) * xl / ll,
            (L0 - ll) * yl / ll - k * G,
            (L0 - lr) * (xr - xb) / lr,
            (L0 - lr) * (yr - yb) / lr - k * G,
        )
        return index1(q, v, t, a, lam, k * ca.SX.eye(4), spring, g)

    def start(self):
        L0, L = self.L0, self.L
        return [0.0, L0, L, L0, -L0 / L, 0.0, -L0 / L, 0.0]

    def to_reference(self, x):
        return x


class Andrews:
    """examples/support/testset_system.rs's Andrews: its Lagrangian, torque and loop closures."""

    name = "andrews"
    n, m = 7, 6
    END = 0.03
    # IDAS fails below 2e-11 (IDACalcIC's line search, or the corrector's convergence later on).
    TOLERANCES = (1e-6, 1e-8, 1e-10, 2e-11, 1e-11, 1e-12)
    P = dict(
        m1=0.04325, m2=0.00365, m3=0.02373, m4=0.00706, m5=0.07050, m6=0.00706, m7=0.05498,
        xa=-0.06934, ya=-0.00227, xb=-0.03635, yb=0.03273, xc=0.014, yc=0.072, c0=4530.0,
        i1=2.194e-6, i2=4.410e-7, i3=5.255e-6, i4=5.667e-7, i5=1.169e-5, i6=5.667e-7,
        i7=1.912e-5, d=28e-3, da=115e-4, e=2e-2, ea=1421e-5, rr=7e-3, ra=92e-5, l0=7785e-5,
        ss=35e-3, sa=1874e-5, sb=1043e-5, sc=18e-3, sd=2e-2, ta=2308e-5, tb=916e-5, u=4e-2,
        ua=1228e-5, ub=449e-5, zf=2e-2, zt=4e-2, fa=1421e-5, mom=33e-3,
    )
    # The test set's andsoln (PSIDE at 1e-14): angles, rates, multipliers in our sign.
    REFERENCE = [
        0.1581077119629904e2, -0.1575637105984298e2, 0.4082224013073101e-1,
        -0.5347301163226948, 0.5244099658805304, 0.5347301163226948, 0.1048080741042263e1,
        0.1139920302151208e4, -0.1424379294994111e4, 0.1103291221937134e2,
        0.1929337464421385e2, 0.5735699284790808, -0.1929337464421385e2, 0.3231791658026955,
        -0.1991753333731910e3, 0.2975531228015052e2, -0.2306654119098399e2,
        -0.3145271365475927e2, -0.2264249232082739e2, -0.1161740700019673e2,
    ]
    # The test set's consistent start (release 2.4, andinit): q'' and lambda (its sign).
    START_ACCELERATIONS = [14222.4439199541138705911625887, -10666.8329399655854029433719415,
                           0.0, 0.0, 0.0, 0.0, 0.0]
    START_MULTIPLIERS_TESTSET = [98.5668703962410896057654982170,
                                 -6.12268834425566265503114393122, 0.0, 0.0, 0.0, 0.0]

    def dae(self):
        p = self.P
        t = ca.SX.sym("t")
        q = ca.SX.sym("q", 7)
        v = ca.SX.sym("v", 7)
        a = ca.SX.sym("a", 7)
        lam = ca.SX.sym("lam", 6)
        be, th, ga, ph, de, om, ep = (q[i] for i in range(7))
        bd, thd, gad, phd, ded, omd, epd = (v[i] for i in range(7))
        ee = p["e"] - p["ea"]
        zz = p["zf"] - p["fa"]
        m11 = (p["m1"] * p["ra"] ** 2
               + p["m2"] * (p["rr"] ** 2 - 2 * p["da"] * p["rr"] * ca.cos(th) + p["da"] ** 2)
               + p["i1"] + p["i2"])
        m21 = p["m2"] * (p["da"] ** 2 - p["da"] * p["rr"] * ca.cos(th)) + p["i2"]
        m22 = p["m2"] * p["da"] ** 2 + p["i2"]
        m33 = p["m3"] * (p["sa"] ** 2 + p["sb"] ** 2) + p["i3"]
        m44 = p["m4"] * ee * ee + p["i4"]
        m54 = p["m4"] * (ee * ee + p["zt"] * ee * ca.sin(ph)) + p["i4"]
        m55 = (p["m4"] * (p["zt"] ** 2 + 2 * p["zt"] * ee * ca.sin(ph) + ee * ee)
               + p["m5"] * (p["ta"] ** 2 + p["tb"] ** 2) + p["i4"] + p["i5"])
        m66 = p["m6"] * zz * zz + p["i6"]
        m76 = p["m6"] * (zz * zz - p["u"] * zz * ca.sin(om)) + p["i6"]
        m77 = (p["m6"] * (zz * zz - 2 * p["u"] * zz * ca.sin(om) + p["u"] ** 2)
               + p["m7"] * (p["ua"] ** 2 + p["ub"] ** 2) + p["i6"] + p["i7"])
        kinetic = (0.5 * (m11 * bd * bd + m22 * thd * thd) + m21 * bd * thd
                   + 0.5 * m33 * gad * gad
                   + 0.5 * (m44 * phd * phd + m55 * ded * ded) + m54 * phd * ded
                   + 0.5 * (m66 * omd * omd + m77 * epd * epd) + m76 * omd * epd)
        xd = p["sd"] * ca.cos(ga) + p["sc"] * ca.sin(ga) + p["xb"]
        yd = p["sd"] * ca.sin(ga) - p["sc"] * ca.cos(ga) + p["yb"]
        length = ca.sqrt((xd - p["xc"]) ** 2 + (yd - p["yc"]) ** 2)
        lagrangian = kinetic - 0.5 * p["c0"] * (length - p["l0"]) ** 2
        torque = ca.vertcat(p["mom"], 0, 0, 0, 0, 0, 0)
        x = p["rr"] * ca.cos(be) - p["d"] * ca.cos(be + th)
        y = p["rr"] * ca.sin(be) - p["d"] * ca.sin(be + th)
        g = ca.vertcat(
            x - p["ss"] * ca.sin(ga) - p["xb"],
            y + p["ss"] * ca.cos(ga) - p["yb"],
            x - p["e"] * ca.sin(ph + de) - p["zt"] * ca.cos(de) - p["xa"],
            y + p["e"] * ca.cos(ph + de) - p["zt"] * ca.sin(de) - p["ya"],
            x - p["zf"] * ca.cos(om + ep) - p["u"] * ca.sin(ep) - p["xa"],
            y - p["zf"] * ca.sin(om + ep) + p["u"] * ca.cos(ep) - p["ya"],
        )
        return lagrangian_dae(lagrangian, q, v, t, a, lam, g, torque)

    def start(self):
        return [-0.0617138900142764496358948458001, 0.0, 0.455279819163070380255912382449,
                0.222668390165885884674473185609, 0.487364979543842550225598953530,
                -0.222668390165885884674473185609, 1.23054744454982119249735015568] + [0.0] * 7

    def check(self, a, lam):
        """Our start's q'', lambda against the test set's (its lambda negated)."""
        want_l = [-x for x in self.START_MULTIPLIERS_TESTSET]
        return [("q''", a, self.START_ACCELERATIONS), ("lambda", lam, want_l)]

    def to_reference(self, x):
        return x


class SliderCrank:
    """examples/support/testset_system.rs's SliderCrank: its Lagrangian (the test set's
    M(p, q), the rod's strain energy 1/2 q^T K q; no gravity, no damping) and constraints."""

    name = "crank"
    n, m = 7, 3
    END = 0.1
    # At 1e-11 the reference's double-precision ceiling (9.4 digits); at 1e-12 IDAS's defaults
    # take a million steps by t = 0.057.
    TOLERANCES = (1e-6, 1e-8, 1e-10, 1e-11, 1e-12)
    L1, L2, M2, M3, J1, J2 = 0.15, 0.30, 0.151104, 0.075552, 0.002727, 0.0045339259
    D, H, RHO, E, OMEGA = 0.008, 0.008, 7870.0, 0.20e12, 150.0
    PI = 3.1415927  # the test set's Fortran's, with which the reference was computed
    X3_OFFSET = 2.031e-10
    # cranksoln (release 2.4, MEBDFI at 1e-14): positions, velocities, multipliers in our sign.
    REFERENCE = [
        0.1500000000000104e2, -0.3311734988256260, 0.1697373328427860, 0.1893192899613509e-3,
        0.2375751249879174e-4, -0.5323896770569702e-5, -0.8363313279112129e-5,
        0.1500000000000000e3, 0.6025346755138369e2, -0.8753116326670527e1,
        -0.3005541400289738e-1, -0.5500431812571696e-2, 0.4974111734266989e-3,
        0.1105560003626645e-2,
        0.6232935833287916e2, 0.1637920993367306e3, -0.2529857947066878e2,
    ]
    # The test set's consistent start (release 2.4, p. II-19-2), y15..y21 and y22..y24 (its sign).
    START_ACCELERATIONS = [0.0, -1.344541576709835e-3, -5.062194924490193e3,
                           -6.829725665986310e-5, 1.813207639590617e-20, -4.268463266810281,
                           2.098339029337557e-1]
    START_MULTIPLIERS_TESTSET = [-6.552727150584648e-8, 3.824589509350831e2,
                                 -4.635908708561371e-9]

    def __init__(self, pi=None):
        self.pi = self.PI if pi is None else pi

    def dae(self):
        l1, l2, m2, m3, j1, j2 = self.L1, self.L2, self.M2, self.M3, self.J1, self.J2
        d, h, rho, e, omega, pi = self.D, self.H, self.RHO, self.E, self.OMEGA, self.pi
        t = ca.SX.sym("t")
        x = ca.SX.sym("q", 7)
        v = ca.SX.sym("v", 7)
        a = ca.SX.sym("a", 7)
        lam = ca.SX.sym("lam", 3)
        phi1, phi2, x3, q1, q2, q3, q4 = (x[i] for i in range(7))
        phi1d, phi2d, x3d, q1d, q2d, q3d, q4d = (v[i] for i in range(7))
        fb = d * h * l2
        fm = rho * fb
        fk = e * d * h / l2
        hl2 = (h / l2) ** 2
        s, c = ca.sin(phi1 - phi2), ca.cos(phi1 - phi2)
        c1_q = fb * (2.0 / 3.0 * q3 + q4 / 6.0)
        c2_q = fb * 2.0 / pi * q1
        c12_q = l2 * fb * (q3 / 3.0 + q4 / 6.0)
        c1_v = fb * (2.0 / 3.0 * q3d + q4d / 6.0)
        c2_v = fb * 2.0 / pi * q1d
        c21_v = l2 * fb * (q1d / pi - q2d / (2.0 * pi))
        b13 = 16.0 / pi ** 3
        b14 = 8.0 / pi ** 3 - 1.0 / pi
        b24 = 0.5 / pi
        q_b_v = fb * (b13 * (q3 * q1d - q1 * q3d) + b14 * (q1 * q4d - q4 * q1d)
                      + b24 * (q2 * q4d - q4 * q2d))
        q_m_q = fm * (0.5 * q1 * q1 + 0.5 * q2 * q2 + 8.0 * q3 * q3 + 2.0 * q3 * q4 + 2.0 * q4 * q4)
        v_m_v = fm * (0.5 * q1d * q1d + 0.5 * q2d * q2d + 8.0 * q3d * q3d + 2.0 * q3d * q4d
                      + 2.0 * q4d * q4d)
        m11 = j1 + m2 * l1 * l1
        m12 = 0.5 * l1 * l2 * m2 * c + rho * l1 * (s * c2_q + c * c1_q)
        m22 = j2 + q_m_q + 2.0 * rho * c12_q
        c_v1 = rho * l1 * (c * c2_v - s * c1_v)
        c_v2 = rho * (c21_v + q_b_v)
        kinetic = (0.5 * (m11 * phi1d * phi1d + m22 * phi2d * phi2d) + m12 * phi1d * phi2d
                   + 0.5 * m3 * x3d * x3d + phi1d * c_v1 + phi2d * c_v2 + 0.5 * v_m_v)
        pi4 = pi ** 4
        strain = 0.5 * fk * (pi4 / 24.0 * hl2 * q1 * q1 + pi4 * 2.0 / 3.0 * hl2 * q2 * q2
                             + 16.0 / 3.0 * q3 * q3 - 16.0 / 3.0 * q3 * q4 + 7.0 / 3.0 * q4 * q4)
        rod = l2 + q4
        g = ca.vertcat(
            l1 * ca.sin(phi1) + rod * ca.sin(phi2),
            x3 - l1 * ca.cos(phi1) - rod * ca.cos(phi2),
            phi1 - omega * t,
        )
        return lagrangian_dae(kinetic - strain, x, v, t, a, lam, g)

    def start(self):
        q4 = 0.169327969e-4
        return [0.0, 0.0, self.L1 + self.L2 + q4, 0.0, 0.0, 0.103339863e-4, q4,
                0.150000000e3, -0.7499576703969453e2, -0.2689386719979040e-5,
                0.4448961125815990, 0.4634339319238670e-2, -0.1785910760000550e-5,
                -0.2689386719979040e-5]

    def check(self, a, lam):
        want_l = [-x for x in self.START_MULTIPLIERS_TESTSET]
        return [("q''", a, self.START_ACCELERATIONS), ("lambda", lam, want_l)]

    def to_reference(self, x):
        """Our x3 as the test set's: the published start's offset added."""
        x = list(x)
        x[2] += self.X3_OFFSET
        return x


PROBLEMS = {"caraxis": CarAxis, "andrews": Andrews, "crank": SliderCrank}


def consistent_start(problem):
    """q'' and lambda at the start: the algebraic equations solved for z (linear in z)."""
    dae, _ = problem.dae()
    z = dae["z"]
    res = ca.Function("res", [dae["t"], dae["x"], z], [dae["alg"]])
    jac = ca.Function("alg_z", [dae["t"], dae["x"], z], [ca.jacobian(dae["alg"], z)])
    nz = z.shape[0]
    x0 = problem.start()
    r0 = res(0.0, x0, [0.0] * nz)
    sol = -ca.solve(jac(0.0, x0, [0.0] * nz), r0)
    sol = [float(e) for e in ca.vertsplit(sol)]
    return sol[: problem.n], sol[problem.n:]


def check(problem):
    """The model's consistent start against the test set's published one, with the test set's
    pi for the crank and with f64's (the published start was computed with the full pi)."""
    variants = [problem]
    if isinstance(problem, SliderCrank):
        variants = [SliderCrank(math.pi), SliderCrank()]
    for p in variants:
        a, lam = consistent_start(p)
        label = f"{p.name}" + (f" (pi = {p.pi!r})" if isinstance(p, SliderCrank) else "")
        for kind, got, want in p.check(a, lam):
            for i, (x, y) in enumerate(zip(got, want)):
                rel = abs(x - y) / abs(y) if y != 0 else abs(x - y)
                print(f"{label} {kind}[{i}]: ours {x:+.16e} test set {y:+.16e} "
                      f"{'relative' if y != 0 else 'absolute'} {rel:.1e}")


# IDAS's configurations, each run at every tolerance: its defaults (every variable in the local
# error test), and the algebraic variables q'', lambda left out of it (IDAS's option for DAEs whose
# algebraic variables need not be controlled: fewer steps, fewer digits at a given tolerance).
# Both with the DAE's functions compiled (CasADi's jit through the system's C compiler, -O3), as
# fast as IDAS runs them; without a compiler, CasADi's interpreted functions.
CONFIGURATIONS = (("", {}), ("suppress_algebraic ", {"suppress_algebraic": True}))
JIT = {"jit": True, "compiler": "shell", "jit_options": {"flags": ["-O3"]}}


def integrator(dae, end, opts):
    """IDAS over [0, end], its functions compiled when a C compiler is there."""
    try:
        return ca.integrator("F", "idas", dae, 0.0, end, {**opts, **JIT}), True
    except RuntimeError:
        return ca.integrator("F", "idas", dae, 0.0, end, opts), False


def main(name):
    problem = PROBLEMS[name]()
    dae, drift = problem.dae()
    n, m = problem.n, problem.m
    x0 = problem.start()
    # q'' and lambda from IDACalcIC: started at their consistent values, IDACalcIC's line search
    # fails on the crank (the residual is at round-off from the start).
    z0 = [0.0] * (n + m)
    ref = problem.REFERENCE
    compiled = None
    for label, options in CONFIGURATIONS:
        for tol in problem.TOLERANCES:
            opts = {"abstol": tol, "reltol": tol, "calc_ic": True, "max_num_steps": 1000000}
            opts.update(options)
            f, jit = integrator(dae, problem.END, opts)
            if compiled is None:
                compiled = jit
                print(f"casadi {ca.__version__} {name}, IDAS, the DAE's functions "
                      + ("compiled (jit, -O3)" if jit else "interpreted (no C compiler for jit)"))
            best = float("inf")
            try:
                for _ in range(5):
                    t0 = time.perf_counter()
                    out = f(x0=x0, z0=z0)
                    best = min(best, time.perf_counter() - t0)
            except RuntimeError as err:
                reason = str(err).splitlines()[-1].split(": ")[-1]
                print(f"casadi IDAS {label}tol {tol:.0e}: failed, {reason}")
                continue
            x = problem.to_reference([float(e) for e in ca.vertsplit(out["xf"])])
            z = [float(e) for e in ca.vertsplit(out["zf"])]
            gx, gv = drift(problem.END, out["xf"])
            g_max = max(abs(float(e)) for e in ca.vertsplit(gx))
            gv_max = max(abs(float(e)) for e in ca.vertsplit(gv))
            st = f.stats()
            print(
                f"casadi IDAS {label}tol {tol:.0e}: best of 5 wall {best * 1e3:.3f} ms, scd q "
                f"{scd(x[:n], ref[:n]):.2f} q' {scd(x[n:], ref[n:2 * n]):.2f} lambda "
                f"{scd(z[n:], ref[2 * n:]):.2f}, steps {st['nsteps']}, rhs {st['nfevals']}, "
                f"jacobians {st['n_call_jacF']}, error test failures {st['netfails']}, "
                f"drift |g| {g_max:.1e} |g'| {gv_max:.1e}",
                flush=True,
            )


if __name__ == "__main__":
    args = sys.argv[1:]
    if not args or args[0] not in PROBLEMS:
        sys.exit(f"usage: casadi_testset.py {'|'.join(PROBLEMS)} [--check]")
    if "--check" in args[1:]:
        if not hasattr(PROBLEMS[args[0]], "check"):
            sys.exit(f"{args[0]}: no published consistent start to check against")
        check(PROBLEMS[args[0]]())
    else:
        main(args[0])
