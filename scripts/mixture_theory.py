#!/usr/bin/env python3
"""T_1/T_2 of a binary mixture of smooth inelastic discs (2D) or spheres (3D, --dim 3; 1D rods are
not covered) driven by
white noise of the same strength D on every grain, in the Maxwellian approximation of the Enskog
equation (docs/validation.md, "Driven binary mixture"; Barrat & Trizac, PRE 66, 051303 (2002);
Garzo & Dufty, PRE 60, 5706 (1999)).

Each species' energy balance, per unit area (T_i = m_i <v^2>_i / 2, k_B = 1):
  n_i 2 D / m_i = sum_j n_i n_j chi_ij sigma_ij 4 sqrt(pi/2) s_ij^3 m_ij (1 + a)
                  [ mu_ji (1 - a) / 2 + (T_i - T_j) / (M_ij s_ij^2) ],
with s_ij^2 = T_i/m_i + T_j/m_j, M_ij = m_i + m_j, mu_ji = m_j / M_ij, m_ij = m_i m_j / M_ij,
sigma_ij = r_i + r_j. In 3D (per unit volume, 3 D / m_i on the left) sigma_ij becomes 2 sigma_ij^2:
the prefactor 2^(3/2) pi^((d-1)/2) / Gamma(d/2) times sigma_ij^(d-1). The right-hand sides are
homogeneous of degree 3/2 in the temperatures, so the ratio T_1/T_2 follows from
m_1 rate_1 = m_2 rate_2 alone (D and the density drop out when chi_ij is the same for every pair,
e.g. equal radii; then the ratio is also the same in 2D and 3D).

usage: mixture_theory.py [--dim 3] m1 m2 r1 r2 x1 eps [chi11 chi12 chi22]   -> prints T_1/T_2
"""
import math
import sys


def rates(T1, T2, m, r, x, eps, chi, dim=2):
    """the collisional loss rates per grain of species 1 and 2 over n (the right-hand sides / n_i)."""
    T = (T1, T2)
    out = []
    for i in range(2):
        tot = 0.0
        for j in range(2):
            M = m[i] + m[j]
            mu_ji = m[j] / M
            mij = m[i] * m[j] / M
            s2 = T[i] / m[i] + T[j] / m[j]
            sig = r[i] + r[j] if dim == 2 else 2.0 * (r[i] + r[j]) * (r[i] + r[j])
            tot += (x[j] * chi[i][j] * sig * 4.0 * math.sqrt(math.pi / 2.0) * s2 ** 1.5 * mij *
                    (1.0 + eps) * (mu_ji * (1.0 - eps) / 2.0 + (T[i] - T[j]) / (M * s2)))
        out.append(tot)
    return out


def ratio(m, r, x, eps, chi=((1.0, 1.0), (1.0, 1.0)), dim=2):
    """T_1/T_2: with T_2 = 1 the balances need m_1 rate_1 = m_2 rate_2 (both = 2 D times the same
    scale factor); m_1 rate_1 - m_2 rate_2 rises with T_1, so bisection in log T_1 finds it."""
    if eps >= 1.0:
        return 1.0

    def g(lr):
        a, b = rates(math.exp(lr), 1.0, m, r, x, eps, chi, dim)
        return m[0] * a - m[1] * b

    lo, hi = -20.0, 20.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if g(mid) > 0.0:
            hi = mid
        else:
            lo = mid
    return math.exp(0.5 * (lo + hi))


if __name__ == "__main__":
    args = sys.argv[1:]
    dim = 2
    if args[:1] == ["--dim"]:
        dim = int(args[1])
        args = args[2:]
    a = [float(v) for v in args]
    if len(a) not in (6, 9) or dim not in (2, 3):
        sys.exit(__doc__)
    m1, m2, r1, r2, x1, eps = a[:6]
    chi = ((a[6], a[7]), (a[7], a[8])) if len(a) == 9 else ((1.0, 1.0), (1.0, 1.0))
    print("%.6f" % ratio((m1, m2), (r1, r2), (x1, 1.0 - x1), eps, chi, dim))
