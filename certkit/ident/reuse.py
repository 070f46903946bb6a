"""What a tuning search computes once and uses for many candidates.

A grid over (γ, σ²) fits the same training rows many times: the fixed-size LS-SVM's
prototypes do not depend on (γ, σ²) at all, and its normal equations ΦᵀΦ, Φᵀy, like the
dual LS-SVM's squared distances between training rows and the kernel between the rows a
fold's models predict and their centres, depend on σ² (or on neither) but not on γ.
Inside :func:`reusing` (entered by :func:`certkit.ident.lssvm.tune`) the fits keep those
parts under a digest of everything they depend on — the rows' bytes, the parameters — and
take them back when the same rows come again with another γ.  Outside it nothing is kept:
a single fit computes everything as before.

The parts kept are exact: a fit that takes one back computes from the same numbers as
one that made it.  They are held in memory until the outermost :func:`reusing` ends, at
most :data:`BUDGET` bytes (the oldest dropped first).
"""

from __future__ import annotations

import hashlib
from collections import OrderedDict
from collections.abc import Callable, Iterator
from contextlib import contextmanager

import numpy as np

#: Bytes of kept parts at most (the oldest are dropped first).
BUDGET = 512 * 2 ** 20

_kept: OrderedDict[str, object] | None = None


@contextmanager
def reusing() -> Iterator[None]:
    """Keep the fits' reusable parts until the outermost ``with reusing()`` ends."""
    global _kept
    outermost = _kept is None
    if outermost:
        _kept = OrderedDict()
    try:
        yield
    finally:
        if outermost:
            _kept = None


def keep_in_this_process() -> None:
    """Keep the fits' reusable parts for as long as this process lives: a worker process
    of one search (:func:`certkit.ident.tune_free_run` with ``n_jobs``), which fits the
    same fold for every candidate."""
    global _kept
    if _kept is None:
        _kept = OrderedDict()


def digest(*parts) -> str:
    """A digest of arrays (their shape, type and bytes) and other values (their repr)."""
    h = hashlib.blake2b(digest_size=20)
    for part in parts:
        if isinstance(part, np.ndarray):
            array = np.ascontiguousarray(part)
            h.update(f"{array.shape}{array.dtype}".encode())
            h.update(array.view(np.uint8).reshape(-1))
        else:
            h.update(repr(part).encode())
        h.update(b"|")
    return h.hexdigest()


def _size(value) -> int:
    if isinstance(value, np.ndarray):
        return value.nbytes
    if isinstance(value, tuple):
        return sum(_size(v) for v in value)
    return 64


def kept(kind: str, key: str, compute: Callable[[], object]):
    """``compute()``, or what it gave before under (``kind``, ``key``) inside
    :func:`reusing`.  What is kept must not be modified by the caller."""
    if _kept is None:
        return compute()
    name = f"{kind}:{key}"
    if name in _kept:
        _kept.move_to_end(name)
        return _kept[name]
    value = compute()
    _kept[name] = value
    while len(_kept) > 1 and sum(_size(v) for v in _kept.values()) > BUDGET:
        _kept.popitem(last=False)
    return value
