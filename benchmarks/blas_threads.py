"""BLAS thread pinning shared by the benchmarks, so that their timings do not depend on how
many threads OpenBLAS, MKL or OpenMP would start on a machine under another load.

These libraries size their thread pools from the environment when they are loaded, so the
variables must be set before numpy (or scipy, or certkit) is first imported: importing this
module sets them (and says so), and every benchmark imports it first.  Child processes
(``certkit`` commands a benchmark times) inherit the variables.  certkit's numba kernels have their own pool
(NUMBA_NUM_THREADS) and are not affected.
"""

from __future__ import annotations

import os
import sys

THREADS = 1
VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def pin(threads: int = THREADS) -> None:
    """Set every BLAS/OpenMP thread-count variable to ``threads``, and say so."""
    if "numpy" in sys.modules:
        raise RuntimeError("BLAS threads must be pinned before numpy is imported")
    before = {name: os.environ.get(name) for name in VARIABLES}
    for name in VARIABLES:
        os.environ[name] = str(threads)
    replaced = [f"{name} was {value}" for name, value in before.items()
                if value is not None and value != str(threads)]
    print(f"BLAS threads pinned: {', '.join(f'{name}={threads}' for name in VARIABLES)}"
          + (f" ({'; '.join(replaced)})" if replaced else ""), flush=True)


def loaded_pools() -> str:
    """The thread pools loaded in this process and their sizes (threadpoolctl), to show
    the pin took effect."""
    from threadpoolctl import threadpool_info

    return ", ".join(f"{pool['internal_api']} {pool['num_threads']} thread(s)"
                     for pool in threadpool_info()) or "none loaded"


pin()
