#!/usr/bin/env python3
"""The coefficients of the single-precision noise path's inverse CDF (src/core/noise.c,
"Single-precision normals"): prints the C table f32_icdf_c and, on stderr, each octave's largest
error of the fit (coefficients rounded to float, evaluated in double).

    /usr/bin/python3 bench/f32_icdf_fit.py [DEGREE]     (default 7; needs numpy and scipy)

|z| = g(q) = Phi^-1(1 - q/2) for q in (0, 1). On the octave q = m 2^e, m in [1, 2), e = -32 .. -1,
g is fitted by a polynomial of degree DEGREE in t = m - 3/2: Chebyshev least squares on 400
Chebyshev nodes against scipy.special.ndtri, converted to the monomial basis, rounded to float.
Column e & 31 of the table holds octave e. The float evaluation in noise.c (Horner with fmaf)
adds rounding: over all 2^31 words the largest |z - exact| is 4.9e-7 (tests/test_noise.c,
test_f32_transform, checks samples).
"""
import sys

import numpy as np
from scipy.special import ndtri

DEG = int(sys.argv[1]) if len(sys.argv) > 1 else 7


def g(q):
    return -ndtri(q / 2)


def fit(e):
    n = 400
    s = np.cos(np.pi * (np.arange(n) + 0.5) / n)  # Chebyshev nodes on [-1, 1], s = t / 0.5
    y = g((1.5 + 0.5 * s) * 2.0**e)
    p = np.polynomial.chebyshev.cheb2poly(np.polynomial.chebyshev.chebfit(s, y, DEG))
    p = p * 2.0 ** np.arange(DEG + 1)  # in powers of t
    pf = p.astype(np.float32).astype(np.float64)
    tt = np.linspace(-0.5, 0.5, 20001)
    err = np.max(np.abs(np.polynomial.polynomial.polyval(tt, pf) - g((tt + 1.5) * 2.0**e)))
    print(f"octave 2^{e}: largest error {err:.3g}", file=sys.stderr)
    return pf


def hexf(x):
    h = float(np.float32(x)).hex()  # e.g. 0x1.919c6e0000000p+2
    mant, exp = h.split("p")
    mant = mant.rstrip("0").rstrip(".")
    return f"{mant}p{exp}f"


coef = [fit(e) for e in range(-32, 0)]  # column e & 31: e = -32 .. -1 -> 0 .. 31
print("static _Alignas(64) const float f32_icdf_c[F32_DEG + 1][32] = {")
for j in range(DEG + 1):
    print(f"    {{ /* t^{j} */")
    vals = [hexf(coef[i][j]) for i in range(32)]
    for k in range(0, 32, 4):
        print("        " + ", ".join(vals[k:k + 4]) + ",")
    print("    },")
print("};")
