"""CasADi peer for benches/testset.rs: the IVP test set's car axis (Mazzia & Magherini, release
2.4) to t = 3 with SUNDIALS IDAS through CasADi, the compiled DAE solver that installs with pip.

IDAS takes a semi-explicit index-1 DAE, so the car axis is given in its index-1 form: the
differential states (q, q'), the algebraic ones (q'', lambda), and the equations
k q'' = f(q, t) + G(q, t)^T lambda, G q'' + gamma(q, q', t) = 0, gamma the rest of g'' (from
CasADi's own derivatives of g). No projection: the run drifts off g = 0 as an index-1 run does.

Prints one line per tolerance: the best-of-5 wall time, the significant correct digits of q,
q' and lambda at t = 3 against the quad-precision reference (GAMD, as in
examples/support/testset_system.rs), and IDAS's statistics.

Install: python3 -m pip install casadi      Run: python3 benches/peers/casadi_caraxis.py
"""
import math
import time

import casadi as ca

EPS, M, L, L0, R, W, G = 1e-2, 10.0, 1.0, 0.5, 0.1, 10.0, 1.0
K = M * EPS * EPS / 2.0
T_END = 3.0
REFERENCE = [
    0.493455784275402809122e-1, 0.496989460230171153861, 0.104174252488542151681e1,
    0.373911027265361256927, -0.770583684040972357970e-1, 0.744686658723778553466e-2,
    0.175568157537232222276e-1, 0.770341043779251976443, -0.473688659084893324729e-2,
    -0.110468033125734368808e-2,
]


def scd(y, ref):
    worst = max(abs((a - b) / b) for a, b in zip(y, ref))
    return -math.log10(worst) if worst > 0 else float("inf")


def problem():
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
    gq = ca.jacobian(g, q)
    gdot = ca.mtimes(gq, v) + ca.jacobian(g, t)
    gamma = ca.mtimes(ca.jacobian(gdot, q), v) + ca.jacobian(gdot, t)
    spring = ca.vertcat(
        (L0 - ll) * xl / ll,
        (L0 - ll) * yl / ll - K * G,
        (L0 - lr) * (xr - xb) / lr,
        (L0 - lr) * (yr - yb) / lr - K * G,
    )
    alg = ca.vertcat(K * a - spring - ca.mtimes(gq.T, lam), ca.mtimes(gq, a) + gamma)
    dae = {"t": t, "x": ca.vertcat(q, v), "z": ca.vertcat(a, lam), "ode": ca.vertcat(v, a), "alg": alg}
    return dae


def main():
    dae = problem()
    x0 = [0.0, L0, L, L0, -L0 / L, 0.0, -L0 / L, 0.0]
    z0 = [0.0] * 6
    print(f"casadi {ca.__version__}")
    for tol in (1e-6, 1e-8, 1e-10, 1e-12):
        opts = {"abstol": tol, "reltol": tol, "calc_ic": True, "max_num_steps": 1000000}
        f = ca.integrator("F", "idas", dae, 0.0, T_END, opts)
        best = float("inf")
        for _ in range(5):
            t0 = time.perf_counter()
            out = f(x0=x0, z0=z0)
            best = min(best, time.perf_counter() - t0)
        x = [float(e) for e in ca.vertsplit(out["xf"])]
        z = [float(e) for e in ca.vertsplit(out["zf"])]
        st = f.stats()
        print(
            f"casadi IDAS tol {tol:.0e}: best of 5 wall {best * 1e3:.3f} ms, scd q "
            f"{scd(x[:4], REFERENCE[:4]):.2f} q' {scd(x[4:], REFERENCE[4:8]):.2f} lambda "
            f"{scd(z[4:], REFERENCE[8:]):.2f}, steps {st.get('nsteps', '?')}, "
            f"rhs {st.get('nfevals', '?')}, jacobians {st.get('njevals', '?')}"
        )


if __name__ == "__main__":
    main()
