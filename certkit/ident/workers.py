"""The worker processes of a tuning search (:func:`certkit.ident.tune_free_run`'s
``n_jobs``): :class:`~certkit.ident.tuning.FreeRunCV` sends fold k of every candidate to
worker k mod n, which keeps what that fold's fits share (:mod:`certkit.ident.reuse`)."""

from __future__ import annotations

import multiprocessing
from collections.abc import Iterator
from concurrent.futures import Future, ProcessPoolExecutor
from contextlib import contextmanager
from dataclasses import replace

from certkit.ident.lssvm import recorded_warnings
from certkit.ident.reuse import keep_in_this_process

#: The worker processes of the search in progress, or None.
_workers: list[ProcessPoolExecutor] | None = None


def running_workers() -> list[ProcessPoolExecutor] | None:
    """The worker processes of the search in progress (None outside one, or with one)."""
    return _workers


@contextmanager
def fold_workers(n_jobs: int) -> Iterator[None]:
    """``n_jobs`` worker processes that score the folds of every candidate of a search
    (none for 1; a search inside a search uses the outer one's); each keeps its folds'
    reusable parts until the search ends.  Forked where the system can (a script needs no
    ``if __name__ == "__main__"`` guard), else started afresh ("spawn", which re-imports
    the calling script: it needs the guard)."""
    global _workers
    if n_jobs == 1 or _workers is not None:
        yield
        return
    methods = multiprocessing.get_all_start_methods()
    context = multiprocessing.get_context("fork" if "fork" in methods else "spawn")
    _workers = [ProcessPoolExecutor(1, mp_context=context, initializer=_start_worker)
                for _ in range(n_jobs)]
    try:
        yield
    finally:
        pools, _workers = _workers, None
        for pool in pools:
            pool.shutdown(cancel_futures=True)


def _start_worker() -> None:
    """A worker keeps its folds' reusable parts for its whole life, and has no workers of
    its own: a forked one inherits this module's list of the search's pools, which are not
    its to use (a search inside its fits scores its folds in the worker itself)."""
    global _workers
    _workers = None
    keep_in_this_process()


def submitted(cv, estimator, pairs, splits) -> list[Future]:
    """The folds ``splits`` ((fold, (train, held)) pairs) of ``estimator`` submitted to the
    workers, fold k to worker k mod n (it keeps that fold's reusable parts): one task per
    worker, its folds in order (:func:`scored_folds`)."""
    n = len(_workers)
    return [_workers[k].submit(scored_folds, cv, estimator, pairs, splits[k::n])
            for k in range(min(n, len(splits)))]


def collected(futures: list[Future]) -> list:
    """The outcomes of :func:`submitted` folds in fold order, cut at the first rejected one
    (each worker stopped at its own first, after it)."""
    outcomes = sorted((o for future in futures for o in future.result()),
                      key=lambda o: o.fold)
    cut = next((i + 1 for i, o in enumerate(outcomes) if o.rejected), len(outcomes))
    return outcomes[:cut]


def scored_folds(cv, estimator, pairs, splits) -> list:
    """``cv``'s outcomes of the folds ``splits`` in order, up to the first rejected one (one
    suffices to reject): in this process or a worker's."""
    out = []
    for fold, (train, held) in splits:
        out.append(scored_fold(cv, fold, estimator, pairs, train, held))
        if out[-1].rejected:
            break
    return out


def scored_fold(cv, fold: int, estimator, pairs, train, held):
    """``cv``'s outcome of one fold (a :class:`~certkit.ident.tuning.FoldOutcome`), with
    the numerical warnings it raised recorded in it, not shown: in this process or a
    worker's."""
    with recorded_warnings() as messages:
        outcome = cv._fold(fold, estimator, pairs, train, held)
    return replace(outcome, warnings=tuple(messages))
