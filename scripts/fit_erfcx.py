"""Generates the ERFCX_POLY table of crates/woven/src/math/special.rs.

erfcx(x) = exp(x^2) erfc(x) on [0, 6) in 12 pieces of width 1/2: on each, the Chebyshev
interpolant at 40 nodes (50-digit arithmetic, mpmath), truncated to degree 15 and converted to
powers of u = x - centre. Prints the Rust table to stdout and, to stderr, the worst relative
error of the f64 Estrin evaluation the library uses, over a grid of step 1e-4.

    python3 scripts/fit_erfcx.py > table.rs     (needs mpmath)
"""
import sys

import mpmath as mp

mp.mp.dps = 50
WIDTH = mp.mpf(1) / 2
PIECES = 12
TERMS = 16
NODES = 40


def erfcx(x):
    return mp.exp(x * x) * mp.erfc(x)


def piece(i):
    a = i * WIDTH
    centre, h = a + WIDTH / 2, WIDTH / 2
    xs = [mp.cos(mp.pi * (k + mp.mpf(1) / 2) / NODES) for k in range(NODES)]
    fx = [erfcx(centre + h * x) for x in xs]
    c = [2 * sum(fx[k] * mp.cos(mp.pi * j * (k + mp.mpf(1) / 2) / NODES) for k in range(NODES)) / NODES
         for j in range(TERMS)]
    c[0] /= 2
    # Chebyshev polynomials T_k as power series in t, then t = u / h.
    T = [[mp.mpf(1)], [mp.mpf(0), mp.mpf(1)]]
    for k in range(2, TERMS):
        p = [mp.mpf(0)] * (k + 1)
        for j, v in enumerate(T[k - 1]):
            p[j + 1] += 2 * v
        for j, v in enumerate(T[k - 2]):
            p[j] -= v
        T.append(p)
    m = [mp.mpf(0)] * TERMS
    for k in range(TERMS):
        for j, v in enumerate(T[k]):
            m[j] += c[k] * v
    return float(centre), [float(m[j] / h ** j) for j in range(TERMS)]


def estrin(c, u):
    u2 = u * u
    u4 = u2 * u2
    u8 = u4 * u4
    p = [c[2 * k] + c[2 * k + 1] * u for k in range(8)]
    q = [p[2 * k] + p[2 * k + 1] * u2 for k in range(4)]
    return (q[0] + q[1] * u4) + (q[2] + q[3] * u4) * u8


rows = [piece(i) for i in range(PIECES)]
worst = 0.0
for k in range(60000):
    x = k * 1e-4
    centre, c = rows[int(2 * x)]
    want = erfcx(mp.mpf(x))
    worst = max(worst, float(abs((estrin(c, x - centre) - want) / want)))
print("worst relative error", worst, file=sys.stderr)
print("const ERFCX_POLY: [(f64, [f64; 16]); 12] = [")
for centre, c in rows:
    print("    (%r, [" % centre)
    for x in c:
        print("        %r," % x)
    print("    ]),")
print("];")
