"""Tuning any identified model on its free run: (γ, σ²) and lag orders by cross-validation on
the estimation data only, with the whole cost surface kept for plotting.

* :class:`FreeRunCV` — the cost: fit on some pieces of the data, simulate the held-out
  pieces in free run (or predict them one step ahead), normalised mean squared error.  Its
  fields (folds, initialisation window, free run or one step, divergence band) are the
  knobs to change.
* :func:`tune_free_run` — a log grid (and a Nelder–Mead refinement) of (γ, σ²) by
  :func:`certkit.ident.lssvm.tune`, for every setting of the orders (or other structure
  parameters) asked for: a grid, a grid with tied orders or a list; optionally a smoothness prior on the surface; returns the refitted
  model — or an :class:`~certkit.ident.ensemble.EnsembleModel` of the K best — and
  :class:`CostSurface`.

A model is validated by its simulation, not its one-step prediction (Ljung 1999, §16.6), so
the free run is the default cost; LS-SVMlab tunes (γ, σ²) the same way, a global search
then a simplex on a cross-validation cost (Suykens et al. 2002, §3.6 and §4.4).

Robust tuning on a short record (the procedure that meets the Cascaded Tanks target, 1 024
samples; README, "Identification on your own data"):

1. **Blocked folds** (``FreeRunCV(folds=8)``, the default): one record is cut into 8
   contiguous blocks; fold k trains on the other 7 (separate experiments: no lag window
   spans a gap) and simulates block k in free run from its first measured outputs.
   Blocked, not shuffled, folds keep the serial dependence inside each block; Bergmeir &
   Benítez (2012) found blocked cross-validation a sound way to evaluate time-series
   predictors, using all the data, where a single last-block hold-out wastes most of it.  Why 8: on
   Cascaded Tanks, 4 folds of 256 samples gave a cost too noisy inside the good region
   (rank correlation with the validation error 0.50 over 320 candidates; a single
   choice at 0.348 V), 8 folds of 128 a cost that ranks them (0.81; the choice at the
   grid's best, 0.300 V against 0.298 V): training sets closer to the final one (7/8 of
   the record) and twice as many held-out starting states, at twice the tuning time.
   Keep blocks of roughly 100-150 samples or more than 10 times the initialisation window.
2. **Unstable anywhere is rejected** (``FreeRunCV(divergence=1.0)``, the default): a
   candidate whose free run is not finite or leaves the band [min, max] ± 1 range of the
   fold's training outputs on ANY fold costs +inf — a simulation model must run on every
   stretch of the data, and one diverging fold would otherwise be averaged away.
3. **Ranking**: the raw cost, a Gaussian smoothness prior (``smoothing=width``) or the
   3 x 3 running median of the grid (``smoothing="median"``, Tukey 1977), so that an
   isolated minimum between bad neighbours loses to a good region.
4. **Ensemble of the K best** (``ensemble=K``): the K best candidates refitted on the whole
   record, their free runs averaged (:class:`~certkit.ident.ensemble.EnsembleModel`).

References
----------
C. Bergmeir, J.M. Benítez, "On the use of cross-validation for time series predictor
evaluation", Information Sciences 191 (2012) 192-213.
L. Ljung, *System Identification: Theory for the User*, 2nd ed., Prentice Hall, 1999.
J.A.K. Suykens, T. Van Gestel, J. De Brabanter, B. De Moor, J. Vandewalle, *Least Squares
Support Vector Machines*, World Scientific, 2002.
J.W. Tukey, *Exploratory Data Analysis*, Addison-Wesley, 1977 (running medians).
L. Breiman, J.H. Friedman, R.A. Olshen, C.J. Stone, *Classification and Regression Trees*,
Wadsworth, 1984 (the one-standard-error rule).
T. Hastie, R. Tibshirani, J. Friedman, *The Elements of Statistical Learning*, 2nd ed.,
Springer, 2009.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial

import numpy as np
from sklearn.base import clone

from certkit.ident.ensemble import EnsembleModel
from certkit.ident.experiments import DataInputError, experiments, free_run_folds
from certkit.ident.hammerstein import HammersteinLSSVM
from certkit.ident.lssvm import recorded_warnings, tune
from certkit.ident.workers import (collected, fold_workers, running_workers, scored_folds,
                                   submitted)
from certkit.ident.narx import NARX
from certkit.ident.search_space import (SearchEdge, order_edges, order_settings, range_edges,
                                        warn_of_edges)
from certkit.ident.sizing import engine_for_folds
from certkit.ident.wiener import WienerLSSVM

MODES = ("free-run", "one-step")
RULES = ("min", "one-se")


def output_variance(pairs) -> float:
    """var(y) over all experiments, the normaliser of the NRMSE² costs (1 for a constant
    output)."""
    return float(np.var(np.concatenate([y for _, y in pairs]))) or 1.0


#: What a fold of :class:`FreeRunCV` gave a candidate (:attr:`FoldOutcome.status`): scored;
#: its estimate not finite or outside the band (diverged); the same from a model whose
#: fitted linear part has a pole on or outside the unit circle (unstable); its fit raised.
SCORED, DIVERGED, UNSTABLE, FAILED = "scored", "diverged", "unstable", "failed fit"


@dataclass(frozen=True)
class FoldOutcome:
    """What one fold of :class:`FreeRunCV` gave a candidate, and why when it is rejected.

    ``fold`` (0-based), ``status`` (:data:`SCORED`, :data:`DIVERGED`, :data:`UNSTABLE` or
    :data:`FAILED`), ``squared`` and ``count`` (the sum of squared errors and the samples
    scored; +inf and 0 when rejected), ``reason`` (in words: where the estimate left the
    band, or the fit's exception and message; empty when scored) and ``warnings`` (each
    warning the fold's fit and simulation raised, as "Category: message", once each:
    recorded here, not shown).
    """

    fold: int
    status: str
    squared: float
    count: int
    reason: str = ""
    warnings: tuple[str, ...] = ()

    @property
    def rejected(self) -> bool:
        return self.status != SCORED


@dataclass(frozen=True)
class FreeRunCV:
    """Cross-validated simulation error of a model, the cost :func:`tune_free_run` minimises.

    Parameters
    ----------
    folds : int, default 8
        Folds (:func:`certkit.ident.experiments.free_run_folds`): whole experiments held
        out when there are at least ``folds`` of them, else contiguous blocks of each
        (blocked cross-validation; 8 is what made the cost rank candidates on a record of
        1 024 samples, see the module's notes).
    n_init : int, optional
        Measured outputs that start each held-out simulation (not scored); default the
        fitted model's ``init_length``.  It must be at least every candidate's
        ``init_length`` = max(na, delay + nb − 1) (the lag window a free run starts from):
        a 10-sample start rules out na = 15 (DataInputError).  To search orders above
        ``n_init``, raise it to the largest window searched; one window for every
        candidate keeps their costs comparable (each scores the same samples).
    mode : {"free-run", "one-step"}, default "free-run"
        Score the free-run simulation or the one-step-ahead prediction.
    divergence : float or None, default 1.0
        Reject (+inf) a candidate whose estimate on any held-out piece leaves
        [min, max] ± ``divergence`` · (max − min) of that fold's training outputs.  None:
        reject only non-finite estimates.

    Calling it with an unfitted estimator and a list of (input, output) experiments returns
    Σ(y − ŷ)² / (count · var(y)) over every held-out sample after its window (NRMSE²);
    +inf when a fit fails or a simulation diverges on any fold (an unstable candidate is
    no candidate).  :meth:`outcomes` says fold by fold what happened and why; numerical
    warnings raised by a candidate (an overflow in a diverging free run, an ill-conditioned
    system) are recorded there instead of shown.
    """

    folds: int = 8
    n_init: int | None = None
    mode: str = "free-run"
    divergence: float | None = 1.0

    def __call__(self, estimator, pairs) -> float:
        return self.pooled(self.fold_errors(estimator, pairs), pairs)

    @staticmethod
    def pooled(errors: list[tuple[float, int]], pairs) -> float:
        """Σ squared errors / (Σ counts · var(y)) of :meth:`fold_errors` (+inf if any fold
        is +inf)."""
        if any(math.isinf(squared) for squared, _ in errors):
            return math.inf
        return sum(q for q, _ in errors) / (sum(n for _, n in errors) * output_variance(pairs))

    def fold_errors(self, estimator, pairs) -> list[tuple[float, int]]:
        """(sum of squared errors, scored samples) of each fold; a fold whose fit fails or
        whose estimate diverges gives (+inf, 0) and ends the evaluation."""
        return [(o.squared, o.count) for o in self.outcomes(estimator, pairs)]

    def outcomes(self, estimator, pairs) -> list[FoldOutcome]:
        """What each fold gave ``estimator`` on the (input, output) experiments ``pairs``;
        the first rejected fold ends the evaluation (one suffices to reject).  Every other
        method (the cost, :meth:`fold_errors`, :func:`tune_free_run`'s record) reads this
        one: a subclass that scores folds otherwise overrides it."""
        if running_workers():
            return collected(self.start(estimator, pairs))
        return scored_folds(self, estimator, pairs, self._splits(pairs))

    def start(self, estimator, pairs):
        """The folds of :meth:`outcomes` submitted to the search's workers, for
        :func:`~certkit.ident.workers.collected` to read (None without workers)."""
        return running_workers() and submitted(self, estimator, pairs, self._splits(pairs))

    def _splits(self, pairs) -> list:
        if self.mode not in MODES:
            raise DataInputError("mode", f"expected one of {', '.join(MODES)}, found "
                                         f"{self.mode!r}")
        return list(enumerate(free_run_folds([y.size for _, y in pairs], self.folds, 2)))

    def _fold(self, fold: int, estimator, pairs, train, held) -> FoldOutcome:
        model = clone(estimator)
        try:
            model.fit([pairs[e][0][s] for e, s in train], [pairs[e][1][s] for e, s in train])
        except (ValueError, np.linalg.LinAlgError) as error:
            return FoldOutcome(fold, FAILED, math.inf, 0, f"{type(error).__name__}: {error}")
        trained = np.concatenate([pairs[e][1][s] for e, s in train])
        low, high = float(trained.min()), float(trained.max())
        band = math.inf if self.divergence is None else self.divergence * (high - low)
        n_init = model.init_length if self.n_init is None else int(self.n_init)
        if n_init < model.init_length:
            raise DataInputError("n_init", f"expected at least the model's init_length "
                                           f"{model.init_length}, found {n_init}")
        squared, count = 0.0, 0
        for e, s in held:
            u, y = pairs[e][0][s], pairs[e][1][s]
            if y.size <= n_init:
                raise DataInputError("folds", f"expected held-out pieces longer than the "
                                              f"{n_init}-sample window, found {y.size}")
            estimate = (model.simulate(u, y[:n_init]) if self.mode == "free-run"
                        else model.predict(u, y))
            error = y[n_init:] - estimate[n_init:]
            piece = f"held-out experiment {e}, samples {s.start or 0} to {s.stop - 1}"
            if not np.all(np.isfinite(error)):
                first = n_init + int(np.argmin(np.isfinite(error)))
                return _diverged(fold, model, f"the {self.mode} estimate is not finite from "
                                              f"sample {first} of the {piece}")
            scored = estimate[n_init:]
            if band < math.inf and (scored.min() < low - band or scored.max() > high + band):
                extreme = scored.min() if scored.min() < low - band else scored.max()
                return _diverged(fold, model, f"the {self.mode} estimate reached "
                                              f"{extreme:.4g}, outside [{low - band:.4g}, "
                                              f"{high + band:.4g}] (the fold's training "
                                              f"outputs ± {self.divergence:g} × their range)"
                                              f" on the {piece}")
            squared += float(error @ error)
            count += error.size
        return FoldOutcome(fold, SCORED, squared, count)


def _diverged(fold: int, model, reason: str) -> FoldOutcome:
    """A rejected fold: unstable when the fitted model reports an unstable linear part
    (``stable_`` of an ARX or Hammerstein model), else diverged."""
    if getattr(model, "stable_", True):
        return FoldOutcome(fold, DIVERGED, math.inf, 0, reason)
    largest = float(np.max(np.abs(model.poles_)))
    return FoldOutcome(fold, UNSTABLE, math.inf, 0, f"the fitted linear part is unstable "
                                                    f"(largest |pole| {largest:.4g}): {reason}")


@dataclass(frozen=True)
class CostSurface:
    """Every point :func:`tune_free_run` evaluated, in call order.

    ``rows``: one dict per evaluation with the parameters set (``gamma``, ``sigma2`` and the
    orders searched), ``cost`` and ``stage`` ("grid" or "refine"); ``best``: the parameters
    chosen; ``smoothed``: the smoothed log10 cost of each row when a smoothness prior was
    used (else None); ``members``: the parameters of the ensemble's members, best first
    (``(best,)`` without an ensemble); ``outcomes``: for each row, what each fold of a
    :class:`FreeRunCV` cost gave it (:class:`FoldOutcome`: scored, or why it was
    rejected; empty for another cost); ``warnings``: for each row, the warnings its
    evaluation raised (recorded, not shown); ``edges``: the boundaries of the search the
    chosen point lies on (:class:`~certkit.ident.search_space.SearchEdge`, each with the
    direction to widen; :func:`tune_free_run` also warns of them).
    """

    rows: tuple[dict, ...]
    best: dict
    smoothed: tuple[float, ...] | None = None
    members: tuple[dict, ...] = ()
    outcomes: tuple[tuple[FoldOutcome, ...], ...] = ()
    warnings: tuple[tuple[str, ...], ...] = ()
    edges: tuple[SearchEdge, ...] = ()

    def to_frame(self):
        """The rows as a pandas DataFrame: one column per parameter, ``cost``, ``stage``,
        and with a :class:`FreeRunCV` cost ``status`` (that of the first rejected fold, or
        "scored") and ``reason`` ("fold k: why"; empty when scored); ``warnings`` (the
        messages recorded, "; "-joined)."""
        import pandas as pd
        frame = pd.DataFrame(list(self.rows))
        if self.smoothed is not None:
            frame["smoothed_log10_cost"] = self.smoothed
        if any(self.outcomes):
            rejected = [next((o for o in found if o.rejected), None) for found in self.outcomes]
            frame["status"] = [o.status if o else SCORED for o in rejected]
            frame["reason"] = [f"fold {o.fold}: {o.reason}" if o else "" for o in rejected]
        if self.warnings:
            frame["warnings"] = ["; ".join(messages) for messages in self.warnings]
        return frame

    def grid(self, **orders) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The grid stage for the given orders as (γ values, σ² values, cost matrix
        [γ index, σ² index]), ready for ``pcolormesh``/``contourf`` on log axes."""
        rows = [r for r in self.rows if r["stage"] == "grid"
                and all(r.get(k) == v for k, v in orders.items())]
        if not rows:
            raise DataInputError("orders", f"expected orders that were searched, found "
                                           f"{orders or 'none'} with no grid rows")
        gammas = np.unique([r["gamma"] for r in rows])
        sigma2s = np.unique([r["sigma2"] for r in rows])
        cost = np.full((gammas.size, sigma2s.size), np.nan)
        for r in rows:
            cost[np.searchsorted(gammas, r["gamma"]), np.searchsorted(sigma2s, r["sigma2"])] \
                = r["cost"]
        return gammas, sigma2s, cost


def default_ranges(estimator, n_inputs: int) -> dict:
    """The (γ, σ²) search ranges of :func:`tune_free_run` when none are given.

    NARX: γ ∈ [1e-1, 1e7], σ² ∈ [0.01, 1000]·d, d = na + Σnb (+ one per input with
    ``filter_pole``) in standardised regressor units (lagged samples of an oversampled
    signal are strongly correlated, so the useful σ² can be far above the dimension).
    Hammerstein: γ ∈ [1e-1, 1e7], σ² ∈ [1e-2, 1e2]·n_inputs
    (standardised inputs).  Wiener: γ ∈ [1, 1e7], σ² ∈ [1e-3, 1e3] (standardised z: a
    smooth map needs σ² of several variances of z).  ARX: none (orders only)."""
    if isinstance(estimator, NARX):
        nb = estimator.nb if np.ndim(estimator.nb) else [estimator.nb] * n_inputs
        d = estimator.na + int(np.sum(nb)) + (n_inputs if estimator.filter_pole else 0)
        return {"gamma": (1e-1, 1e7), "sigma2": (0.01 * d, 1e3 * d)}
    if isinstance(estimator, HammersteinLSSVM):
        return {"gamma": (1e-1, 1e7), "sigma2": (1e-2 * n_inputs, 1e2 * n_inputs)}
    if isinstance(estimator, WienerLSSVM):
        return {"gamma": (1e0, 1e7), "sigma2": (1e-3, 1e3)}
    return {}


def _smoothed(rows: list[dict], width: float) -> list[float]:
    """log10 cost averaged with Gaussian weights over the grid rows of the same orders, in
    (log10 γ, log10 σ²) [decades] — a smoothness prior: a point wins by a good
    neighbourhood, not by one lucky evaluation."""
    out = []
    for r in rows:
        same = [q for q in rows if q["stage"] == "grid" and q["orders"] == r["orders"]
                and math.isfinite(q["cost"])]
        if not same or not math.isfinite(r["cost"]):
            out.append(math.inf)
            continue
        weights, values = [], []
        for q in same:
            distance2 = sum((math.log10(q[k]) - math.log10(r[k])) ** 2
                            for k in ("gamma", "sigma2") if k in r)
            weights.append(math.exp(-distance2 / (2 * width ** 2)))
            values.append(math.log10(max(q["cost"], 1e-300)))
        out.append(float(np.dot(weights, values) / np.sum(weights)))
    return out


def _median_smoothed(rows: list[dict]) -> list[float]:
    """log10 of the median of each grid point's cost and its (up to 8) neighbours on the
    (γ, σ²) grid of the same orders; +inf (an unstable neighbour) counts as the worst
    value, an unstable point stays +inf; refinement rows keep their own cost."""
    out = [math.log10(max(r["cost"], 1e-300)) if math.isfinite(r["cost"]) else math.inf
           for r in rows]
    for combination in {r["orders"] for r in rows}:
        mine = [i for i, r in enumerate(rows)
                if r["stage"] == "grid" and r["orders"] == combination]
        keys = [k for k in ("gamma", "sigma2") if k in rows[mine[0]]] if mine else []
        axes = [np.unique([rows[i][k] for i in mine]) for k in keys]
        table = np.full([a.size for a in axes] + [1] * (2 - len(axes)), math.inf)
        where = {}
        for i in mine:
            index = tuple(int(np.searchsorted(a, rows[i][k])) for a, k in zip(axes, keys))
            index += (0,) * (2 - len(index))
            table[index] = rows[i]["cost"]
            where[i] = index
        for i, (a, b) in where.items():
            if math.isfinite(table[a, b]):
                patch = table[max(a - 1, 0):a + 2, max(b - 1, 0):b + 2]
                out[i] = math.log10(max(float(np.median(patch)), 1e-300))
    return out


def _one_standard_error(rows: list[dict], ranked: list[int], folds: dict) -> list[int]:
    """``ranked`` (least cost first) reordered by the one-standard-error rule: the rows
    within one standard error of the best first, most regularised first (least γ, then
    largest σ², then least cost), then the others as they were."""
    best = rows[ranked[0]]
    per_fold = np.array(folds[(best["orders"], best.get("gamma"), best.get("sigma2"))])
    error = float(np.std(per_fold, ddof=1) / math.sqrt(per_fold.size)) \
        if per_fold.size > 1 else 0.0
    near = [i for i in ranked if rows[i]["cost"] <= best["cost"] + error]
    near.sort(key=lambda i: (rows[i].get("gamma") or 0.0, -(rows[i].get("sigma2") or 0.0),
                             rows[i]["cost"]))
    return near + [i for i in ranked if i not in near]


def _resolve(spec, estimator):
    return spec(estimator) if callable(spec) else spec


def tune_free_run(estimator, u, y, *, gamma=None, sigma2=None,
                  orders: dict | list | None = None,
                  cost: Callable | None = None, grid: int | tuple[int, int] = 5,
                  refine: bool = True, max_refine: int = 20,
                  smoothing: float | str = 0.0, ensemble: int = 1, rule: str = "min",
                  n_jobs: int = 1):
    """Tune a model's hyper-parameters (and orders) on its cross-validated free run.

    Parameters
    ----------
    estimator : ARX, NARX, HammersteinLSSVM or WienerLSSVM
        The model, its other settings as wanted (not modified: clones are fitted).
    u, y : array_like or list of array_like
        Estimation data only (one experiment or a list, as for ``fit``).
    gamma, sigma2 : (low, high), float, None, or callable
        Search range (log10), a fixed value, or None for :func:`default_ranges`; a callable
        gets the estimator with the orders set and returns one of those (e.g. σ² ranges
        proportional to the regressor dimension).  Ignored for ARX (no hyper-parameter).
    orders : dict or list of dict, optional
        Orders (or any other structure parameters of the estimator) to search; each
        setting gets its own (γ, σ²) search (:func:`certkit.ident.search_space.order_settings`).
        A dict is a grid, every combination of the values listed:
        ``{"na": [1, 2, 3], "filter_pole": [0.93, 0.95]}``; a value that names another
        order of the grid ties this one to it: ``{"na": [1, 2, 3], "nb": "na"}`` searches
        na = nb = 1, 2, 3.  A list of dicts gives the settings one by one, each setting
        the same orders: ``[{"na": 2, "nb": 1}, {"na": 4, "nb": 3}]``.  Orders must fit the
        cost's initialisation window (``FreeRunCV(n_init=...)`` at least every setting's
        ``init_length``).
    cost : callable, default FreeRunCV()
        ``cost(unfitted_estimator, experiments) -> float``; e.g. ``FreeRunCV(folds=5)``,
        ``FreeRunCV(mode="one-step")`` or any function of that signature.  The default
        is the robust cost: 8 blocked free-run folds, unstable on any fold rejected.
    grid : int or (int, int), default 5
        Grid points per searched parameter (log-spaced), or (γ points, σ² points).
    refine : bool, default True
        Nelder–Mead refinement from the best grid point (:func:`certkit.ident.lssvm.tune`);
        not used with ``smoothing``.
    max_refine : int, default 20
        Cost evaluations allowed to each refinement.
    smoothing : float or "median", default 0
        Width [decades] of a Gaussian smoothness prior: the grid point with the least
        smoothed log10 cost wins (0: the least cost wins); "median": the 3 x 3 running
        median of each (γ, σ²) grid.  Ties are broken by the raw cost.
    ensemble : int, default 1
        Return the mean of the ``ensemble`` best candidates (by the same ranking, unstable
        ones excluded), each refitted on all the data, as an
        :class:`~certkit.ident.ensemble.EnsembleModel`.
    rule : {"min", "one-se"}, default "min"
        "min": the least (raw or smoothed) cost wins.  "one-se": the one-standard-error
        rule (Breiman et al. 1984, §3.4.3; Hastie, Tibshirani & Friedman 2009, §7.10):
        among the candidates whose cost is within one standard error of the least cost,
        the most regularised wins — least γ, then largest σ², then least cost.  The
        standard error is that of the best candidate's per-fold NRMSE² (standard deviation
        over the folds / √folds); the cost must be a :class:`FreeRunCV`.  A long record
        gives a flat cost surface in γ where any tie-break is arbitrary; this one prefers
        the kernel part most penalised, so the parametric part of a partially linear NARX
        (or the bias) carries the model where data are sparse.  Not used with
        ``smoothing``.  The ensemble takes the next candidates in the same order.
    n_jobs : int, default 1
        Worker processes that score the folds (a :class:`FreeRunCV` cost only): fold k of
        every candidate goes to worker k mod n_jobs, which keeps what that fold's fits
        share (:mod:`certkit.ident.reuse`).  The same numbers whatever ``n_jobs``.  The
        workers are forked where the system can; where it cannot (Windows) they re-import
        the calling script, which then needs an ``if __name__ == "__main__":`` guard.
        Inside a process that already runs one worker per core (certkit's model stages
        do), keep 1.

    Returns
    -------
    estimator
        A clone with the chosen parameters set, refitted on all of ``u``, ``y`` (or the
        ensemble of the best, with ``ensemble > 1``).
    CostSurface
        Every evaluation (parameters, cost, stage), the chosen point and the members.

    Notes
    -----
    Only ``u`` and ``y`` are used: give estimation data, never the records the model is to
    be validated on.
    """
    pairs, _ = experiments(u, y)
    cost = FreeRunCV() if cost is None else cost
    if rule not in RULES:
        raise DataInputError("rule", f"expected one of {', '.join(RULES)}, found {rule!r}")
    if rule == "one-se" and (not isinstance(cost, FreeRunCV) or smoothing != 0.0):
        raise DataInputError("rule", "expected a FreeRunCV cost and no smoothing with the "
                                     "one-standard-error rule (it needs the fold errors), "
                                     f"found cost {cost!r}, smoothing {smoothing!r}")
    if isinstance(ensemble, bool) or not isinstance(ensemble, (int, np.integer)) or ensemble < 1:
        raise DataInputError("ensemble", f"expected a positive integer, found {ensemble!r}")
    if isinstance(n_jobs, bool) or not isinstance(n_jobs, (int, np.integer)) or n_jobs < 1:
        raise DataInputError("n_jobs", f"expected a positive integer, found {n_jobs!r}")
    if n_jobs > 1 and not isinstance(cost, FreeRunCV):
        raise DataInputError("n_jobs", f"expected 1 with a cost other than FreeRunCV (only "
                                       f"its folds are scored in parallel), found {n_jobs}")
    folds: dict = {}                     # (orders, γ, σ²) -> per-fold NRMSE² ("one-se")
    found: dict = {}                     # (orders, γ, σ²) -> a FreeRunCV's fold outcomes
    started: dict = {}                   # (orders, γ, σ²) -> its folds, started in the workers
    variance = output_variance(pairs)

    def start(base, setting, points) -> None:
        """Every grid point's folds started in the workers before the first is read, so
        that they never wait for this process (a subclass's own outcomes are not)."""
        if n_jobs > 1 and type(cost).outcomes is FreeRunCV.outcomes:
            started.update({(setting, g, s): cost.start(clone(base).set_params(
                gamma=g, sigma2=s), pairs) for g, s in points})

    def evaluate(candidate, key) -> float:
        if not isinstance(cost, FreeRunCV):
            return cost(candidate, pairs)
        futures = started.pop(key, None)
        found[key] = tuple(collected(futures) if futures else cost.outcomes(candidate, pairs))
        errors = [(o.squared, o.count) for o in found[key]]
        if rule == "one-se":
            folds[key] = [q / (n * variance) if n else math.inf for q, n in errors]
        return cost.pooled(errors, pairs)
    hyper = "gamma" in estimator.get_params()
    space = order_settings(orders, estimator.get_params(), type(estimator).__name__,
                           ("gamma", "sigma2") if hyper else ())
    engine = {}                          # the folds fit with the engine of the final model
    if "engine" in estimator.get_params():
        engine = {"engine": engine_for_folds(estimator.get_params()["engine"],
                                             sum(y.size for _, y in pairs))}
    rows: list[dict] = []
    keys: list[tuple] = []               # each row's key of found
    raised: list[tuple[str, ...]] = []   # each row's warnings from a cost of the user's
    searched: dict = {}                  # setting (index) -> its (γ, σ²) ranges
    with fold_workers(n_jobs):
        for setting, chosen in enumerate(space.settings):
            base = clone(estimator).set_params(**{**engine, **chosen})
            if not hyper:
                with recorded_warnings() as messages:
                    value = evaluate(base, (setting, None, None))
                rows.append({**chosen, "cost": value, "stage": "grid", "orders": setting})
                keys.append((setting, None, None))
                raised.append(tuple(messages))
                continue
            ranges = default_ranges(base, pairs[0][0].shape[1])
            ranges.update({k: _resolve(v, base) for k, v in (("gamma", gamma), ("sigma2", sigma2))
                           if v is not None})
            searched[setting] = ranges
            result = tune(lambda g, s, base=base, c=setting: evaluate(
                              clone(base).set_params(gamma=g, sigma2=s), (c, g, s)),
                          grid=grid, refine=refine and smoothing == 0.0,
                          max_refine=max_refine, allow_infinite=True,
                          prefetch=partial(start, base, setting), **ranges)
            points = (grid, grid) if np.ndim(grid) == 0 else tuple(grid)
            n_grid = int(np.prod([n for n, k in zip(points, ("gamma", "sigma2"))
                                  if np.ndim(ranges[k]) > 0]))
            for index, (g, s, value) in enumerate(result.evaluations):
                rows.append({**chosen, "gamma": g, "sigma2": s, "cost": value,
                             "stage": "grid" if index < n_grid else "refine",
                             "orders": setting})
                keys.append((setting, g, s))
                raised.append(result.warnings[index])
    outcomes = tuple(found.get(key, ()) for key in keys)
    messages = tuple(tuple(dict.fromkeys([m for o in outcome for m in o.warnings] + list(r)))
                     for outcome, r in zip(outcomes, raised))
    if smoothing == "median":
        smoothed = _median_smoothed(rows)
    elif isinstance(smoothing, str):
        raise DataInputError("smoothing", f"expected a width [decades] or 'median', found "
                                          f"{smoothing!r}")
    else:
        smoothed = _smoothed(rows, smoothing) if smoothing > 0 else None
    score = smoothed if smoothed is not None else [r["cost"] for r in rows]
    ranked = sorted((i for i in range(len(rows))
                     if math.isfinite(rows[i]["cost"]) and math.isfinite(score[i])),
                    key=lambda i: (score[i], rows[i]["cost"]))
    if not ranked:
        # a wrong structure setting fails every fold's fit, and the cost scores it +inf:
        # fit the first candidate on all the data so that its own message reaches the user
        first = {k: v for k, v in rows[0].items() if k not in ("cost", "stage", "orders")}
        try:
            clone(estimator).set_params(**first).fit(u, y)
        except DataInputError:
            raise
        except (ValueError, np.linalg.LinAlgError):
            pass                         # a numerical failure: the message below says so
        raise DataInputError("u, y", "expected at least one candidate with a finite free-run "
                                     "cost, found none (every fit failed or diverged)"
                             + _rejections(outcomes))
    if rule == "one-se":
        ranked = _one_standard_error(rows, ranked, folds)
    members = tuple({k: v for k, v in rows[i].items() if k not in ("cost", "stage", "orders")}
                    for i in ranked[:int(ensemble)])
    best = members[0]
    edges = (range_edges(best, searched.get(rows[ranked[0]]["orders"], {}))
             + order_edges(best, space.values, space.ties))
    warn_of_edges(edges, f"tune_free_run of {type(estimator).__name__}")
    if ensemble == 1:
        model = clone(estimator).set_params(**best).fit(u, y)
    else:
        model = EnsembleModel([clone(estimator).set_params(**m) for m in members]).fit(u, y)
    public = tuple({k: v for k, v in r.items() if k != "orders"} for r in rows)
    return model, CostSurface(public, best, None if smoothed is None else tuple(smoothed),
                              members, outcomes, messages, tuple(edges))


def _rejections(outcomes) -> str:
    """': 12 diverged, 3 failed fit; the first: fold k: why' from the rows' fold outcomes
    ('' when there are none: a cost other than FreeRunCV)."""
    rejected = [next(o for o in found if o.rejected) for found in outcomes
                if any(o.rejected for o in found)]
    if not rejected:
        return ""
    counts = {}
    for o in rejected:
        counts[o.status] = counts.get(o.status, 0) + 1
    listed = ", ".join(f"{n} {status}" for status, n in counts.items())
    return f": {listed}; the first: fold {rejected[0].fold}: {rejected[0].reason}"
