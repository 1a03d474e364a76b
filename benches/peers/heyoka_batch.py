"""heyoka batch peer for benches/ensemble.rs: heavy tops with their own parameters and initial
states (read from stdin, one per line: "i_perp i_par mgl theta0 phidot0 psidot0"), integrated to
t = 114.3 in heyoka's batch mode (taylor_adaptive_batch, the parameters as heyoka `par`s), scalar
tolerance TOL, with PATH "hand" (the hand-written right-hand side, the default) or "lagrangian"
(the equations heyoka derives itself with heyoka.lagrangian).

heyoka's batch size is the number of tops per SIMD vector; its fastest on a machine is not always
its recommended one (4 for AVX2 doubles): this runs every size of BATCHES (or the one given as
BATCH) and reports the fastest, so the bench compares with heyoka's fastest configuration.

Prints one summary line (the fastest batch size's best-of-R wall time of the whole propagation,
compile time apart, and the time per top, then every size's time per top in parentheses) and the
final theta of every top from the fastest run (one per line), for the bench's error check.

Usage: python3 benches/peers/heyoka_batch.py TOL [REPEATS] [PATH] [BATCH] < tops.txt
Install: python3 -m pip install heyoka   (7.x)
"""
import sys
import time

import heyoka as hy
import numpy as np

T_END = 114.3
BATCHES = (1, 2, 4, 8, 16)


def system():
    th, ph, ps, th_d, ph_d, ps_d = hy.make_vars("th", "ph", "ps", "th_d", "ph_d", "ps_d")
    i_perp, i_par, mgl = hy.par[0], hy.par[1], hy.par[2]
    s, c = hy.sin(th), hy.cos(th)
    w3 = ps_d + ph_d * c
    th_dd = ph_d * ph_d * s * c - i_par / i_perp * w3 * ph_d * s + mgl / i_perp * s
    ph_dd = th_d * (i_par * w3 - 2.0 * i_perp * ph_d * c) / (i_perp * s)
    ps_dd = ph_d * th_d * s - ph_dd * c
    return [(th, th_d), (ph, ph_d), (ps, ps_d), (th_d, th_dd), (ph_d, ph_dd), (ps_d, ps_dd)]


def lagrangian_system():
    th, ph, ps, th_d, ph_d, ps_d = hy.make_vars("th", "ph", "ps", "th_d", "ph_d", "ps_d")
    i_perp, i_par, mgl = hy.par[0], hy.par[1], hy.par[2]
    s, c = hy.sin(th), hy.cos(th)
    w3 = ps_d + ph_d * c
    L = i_perp / 2.0 * (th_d * th_d + (ph_d * s) * (ph_d * s)) + i_par / 2.0 * w3 * w3 - mgl * c
    # The state in the order the pairs are given: the qs, then the q-dots (as system()).
    return hy.lagrangian(L, [th, ph, ps], [th_d, ph_d, ps_d])


def run(make, tops, tol, batch, repeats):
    """Best-of-`repeats` wall time of the propagation of `tops` in batches of `batch` (the last
    batch padded with copies of the last top), the compile time, and the final thetas."""
    n = len(tops)
    pad = (-n) % batch
    if pad:
        tops = np.vstack([tops, np.repeat(tops[-1:], pad, axis=0)])
    t0 = time.perf_counter()
    ta = hy.taylor_adaptive_batch(make(), np.zeros((6, batch)), tol=tol, pars=np.ones((3, batch)))
    compile_ms = (time.perf_counter() - t0) * 1e3
    best = float("inf")
    theta = np.zeros(len(tops))
    for _ in range(repeats):
        t0 = time.perf_counter()
        for b in range(0, len(tops), batch):
            blk = tops[b:b + batch]
            ta.set_time(np.zeros(batch))
            ta.state[:] = 0.0
            ta.state[0, :] = blk[:, 3]
            ta.state[4, :] = blk[:, 4]
            ta.state[5, :] = blk[:, 5]
            ta.pars[:] = blk[:, 0:3].T
            ta.propagate_until(T_END)
            theta[b:b + batch] = ta.state[0, :]
        best = min(best, time.perf_counter() - t0)
    return best, compile_ms, theta[:n]


def main():
    tol = float(sys.argv[1])
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    path = sys.argv[3] if len(sys.argv) > 3 else "hand"
    sizes = (int(sys.argv[4]),) if len(sys.argv) > 4 else BATCHES
    make = {"hand": system, "lagrangian": lagrangian_system}[path]
    tops = np.array([[float(x) for x in line.split()] for line in sys.stdin if line.strip()])
    n = len(tops)
    results = {b: run(make, tops, tol, b, repeats) for b in sizes}
    fastest = min(results, key=lambda b: results[b][0])
    best, compile_ms, theta = results[fastest]
    each = ", ".join(f"batch {b}: {results[b][0] / n * 1e3:.4f}" for b in sizes)
    print(f"heyoka batch-{fastest} {path} tol {tol:.0e}: {n} tops, best of {repeats} {best * 1e3:.1f} ms, "
          f"{best / n * 1e3:.4f} ms per top, compile {compile_ms:.0f} ms (fastest of {each} ms per top)",
          flush=True)
    for x in theta:
        print(repr(float(x)))


if __name__ == "__main__":
    main()
