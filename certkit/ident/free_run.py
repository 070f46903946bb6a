"""The two recursions of a NARX free run, compiled (numba): the input low-pass filter and the
output recursion y_t = f(y_{t−1}, …, y_{t−na}, ·).  Each step depends on the step before,
so neither vectorises over time; in Python their loops cost more than the rest of a
tuning search's free runs together (Cascaded Tanks: about 2 500 free runs of 128 steps
against 900 support vectors).

Strict IEEE evaluation (no fast-math flags: no fused multiply-add, no reordered sums), one
thread: the same bytes on any machine's thread count.  The filter is operation for
operation the Python recursion it replaced (the same bytes); the output recursion sums its
kernel terms in index order, where the numpy loop it replaced used BLAS dot products
(another order): the two agree to rounding (tests/test_narx_free_run.py pins them).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, error_model="numpy")
def low_pass(u: np.ndarray, pole: float, z0: np.ndarray, delay: int, cap: float
             ) -> np.ndarray:
    """z[t, k] = min(pole·z[t−1, k] + (1 − pole)·u[t − delay], cap) from z[0, k] =
    min(z0[k], cap), with u[t − delay] = u[0] before the record starts: one column per
    starting state z0[k], (n, len(z0))."""
    gain = 1.0 - pole
    z = np.empty((u.size, z0.size))
    for k in range(z0.size):
        z[0, k] = cap if cap < z0[k] else z0[k]
    for t in range(1, u.size):
        source = u[t - delay] if t >= delay else u[0]
        for k in range(z0.size):
            value = pole * z[t - 1, k] + gain * source
            z[t, k] = cap if cap < value else value
    return z


@njit(cache=True, error_model="numpy")
def narx_steps(y: np.ndarray, first: int, weights: np.ndarray, shift: np.ndarray,
               lin: np.ndarray, offset: np.ndarray, sigma2: float, beta_y: np.ndarray,
               theta: np.ndarray, monomials: np.ndarray, low: float, high: float) -> None:
    """y[first + r] for each row r of ``weights``, in place, from y's ``na`` samples before:

    y_t = Σ_j w[r, j]·exp(min(lin_j·h + offset_j − h·h/σ², 0)) + shift[r] + β_y·h
          (+ θ·(products of h over the rows of ``monomials``)), clipped to [low, high],

    h = y[t−na:t] (oldest first), na = lin.shape[1]: the output-lag factor of the RBF kernel
    exp(−‖h − c‖²/σ²) expanded, times the input part w precomputed for the block."""
    na = lin.shape[1]
    h = np.empty(na)
    for r in range(weights.shape[0]):
        t = first + r
        square = 0.0
        for i in range(na):
            h[i] = y[t - na + i]
            square += h[i] * h[i]
        square = square / sigma2
        value = 0.0
        lost = 0.0                 # the kernel sum, compensated (Knuth's two-sum, no branch)
        for j in range(lin.shape[0]):
            z = 0.0
            for i in range(na):
                z += lin[j, i] * h[i]
            z = z + offset[j] - square
            if z > 0.0:                      # NaN stays NaN (a diverged run stays one)
                z = 0.0
            term = weights[r, j] * math.exp(z)
            total = value + term
            part = total - value
            lost += (value - (total - part)) + (term - part)
            value = total
        value += lost
        value += shift[r]
        linear = 0.0
        for i in range(na):
            linear += beta_y[i] * h[i]
        value += linear
        if theta.size:
            cubic = 0.0
            for k in range(theta.size):
                cubic += theta[k] * (h[monomials[k, 0]] * h[monomials[k, 1]]
                                     * h[monomials[k, 2]])
            value += cubic
        if value < low:
            value = low
        elif value > high:
            value = high
        y[t] = value
