"""How large a problem each engine takes: the memory of the full (dense-kernel) engine, the
budget it may use, and the choice ``engine="auto"`` makes.

The full engines (:class:`~certkit.ident.lssvm.LSSVMRegressor`, and ``engine="full"`` of
NARX, Hammerstein and Wiener models) hold the kernel matrix of all N training rows, and
while it is evaluated (:func:`~certkit.ident.lssvm.rbf_kernel`: the cross products, the
squared distances, their exponential) three N × N arrays of doubles at once: 24·N² bytes,
:func:`dense_bytes` (measured with ``tracemalloc``: a peak of 3.00 × 8N² bytes for
``LSSVMRegressor`` and NARX, 3.1 × 8N² for the Hammerstein dual over N samples).  At
N = 40 960 that is 37.5 GiB.  The fixed-size engines hold M prototypes and blocks of
rows, O(N·d + M²) (Suykens et al. 2002, §6.5): any N.

Two rules, each with its reason:

* :data:`MEMORY_BUDGET`, the **guard**: a full engine whose :func:`dense_bytes` exceed it
  refuses to start (:class:`certkit.errors.DataInputError` naming the size, the memory and
  the option that fits) instead of raising a bare ``MemoryError`` or paging the machine
  for hours.  Half the machine's physical memory (2 GiB when the system does not say): the
  guard only decides whether a fit runs, never which numbers come out, so it may follow the
  machine, and half leaves room for the data, the rest of the process and other programs.
  Raise it (``certkit.ident.sizing.MEMORY_BUDGET = 48 * 2**30``) to use more.
* :data:`AUTO_FULL_SAMPLES`, the **choice** of ``engine="auto"``: the exact dual up to
  5 000 training samples, the fixed-size engine above.  A fixed count, not the budget:
  the choice changes the model, so it must not depend on the machine (the same data give
  the same model everywhere, as one BLAS thread makes the numbers independent of the core
  count).  Why 5 000: the dual's O(N³) Cholesky factorisation takes about 2 s at N = 5 000
  on one core (3.7 s measured at 6 000) and 0.6 GB, and a tuning search repeats it for
  every candidate and fold; beyond that Suykens et al. (2002, §6.5) turn to the fixed-size
  LS-SVM.

References
----------
J.A.K. Suykens, T. Van Gestel, J. De Brabanter, B. De Moor, J. Vandewalle, *Least Squares
Support Vector Machines*, World Scientific, 2002, §6.5 (fixed-size LS-SVM for large data).
"""

from __future__ import annotations

import os

from certkit.errors import DataInputError

ENGINES = ("full", "fixed-size", "auto")
#: N × N arrays of doubles alive at once while a dense kernel matrix is evaluated.
DENSE_ARRAYS = 3
#: Training samples up to which ``engine="auto"`` takes the exact dual.
AUTO_FULL_SAMPLES = 5_000


def _physical_memory() -> int | None:
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):      # not a POSIX system
        return None


#: Bytes a full engine may use [B]: half the machine's physical memory, or 2 GiB when the
#: system does not say.  Read at each fit, so it can be raised.
MEMORY_BUDGET = (_physical_memory() or 4 * 2**30) // 2


def dense_bytes(n: int) -> int:
    """Peak memory of a full engine on ``n`` rows [B]: :data:`DENSE_ARRAYS` × 8·n²."""
    return DENSE_ARRAYS * 8 * int(n) ** 2


def size_text(size: float) -> str:
    """Bytes as a person reads them: ``37.5 GiB``, ``220 MiB``."""
    for unit, scale in (("GiB", 2**30), ("MiB", 2**20), ("KiB", 2**10)):
        if size >= scale:
            return f"{size / scale:.3g} {unit}" if size < 100 * scale else \
                f"{size / scale:.0f} {unit}"
    return f"{size:.0f} B"


def check_dense_memory(who: str, n: int, advice: str) -> None:
    """Refuse a full engine on ``n`` rows whose :func:`dense_bytes` exceed the budget.

    Parameters
    ----------
    who : str
        The estimator, as the message names it.
    n : int
        Rows of its kernel matrix.
    advice : str
        The option that fits, e.g. ``"engine='fixed-size' with prototypes=300"``.

    Raises
    ------
    certkit.errors.DataInputError
        Naming ``n``, the memory needed, the budget and ``advice``.
    """
    need = dense_bytes(n)
    if need > MEMORY_BUDGET:
        raise DataInputError("engine", f"{who}: the full engine on {n:,} rows would need about "
                                       f"{size_text(need)} (its kernel matrix: {DENSE_ARRAYS} "
                                       f"arrays of {n:,} × {n:,} doubles), more than the "
                                       f"budget of {size_text(MEMORY_BUDGET)} (half this "
                                       f"machine's memory, certkit.ident.sizing.MEMORY_BUDGET)"
                                       f": use {advice}")


def choose_engine(who: str, engine: str, n_samples: int, n_rows: int, prototypes,
                  fixed_size_only: str | None = None) -> tuple[str, str]:
    """The engine an estimator uses, and why, in words; a full engine is checked against
    the budget (:func:`check_dense_memory`).

    Parameters
    ----------
    who : str
        The estimator, as messages name it.
    engine : {"full", "fixed-size", "auto"}
        The estimator's ``engine`` parameter.
    n_samples : int
        Training samples (all experiments): what ``"auto"`` decides by.
    n_rows : int
        Rows of the full engine's kernel matrix: what its memory grows with.
    prototypes : int
        The estimator's ``prototypes``, named in the advice and the reason.
    fixed_size_only : str, optional
        Why only the fixed-size engine fits the estimator's other options (``"auto"`` then
        takes it).

    Returns
    -------
    (str, str)
        ``"full"`` or ``"fixed-size"``, and the reason (the fitted ``engine_reason_``).
    """
    if engine not in ENGINES:
        raise DataInputError("engine", f"expected one of {', '.join(map(repr, ENGINES))}, "
                                       f"found {engine!r}")
    if engine != "auto":
        chosen, reason = engine, f"engine={engine!r} as given"
    elif fixed_size_only:
        chosen, reason = "fixed-size", f"engine='auto': fixed-size, as {fixed_size_only}"
    elif n_samples <= AUTO_FULL_SAMPLES:
        chosen, reason = "full", (f"engine='auto': full (the exact dual, about "
                                  f"{size_text(dense_bytes(n_rows))}), as {n_samples:,} "
                                  f"training samples are at most AUTO_FULL_SAMPLES = "
                                  f"{AUTO_FULL_SAMPLES:,}")
    else:
        chosen, reason = "fixed-size", (f"engine='auto': fixed-size with {prototypes} "
                                        f"prototypes, as {n_samples:,} training samples are "
                                        f"more than AUTO_FULL_SAMPLES = {AUTO_FULL_SAMPLES:,} "
                                        f"(the exact dual would need about "
                                        f"{size_text(dense_bytes(n_rows))})")
    if chosen == "full":
        check_dense_memory(who, n_rows, f"engine='fixed-size' with prototypes={prototypes} "
                                        f"(memory O(N·M), any N; more prototypes come closer "
                                        f"to the exact dual), or engine='auto'")
    return chosen, reason


def engine_for_folds(engine: str, n_samples: int) -> str:
    """The engine a tuning search's folds use for an estimator whose ``engine`` is given and
    whose data hold ``n_samples``: ``"auto"`` becomes ``"fixed-size"`` when it takes that
    engine on all the data (a fold, smaller, could otherwise take the dual and the search
    would tune another model than the one refitted); anything else is kept (with at most
    :data:`AUTO_FULL_SAMPLES` samples a fold decides as the whole record does)."""
    return "fixed-size" if engine == "auto" and n_samples > AUTO_FULL_SAMPLES else engine
