#!/usr/bin/env python3
"""The ceiling of per-particle (asynchronous) hybrid windows, measured on snapshots.

The hybrid (docs/hybrid.md) touches every free particle once per window: selection, the leap's
normals, the leap, the miss check. With per-particle windows a free particle would be touched only
when its own horizon runs out: the first time at which it could touch anybody. This script measures
those horizons on a run's extended-XYZ snapshots (output.trajectory = snapshots) and prints, per
frame, how many windows a free particle could leap at once (k) and the mean of 1/k over the free
particles: the fraction of today's per-free-particle work that per-particle windows would still do.
It also prints the fraction of particles in contact (overlapping someone), the most that exact
propagation of contacting clusters could take off the active set.

Horizon of a pair: the first t with  v_rel t + m sqrt(2) sigma_x(t) >= gap, where gap is the
surface distance, sigma_x(t) = sqrt(2 D t^3 / 3) / M is the free-flight position spread of one
component (docs/hybrid.md, "Why a leap is exact in law"), m the margin in sigmas, and v_rel the
approach speed in 1D (only an approaching neighbour can touch) or |v_i - v_j| in 2D (a pair passing
at an angle can touch too). A particle's horizon is the smallest over its pairs; k = floor(h / tau).
This is an oracle: the velocities are those of the frame, so the horizons ignore that a
neighbour's collision with a third particle changes its velocity (a real scheduler must then
re-check the neighbour's partners), and the bookkeeping of a per-particle schedule is free. The
real gain can only be smaller.

usage: hybrid_horizons.py SNAPSHOT_DIR WINDOW_S D_NS2 [MARGIN_SIGMAS] [FRAMES]   (or --self-test)
"""
import glob
import math
import sys

import ase.io
import numpy as np


def read_frame(path):
    """One extended-XYZ frame through ASE (granule's trajectories are checked readable by it):
    dimension (from pbc), box side, positions, velocities, radius and mass of the first particle."""
    a = ase.io.read(path)
    dim = int(a.pbc.sum())
    return dim, float(a.cell.lengths()[0]), a.positions[:, :dim], a.arrays["velo"][:, :dim], \
        float(a.arrays["radius"][0]), float(a.get_masses()[0])


def spread(t, D, M, margin):
    """m sqrt(2) sigma_x(t): the margin on the relative free-flight displacement of a pair."""
    return margin * math.sqrt(2.0) * np.sqrt(2.0 * D * t ** 3 / 3.0) / M


def pair_horizons(gap, vrel, D, M, margin, t_max):
    """Largest t <= t_max with vrel t + spread(t) < gap (bisection; the left side grows with t)."""
    lo = np.zeros_like(gap)
    hi = np.full_like(gap, t_max)
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        ok = vrel * mid + spread(mid, D, M, margin) < gap
        lo = np.where(ok, mid, lo)
        hi = np.where(ok, hi, mid)
    return np.where(gap <= 0.0, 0.0, lo)


def horizons_1d(box, x, v, r, D, M, margin, t_max):
    order = np.argsort(x[:, 0] % box)
    xs, vs = x[order, 0] % box, v[order, 0]
    gap = (np.roll(xs, -1) - xs) % box - 2.0 * r
    approach = np.maximum(0.0, vs - np.roll(vs, -1))  # right neighbour closing in
    h_pair = pair_horizons(gap, approach, D, M, margin, t_max)
    h = np.minimum(h_pair, np.roll(h_pair, 1))
    touching = (gap < 0.0) | np.roll(gap < 0.0, 1)
    out, contact = np.empty_like(h), np.empty_like(touching)
    out[order], contact[order] = h, touching
    return out, contact


def horizons_2d(box, x, v, r, D, M, margin, t_max):
    n = len(x)
    h = np.full(n, t_max)
    contact = np.zeros(n, dtype=bool)
    x = x % box
    for i0 in range(0, n, 256):  # rows in blocks: no neighbour library needed
        d = x[i0:i0 + 256, None, :] - x[None, :, :]
        d -= box * np.round(d / box)
        gap = np.hypot(d[..., 0], d[..., 1]) - 2.0 * r
        dv = v[i0:i0 + 256, None, :] - v[None, :, :]
        vrel = np.hypot(dv[..., 0], dv[..., 1])
        rows = np.arange(i0, min(i0 + 256, n))
        gap[rows - i0, rows] = np.inf  # no self pair
        near = gap < vrel * t_max + spread(t_max, D, M, margin)
        hb = np.full(gap.shape, t_max)
        hb[near] = pair_horizons(gap[near], vrel[near], D, M, margin, t_max)
        h[rows] = np.minimum(h[rows], hb.min(axis=1))
        contact[rows] = (gap < 0.0).any(axis=1)
    return h, contact


def self_test():
    """The horizon against closed forms: no noise (t = gap / v_rel) and no drift (spread(t) = gap)."""
    gap, M, margin = np.array([1e-4, 3e-3]), 3.53e-5, 6.0
    t = pair_horizons(gap, np.array([0.5, 0.2]), 0.0, M, margin, 1.0)
    assert np.allclose(t, gap / np.array([0.5, 0.2]), rtol=1e-9), t
    D = 1e-8
    t = pair_horizons(gap, np.zeros(2), D, M, margin, 1.0)
    exact = (gap * M / (margin * math.sqrt(2.0) * math.sqrt(2.0 * D / 3.0))) ** (2.0 / 3.0)
    assert np.allclose(t, exact, rtol=1e-9), (t, exact)
    # a ring of three (length 1 m): particle 1 closes in on 2 at 0.5 m/s over 1e-4 m
    x = np.array([[0.1], [0.2], [0.2 + 2 * 0.0015 + 1e-4]])
    v = np.array([[-1.0], [0.5], [0.0]])
    h, contact = horizons_1d(1.0, x, v, 0.0015, 0.0, M, margin, 1.0)
    assert abs(h[1] - 2e-4) < 1e-12 and abs(h[2] - 2e-4) < 1e-12, h
    # 0 recedes from 1 but meets 2 across the ring's seam: gap 1 - 0.2031 + 0.1 - 0.003, closing at 1 m/s
    assert abs(h[0] - (1.0 - (0.2 + 2 * 0.0015 + 1e-4) + 0.1 - 2 * 0.0015)) < 1e-12, h
    assert not contact.any()
    # 2D: the same pair seen in a plane, a touching pair,
    # and the same approach across the periodic boundary
    x2 = np.array([[0.1, 0.1], [0.1 + 2 * 0.0015 + 1e-4, 0.1], [0.5, 0.5], [0.5 + 0.0029, 0.5],
                   [0.999, 0.8], [0.999 + 2 * 0.0015 + 1e-4 - 1.0, 0.8]])
    v2 = np.array([[0.5, 0.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [0.5, 0.0], [0.0, 0.0]])
    h2, c2 = horizons_2d(1.0, x2, v2, 0.0015, 0.0, M, margin, 1.0)
    assert np.all(np.abs(h2[[0, 1, 4, 5]] - 2e-4) < 1e-12), h2
    assert h2[2] == 0.0 and h2[3] == 0.0 and list(c2) == [False, False, True, True, False, False], (h2, c2)
    print('hybrid_horizons.py: self-test passed (closed forms, 1D ring, 2D pairs)')
    return 0


def main(argv):
    if len(argv) == 2 and argv[1] == '--self-test':
        return self_test()
    if len(argv) < 4:
        sys.stderr.write(__doc__.split('usage: ')[1])
        return 2
    folder = argv[1]
    try:
        tau, D = float(argv[2]), float(argv[3])
        margin = float(argv[4]) if len(argv) > 4 else 6.0
        frames = int(argv[5]) if len(argv) > 5 else 3
    except ValueError as e:
        sys.stderr.write('hybrid_horizons.py: %s (usage: %s)\n' % (e, __doc__.split('usage: ')[1].strip()))
        return 2
    for name, value, ok, allowed in (('WINDOW_S', tau, tau > 0, '> 0'), ('D_NS2', D, D >= 0, '>= 0'),
                                     ('MARGIN_SIGMAS', margin, margin > 0, '> 0'), ('FRAMES', frames, frames >= 1, '>= 1')):
        if not (ok and math.isfinite(value)):
            sys.stderr.write('hybrid_horizons.py: %s = %s out of range (allowed: %s)\n' % (name, value, allowed))
            return 2
    paths = sorted(glob.glob(folder + '/snap_*.xyz'))
    if not paths:
        sys.stderr.write('%s: no snap_*.xyz frames (run with output.snapshot_every > 0)\n' % folder)
        return 2
    t_max = 1000 * tau
    q_all, c_all = [], []
    for path in paths[-frames:]:
        dim, box, x, v, r, M = read_frame(path)
        hfun = horizons_1d if dim == 1 else horizons_2d
        h, contact = hfun(box, x, v, r, D, M, margin, t_max)
        k = np.floor(h / tau)
        free = k >= 1
        q = float(np.mean(1.0 / k[free])) if free.any() else 1.0
        q_all.append(q)
        c_all.append(contact.mean())
        print('%s: %dD, N = %d, in contact %.3f, active now %.3f, windows per leap of a free particle: median %.0f, '
              'mean %.1f; mean 1/k over the free %.3f' % (path.split('/')[-1], dim, len(x), contact.mean(), 1.0 - free.mean(),
                                                np.median(k[free]) if free.any() else 0,
                                                k[free].mean() if free.any() else 0, q))
    print('per-free-particle work left with per-particle windows (oracle): %.3f of today\'s (mean of %d frames)' %
          (float(np.mean(q_all)), len(q_all)))
    print('particles in contact (overlapping someone): %.4f (mean of the frames; the rest of the active set is '
          'approaching, not touching)' % float(np.mean(c_all)))
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
