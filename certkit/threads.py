"""One BLAS thread for the model stages, so that their numbers do not depend on the
machine's core count.

A multi-threaded BLAS splits a matrix product or a factorisation by the number of its
threads, which changes the order of the floating-point sums and so the last bits of the
result; a least-squares fit that starts from those bits can end elsewhere (on a bound, in
another local minimum).  With one BLAS thread the same inputs give the same numbers at any
``OMP_NUM_THREADS`` / ``OPENBLAS_NUM_THREADS``.  (numba's threads need no such limit: the
compiled simulation gives each drop to one thread whole.)
"""

from __future__ import annotations

import functools

from threadpoolctl import threadpool_limits


def one_blas_thread(function):
    """``function`` run with BLAS (and OpenMP) limited to one thread."""

    @functools.wraps(function)
    def limited(*args, **kwargs):
        with threadpool_limits(limits=1):
            return function(*args, **kwargs)

    return limited
