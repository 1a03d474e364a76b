"""heyoka peer for the Taylor work-precision race (benches/taylor.rs): the heavy top
(I_perp = 1, I_par = 0.5, m g l = 4.905; theta0 = 0.7, phidot0 = 2, psidot0 = 12, others 0) for
t = 114.3, scalar mode, with

- "hand": the hand-written right-hand side (the closed form of the Euler-Lagrange equations),
- "lagrangian": the equations heyoka derives itself with heyoka.lagrangian(L, qs, qdots).

With --var, the same with the first-order variational equations integrated along
(heyoka.var_ode_sys(sys, var_args.vars, order=1): the state transition matrix, 6 x 6, its
initial value the identity), paths "hand-var" and "lagrangian-var": what benches/taylor.rs's
variational section compares our sensitivity runs with.

For each path and tolerance: the compile time (building the integrator: heyoka JIT-compiles with
LLVM) once, then the propagation alone (the state reset to the initial one, propagate_until), min
and median wall time over many repeats, the steps, and the final theta.

Usage: python3 benches/peers/heyoka_top.py [--repeats R] [--var] TOL [TOL ...]
Prints one line per (path, tol):
    heyoka <path> tol <tol> compile_ms <c> min_ms <m> median_ms <md> steps <n> theta <th>
Install: python3 -m pip install heyoka   (7.x)
"""
import sys
import time

import heyoka as hy
import numpy as np

I_PERP, I_PAR, MGL = 1.0, 0.5, 4.905
T_END = 114.3
Y0 = [0.7, 0.0, 0.0, 0.0, 2.0, 12.0]  # theta, phi, psi, theta', phi', psi'


def hand_sys():
    th, ph, ps, th_d, ph_d, ps_d = hy.make_vars("th", "ph", "ps", "th_d", "ph_d", "ps_d")
    s, c = hy.sin(th), hy.cos(th)
    w3 = ps_d + ph_d * c
    th_dd = ph_d * ph_d * s * c - I_PAR / I_PERP * w3 * ph_d * s + MGL / I_PERP * s
    ph_dd = th_d * (I_PAR * w3 - 2.0 * I_PERP * ph_d * c) / (I_PERP * s)
    ps_dd = ph_d * th_d * s - ph_dd * c
    return [(th, th_d), (ph, ph_d), (ps, ps_d), (th_d, th_dd), (ph_d, ph_dd), (ps_d, ps_dd)]


def lagrangian_sys():
    th, ph, ps, th_d, ph_d, ps_d = hy.make_vars("th", "ph", "ps", "th_d", "ph_d", "ps_d")
    s, c = hy.sin(th), hy.cos(th)
    L = (I_PERP / 2.0 * (th_d * th_d + (ph_d * s) * (ph_d * s))
         + I_PAR / 2.0 * (ps_d + ph_d * c) * (ps_d + ph_d * c) - MGL * c)
    return hy.lagrangian(L, [th, ph, ps], [th_d, ph_d, ps_d])


def measure(path, make, tol, repeats, var=False):
    sys_ = make()
    t0 = time.perf_counter()
    if var:
        sys_ = hy.var_ode_sys(sys_, hy.var_args.vars, order=1)
        path += "-var"
    ta = hy.taylor_adaptive(sys_, Y0, tol=tol)
    compile_ms = (time.perf_counter() - t0) * 1e3
    # The whole initial state (with a variational system: the identity after Y0).
    start = np.array(ta.state)
    # heyoka orders the state as the pairs were given: lagrangian() gives qs then qdots, as hand.
    times = []
    steps = 0
    for _ in range(repeats):
        ta.time = 0.0
        ta.state[:] = start
        t0 = time.perf_counter()
        res = ta.propagate_until(T_END)
        times.append(time.perf_counter() - t0)
        steps = res[3]
    times.sort()
    print(f"heyoka {path} tol {tol:.0e} compile_ms {compile_ms:.1f} min_ms {times[0] * 1e3:.4f} "
          f"median_ms {times[len(times) // 2] * 1e3:.4f} steps {steps} theta {float(ta.state[0])!r}",
          flush=True)


def main():
    args = sys.argv[1:]
    repeats = 50
    if args and args[0] == "--repeats":
        repeats = int(args[1])
        args = args[2:]
    var = bool(args) and args[0] == "--var"
    if var:
        args = args[1:]
    tols = [float(a) for a in args] or [1e-13, 1e-15]
    for tol in tols:
        measure("hand", hand_sys, tol, repeats, var)
        measure("lagrangian", lagrangian_sys, tol, repeats, var)


if __name__ == "__main__":
    main()
