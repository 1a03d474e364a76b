"""SciPy peer for benches/stiff.rs: two unit masses, a soft spring k1 = 1 to the wall and a stiff
one k2 = 1e8 between them, from the slow manifold (the slow mode's shape, at rest) to t = 10 with
solve_ivp(method="Radau") and solve_ivp(method="BDF"), rtol=1e-8, atol=1e-10, given the exact
(constant) Jacobian.

Prints one line per method: the best-of-5 wall time, steps, nfev, njev, nlu and the largest error
in (q, q') at t = 10 against the modal solution.

Install: python3 -m pip install scipy      Run: python3 benches/peers/scipy_stiff.py
"""
import time

import numpy as np
import scipy
from scipy.integrate import solve_ivp

K1, K2 = 1.0, 1e8
T_END = 10.0
RTOL, ATOL = 1e-8, 1e-10
K = np.array([[K1 + K2, -K2], [-K2, K2]])
JAC = np.block([[np.zeros((2, 2)), np.eye(2)], [-K, np.zeros((2, 2))]])


def modes():
    """(omega^2, shape) of the slow and the fast mode, shapes of unit length (as the Rust model)."""
    b = K1 + 2.0 * K2
    fast = 0.5 * (b + np.sqrt(b * b - 4.0 * K1 * K2))
    slow = K1 * K2 / fast
    out = []
    for w2 in (slow, fast):
        v = np.array([1.0, (K1 + K2 - w2) / K2]) if w2 < K2 else np.array([(K2 - w2) / K2, 1.0])
        out.append((w2, v / np.linalg.norm(v)))
    return out


def exact(q0, v0, t):
    q, v = np.zeros(2), np.zeros(2)
    for w2, s in modes():
        w = np.sqrt(w2)
        a = s @ q0
        b = (s @ v0) / w
        q += s * (a * np.cos(w * t) + b * np.sin(w * t))
        v += s * w * (b * np.cos(w * t) - a * np.sin(w * t))
    return q, v


def rhs(_t, y):
    return np.concatenate([y[2:], -K @ y[:2]])


def main():
    s = modes()[0][1]
    q0, v0 = np.array([1.0, s[1] / s[0]]), np.zeros(2)
    y0 = np.concatenate([q0, v0])
    qe, ve = exact(q0, v0, T_END)
    for method in ("Radau", "BDF"):
        times = []
        sol = None
        for _ in range(5):
            t0 = time.perf_counter()
            sol = solve_ivp(rhs, (0.0, T_END), y0, method=method, rtol=RTOL, atol=ATOL, jac=JAC)
            times.append(time.perf_counter() - t0)
        assert sol.success, sol.message
        y = sol.y[:, -1]
        err = max(np.max(np.abs(y[:2] - qe)), np.max(np.abs(y[2:] - ve)))
        print(f"scipy {scipy.__version__} solve_ivp {method}: best of 5 wall "
              f"{min(times) * 1e3:.3f} ms, steps {len(sol.t) - 1}, nfev {sol.nfev}, "
              f"njev {sol.njev}, nlu {sol.nlu}, error {err:.2e}")


if __name__ == "__main__":
    main()
