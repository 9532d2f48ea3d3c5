"""Scalar twins of the World's queries and of numpy's reductions, for the compiled episode.

Each function computes exactly what its reference computes, in the same order, so that the compiled and the
reference runs give the same numbers: np.sum's pairwise summation and np.linspace's spacing are spelled out.
The world travels as one tuple W = (clearance, blocked, obstacle table, affine, floats) built by
`world_tuple`; floats = (metres per pixel, obstacle range, has obstacles 0/1).
"""

from __future__ import annotations

import numpy as np

from socnavgen.sim.kernels import _clearance, no_alloc, obstacle_point, segment_clear

PW_BLOCK = 128  # numpy's pairwise-summation block


def world_tuple(world) -> tuple:  # noqa: ANN001
    """The World's arrays as the compiled functions take them."""
    table = world.obstacle_table if world.has_obstacles else np.zeros((1, 1), dtype=complex)
    floats = np.array([world.mpp, world.obstacle_range, 1.0 if world.has_obstacles else 0.0])
    return (np.ascontiguousarray(world.clearance, dtype=np.float64), np.ascontiguousarray(world.blocked),
            np.ascontiguousarray(table), np.ascontiguousarray(world.transform.inverse, dtype=np.float64), floats)


@no_alloc
def _block_sum(a, lo, n):  # noqa: ANN001, ANN202
    """numpy's pairwise_sum on a block of at most PW_BLOCK floats."""
    if n < 8:
        res = -0.0
        for i in range(n):
            res += a[lo + i]
        return res
    r0, r1, r2, r3 = a[lo], a[lo + 1], a[lo + 2], a[lo + 3]
    r4, r5, r6, r7 = a[lo + 4], a[lo + 5], a[lo + 6], a[lo + 7]
    i = 8
    while i < n - (n % 8):
        r0 += a[lo + i]
        r1 += a[lo + i + 1]
        r2 += a[lo + i + 2]
        r3 += a[lo + i + 3]
        r4 += a[lo + i + 4]
        r5 += a[lo + i + 5]
        r6 += a[lo + i + 6]
        r7 += a[lo + i + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[lo + i]
        i += 1
    return res


@no_alloc
def _block_sum_complex(re, im, lo, m):  # noqa: ANN001, ANN202
    """numpy's complex pairwise_sum on a block of at most PW_BLOCK / 2 terms (2m interleaved floats, the real
    and imaginary parts in alternate accumulators)."""
    if 2 * m < 8:
        rr, ri = -0.0, -0.0
        for i in range(m):
            rr += re[lo + i]
            ri += im[lo + i]
        return complex(rr, ri)
    r0, r2, r4, r6 = re[lo], re[lo + 1], re[lo + 2], re[lo + 3]
    r1, r3, r5, r7 = im[lo], im[lo + 1], im[lo + 2], im[lo + 3]
    i = 4
    while i < m - (m % 4):
        r0 += re[lo + i]
        r1 += im[lo + i]
        r2 += re[lo + i + 1]
        r3 += im[lo + i + 1]
        r4 += re[lo + i + 2]
        r5 += im[lo + i + 2]
        r6 += re[lo + i + 3]
        r7 += im[lo + i + 3]
        i += 4
    rr = (r0 + r2) + (r4 + r6)
    ri = (r1 + r3) + (r5 + r7)
    while i < m:
        rr += re[lo + i]
        ri += im[lo + i]
        i += 1
    return complex(rr, ri)


@no_alloc
def _pairwise(re, im, lo, n, as_complex, frames, left_re, left_im):  # noqa: ANN001, ANN202
    """numpy's pairwise summation of n terms from lo: floats re (as_complex False) or complex re + 1j * im.
    numpy sums blocks of PW_BLOCK floats and adds two halves split after a multiple of 8 floats, recursively;
    the recursion runs on the caller's frames (int64 (64, 3)) and left parts (float (64,) each): numba's cache
    cannot link a self-recursive function, and these helpers allocate nothing."""
    floats = 2 if as_complex else 1  # floats per term
    frames[0, 0], frames[0, 1], frames[0, 2], sp, value = lo, n, 0, 1, 0j
    while sp > 0:
        f = sp - 1
        size = frames[f, 1]
        half = floats * size // 2
        half = (half - half % 8) // floats  # terms in the first half
        if floats * size <= PW_BLOCK:
            start = frames[f, 0]
            value = _block_sum_complex(re, im, start, size) if as_complex else complex(_block_sum(re, start, size))
            sp -= 1
        elif frames[f, 2] == 0:
            frames[f, 2] = 1
            frames[sp, 0], frames[sp, 1], frames[sp, 2] = frames[f, 0], half, 0
            sp += 1
        elif frames[f, 2] == 1:
            left_re[f], frames[f, 2] = value.real, 2
            if as_complex:
                left_im[f] = value.imag
            frames[sp, 0], frames[sp, 1], frames[sp, 2] = frames[f, 0] + half, size - half, 0
            sp += 1
        else:
            value = complex(left_re[f] + value.real, (left_im[f] if as_complex else 0.0) + value.imag)
            sp -= 1
    return value


@no_alloc
def pairwise_sum(a, lo, n, frames, left):  # noqa: ANN001, ANN201
    """np.sum(a[lo:lo + n]) for float64, bit for bit (`left` holds the halves' sums; its second use below is
    never written in this mode)."""
    if n <= PW_BLOCK:
        return _block_sum(a, lo, n)
    return _pairwise(a, a, lo, n, False, frames, left, left).real


@no_alloc
def pairwise_sum_complex(re, im, m, frames, left_re, left_im):  # noqa: ANN001, ANN201
    """np.sum of the m complex numbers re[:m] + 1j * im[:m], bit for bit."""
    return _pairwise(re, im, 0, m, True, frames, left_re, left_im)


@no_alloc
def clearance_at(W, p):  # noqa: ANN001, ANN201
    """World.clearance_at_point."""
    return _clearance(W[0], W[3], p)


@no_alloc
def line_of_sight(W, a, b):  # noqa: ANN001, ANN201
    """World.line_of_sight for one segment."""
    if W[4][2] == 0.0:
        return True
    return segment_clear(W[1], W[3], a, b, 0.5 * W[4][0])


@no_alloc
def nearest_obstacle(W, p):  # noqa: ANN001, ANN201
    """World.nearest_obstacles for one point: (the obstacle point, whether it is within range)."""
    if W[4][2] == 0.0:
        return 0j, False
    o = obstacle_point(W[2], W[3], W[4][0], p)
    return o, abs(p - o) <= W[4][1]


@no_alloc
def free_along(W, start, direction, max_distance, radius):  # noqa: ANN001, ANN201
    """World.free_along: how far one can move from `start` along `direction` keeping `radius` clearance."""
    steps = max(2, int(max_distance / (0.5 * W[4][0])) + 1)
    step = max_distance / (steps - 1)
    prev = 0.0
    for k in range(steps):
        s = max_distance if k == steps - 1 else k * step
        if clearance_at(W, start + direction * s) < radius:
            return prev if k > 0 else 0.0
        prev = s
    return max_distance


@no_alloc
def path_clear(W, a, b, clearance):  # noqa: ANN001, ANN201
    """robot._segment_clear: points every <= 0.1 m from a to b all keep `clearance` from walls."""
    n = max(2, int(abs(b - a) / 0.1) + 1)
    step = 1.0 / (n - 1)
    d = b - a
    for k in range(n):
        f = 1.0 if k == n - 1 else k * step
        if clearance_at(W, a + d * f) < clearance:
            return False
    return True


@no_alloc
def np_div(z, c):  # noqa: ANN001, ANN201
    """z / c as numpy divides a complex by a real (array or numpy scalar): times the reciprocal, which can
    differ from Python's (and numba's) z / c in the last bit. The reference divides numpy values where its
    twin here calls this."""
    inv = 1.0 / c
    return complex(z.real * inv, z.imag * inv)


@no_alloc
def project(p, a, b):  # noqa: ANN001, ANN201
    """nodes._project for one point and one segment: (distance along a->b, distance to it)."""
    ab = b - a
    length = abs(ab)
    unit = np_div(ab, length) if length > 1e-9 else 0j
    along = min(max(((p - a) * unit.conjugate()).real, 0.0), length)
    closest = a + unit * along
    return along, abs(p - closest)
