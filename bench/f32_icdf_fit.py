import numpy as np, sys
from scipy.special import ndtri
D = int(sys.argv[1]) if len(sys.argv) > 1 else 7
def g(q):  # Phi^-1(1 - q/2), q in (0,1]
    return -ndtri(q / 2)
maxerr = 0
coefs = []
for e in range(-32, 0):  # octave [2^e, 2^(e+1)), variable t = m - 1.5, m in [1,2)
    n = 400
    x = np.cos(np.pi * (np.arange(n) + 0.5) / n) * 0.5  # chebyshev nodes in [-0.5,0.5]
    m = x + 1.5
    y = g(m * 2.0**e)
    c = np.polynomial.chebyshev.chebfit(x / 0.5, y, D)
    p = np.polynomial.chebyshev.cheb2poly(c)  # in s = t/0.5
    p = p * (2.0 ** np.arange(D + 1))  # in t
    pf = p.astype(np.float32).astype(np.float64)
    tt = np.linspace(-0.5, 0.5, 20001)
    yt = g((tt + 1.5) * 2.0**e)
    err = np.max(np.abs(np.polynomial.polynomial.polyval(tt, pf) - yt))
    maxerr = max(maxerr, err)
    coefs.append(pf)
    print(e, "%.3g" % err, file=sys.stderr)
print("max", maxerr, file=sys.stderr)
np.save("/tmp/f32/coefs%d.npy" % D, np.array(coefs))
