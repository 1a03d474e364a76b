"""SciPy peer for benches/integrators.rs: the heavy top (I_perp = 1, I_par = 0.5, m g l = 4.905;
theta0 = 0.7, phidot0 = 2, psidot0 = 12, others 0) for t = 114.3 with
solve_ivp(method="DOP853", rtol=1e-10, atol=1e-12).

Reports the best-of-5 wall time, steps, nfev and the max relative drift of the energy and of the
two cyclic momenta over the returned steps.

With --family, reads initial conditions "theta0 phidot0 psidot0" (one per line) from stdin and
prints, for each, "nfev drift_energy drift_p_phi drift_p_psi" of the same untimed run (the drift of
one trajectory is partly luck of its step sequence; benches/integrators.rs compares many).

Install: python3 -m pip install scipy      Run: python3 benches/peers/scipy_dop853.py
"""
import sys
import time

import numpy as np
import scipy
from scipy.integrate import solve_ivp

I_PERP, I_PAR, MGL = 1.0, 0.5, 4.905
T_END = 114.3
Y0 = np.array([0.7, 0.0, 0.0, 0.0, 2.0, 12.0])  # theta, phi, psi, theta', phi', psi'


def rhs(_t, y):
    th, _ph, _ps, th_d, ph_d, ps_d = y
    s, c = np.sin(th), np.cos(th)
    w3 = ps_d + ph_d * c
    th_dd = ph_d * ph_d * s * c - I_PAR / I_PERP * w3 * ph_d * s + MGL / I_PERP * s
    ph_dd = th_d * (I_PAR * w3 - 2.0 * I_PERP * ph_d * c) / (I_PERP * s)
    ps_dd = ph_d * th_d * s - ph_dd * c
    return np.array([th_d, ph_d, ps_d, th_dd, ph_dd, ps_dd])


def invariants(y):
    th, _ph, _ps, th_d, ph_d, ps_d = y
    s, c = np.sin(th), np.cos(th)
    l_par = I_PAR * (ps_d + ph_d * c)
    l_phi = I_PERP * ph_d * s * s + l_par * c
    energy = 0.5 * I_PERP * (th_d**2 + (ph_d * s) ** 2) + l_par**2 / (2 * I_PAR) + MGL * c
    return energy, l_phi, l_par


def drift(x):
    return float(np.max(np.abs(x - x[0])) / max(abs(x[0]), 1e-12))


def main():
    times = []
    sol = None
    for _ in range(5):
        t0 = time.perf_counter()
        sol = solve_ivp(rhs, (0.0, T_END), Y0, method="DOP853", rtol=1e-10, atol=1e-12)
        times.append(time.perf_counter() - t0)
    assert sol.success, sol.message
    e, p_phi, p_psi = invariants(sol.y)
    print(f"scipy {scipy.__version__} solve_ivp DOP853: best of 5 wall {min(times) * 1e3:.2f} ms "
          f"(median {sorted(times)[2] * 1e3:.2f} ms), steps {len(sol.t) - 1}, nfev {sol.nfev}, "
          f"max rel drift: energy {drift(e):.2e}, p_phi {drift(p_phi):.2e}, p_psi {drift(p_psi):.2e}, "
          f"final theta {sol.y[0, -1]:.12f}")


def family():
    for line in sys.stdin:
        if not line.strip():
            continue
        th, ph_d, ps_d = map(float, line.split())
        y0 = np.array([th, 0.0, 0.0, 0.0, ph_d, ps_d])
        sol = solve_ivp(rhs, (0.0, T_END), y0, method="DOP853", rtol=1e-10, atol=1e-12)
        assert sol.success, sol.message
        e, p_phi, p_psi = invariants(sol.y)
        print(sol.nfev, drift(e), drift(p_phi), drift(p_psi), flush=True)


if __name__ == "__main__":
    if "--family" in sys.argv[1:]:
        family()
    else:
        main()
