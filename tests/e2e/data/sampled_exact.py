#!/usr/bin/env python3
"""The exact references of the sampled-data study tests (test_event_studies.cpp).

Between ticks the plants of SampledLoop.mo, MslSampledLoop.mo and
LatchedSlope.mop are linear with a constant held input, so their solution
is a closed form. This script writes the data files from it and prints the
references the tests hold: each Fisher matrix (central differences of the
closed form, σ = 0.01) and SampledTrack.mop's least-squares optimum.

Usage: python3 tests/e2e/data/sampled_exact.py [--write]   (--write: the .csv files)
"""
import math
import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent


def sampled_loop(a, b, kp, r, x0, ticks, times):
    """x' = -a x + b uh, uh := kp (r - x) at each tick; x at `times` (a sample on a tick: before it)."""
    out, t, x, uh, i = [], 0.0, x0, 0.0, 0
    advance = lambda x, uh, dt: x * math.exp(-a * dt) + b * uh / a * (1 - math.exp(-a * dt))
    for tm in times:
        while i < len(ticks) and ticks[i] <= tm:
            x, t = advance(x, uh, ticks[i] - t), ticks[i]
            uh, i = kp * (r - x), i + 1
        out.append(advance(x, uh, tm - t))
    return out


def latched_slope(a, c, times):
    """x' = a until x crosses c, then a - xs with xs = 0.5 c + 0.2 a."""
    ts, xs = c / a, 0.5 * c + 0.2 * a
    return [a * t if t <= ts else c + (a - xs) * (t - ts) for t in times]


def fisher(f, p, h, sigma=0.01):
    cols = []
    for i in range(len(p)):
        up, down = list(p), list(p)
        up[i] += h
        down[i] -= h
        cols.append([(u - d) / (2 * h) for u, d in zip(f(*up), f(*down))])
    return [[sum(u * v for u, v in zip(ci, cj)) / sigma**2 for cj in cols] for ci in cols]


CASES = {
    # file: (column, times, model as a function of the estimated parameters, their values, FD step)
    "sampled_loop.csv": ("x", [0.1 * k for k in range(1, 21)],
                         lambda a, b: sampled_loop(a, b, 0.8, 1.0, 0.0, [0.2 * k for k in range(11)],
                                                   [0.1 * k for k in range(1, 21)]), [1.5, 2.0], 1e-6),
    "msl_sampled_loop.csv": ("plant.y", [0.05 + 0.1 * k for k in range(20)],
                             lambda k, T: sampled_loop(1 / T, 1.5 / T, k, 1.0, 0.1,
                                                       [0.0] + [0.2 + 0.1 * m for m in range(20)],
                                                       [0.05 + 0.1 * m for m in range(20)]), [2.0, 0.4], 1e-6),
    "sampled_period.csv": ("x", [0.05 + 0.1 * k for k in range(20)],
                           lambda a, T: sampled_loop(a, 2.0, 0.8, 1.0, 0.0, [T * k for k in range(10)],
                                                     [0.05 + 0.1 * m for m in range(20)]), [1.5, 0.2], 1e-7),
    "latched_slope.csv": ("x", [0.1 * k for k in range(1, 21)],
                          lambda a, c: latched_slope(a, c, [0.1 * k for k in range(1, 21)]), [1.0, 0.55], 1e-7),
}


def track_optimum():
    """SampledTrack.mop: min over ten held values uh_k of ∫0^2 (x − 1)², exactly (a quadratic)."""
    a, b, T, n = 1.5, 2.0, 0.2, 10
    E, E2 = math.exp(-a * T), math.exp(-2 * a * T)

    def cost(u):
        x, J = 0.0, 0.0
        for uk in u:
            c = b * uk / a
            J += (c - 1) ** 2 * T + 2 * (c - 1) * (x - c) * (1 - E) / a + (x - c) ** 2 * (1 - E2) / (2 * a)
            x = c + (x - c) * E
        return J

    e = lambda i, s: [s if k == i else 0.0 for k in range(n)]
    g = [(cost(e(i, 1)) - cost(e(i, -1))) / 2 for i in range(n)]
    H = [[(cost([x + y for x, y in zip(e(i, 1), e(j, 1))]) - cost([x + y for x, y in zip(e(i, 1), e(j, -1))])
           - cost([x + y for x, y in zip(e(i, -1), e(j, 1))]) + cost([x + y for x, y in zip(e(i, -1), e(j, -1))])) / 4
          for j in range(n)] for i in range(n)]
    A = [H[i] + [-g[i]] for i in range(n)]
    for c in range(n):  # Gauss-Jordan on H u = -g
        p = max(range(c, n), key=lambda r: abs(A[r][c]))
        A[c], A[p] = A[p], A[c]
        for r in range(n):
            if r != c:
                A[r] = [x - A[r][c] / A[c][c] * y for x, y in zip(A[r], A[c])]
    u = [A[i][n] / A[i][i] for i in range(n)]
    return cost(u), u[0] / 0.8


if __name__ == "__main__":
    for name, (column, times, model, p, h) in CASES.items():
        if "--write" in sys.argv:
            with open(HERE / name, "w") as f:
                f.write(f"time,{column}\n")
                for t, y in zip(times, model(*p)):
                    f.write(f"{t:.10g},{y:.12g}\n")
        print(name, "Fisher", fisher(model, p, h))
    J, r0 = track_optimum()
    print("SampledTrack optimum", J, "r(0)", r0)
