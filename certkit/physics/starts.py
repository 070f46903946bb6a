"""Further starts of a calibration: where a bounded least-squares fit of a drop model is
tried from besides its nominal values, and how the result is chosen.

A fit of a drop model can stop in a basin of its cost far from the best one: a stiff
top-out pad barely moves the load until it is much softer, so a trust-region step from the
stiff pad sees almost no slope.  Fitting again from points spread over the bounds finds the
other basins.  The points are fixed (Sobol's sequence, unscrambled), so the answer is the
same on every machine.  Fitting locally from many points spread over the box and keeping
the best is the multistart method (A. H. G. Rinnooy Kan and G. T. Timmer, "Stochastic
global optimization methods, part I: clustering methods", Math. Programming 39 (1987)
27-56); a low-discrepancy set in place of random points spreads the starts evenly (H.
Niederreiter, Random Number Generation and Quasi-Monte Carlo Methods, SIAM, 1992, ch. 4:
the first 2^m points of Sobol's sequence form a (t, m, s)-net in base 2).  The margin
below which two costs count as one minimum (:data:`KEEP_MARGIN`) is a judgement, not a
derived figure.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.stats import qmc

from certkit.physics.fitting import FitError, FitParameter, FitResult, fit
from certkit.physics.simulation import SimulationError

#: Each further start is fitted with forward differences (half the cost of central ones,
#: enough to tell basins apart, whose costs differ by factors) within this many residual
#: evaluations; the best is then fitted again with the fit's own settings.
START_EVALUATIONS = 60
#: The best further start replaces the first fit only when its converged cost is lower by
#: more than this share: below it the two are one minimum reached to the fit's tolerance,
#: and the first fit's estimate is kept.  Among further starts, the earliest whose cost is
#: within this share of the lowest counts as the best (so an answer never hangs on the last
#: bits of a cost).
KEEP_MARGIN = 1e-3
#: At most this many further starts (the Sobol points are drawn in a power of two).
MOST_STARTS = 20


@dataclass(frozen=True)
class StartSearch:
    """The further starts of a calibration (``starts`` of
    :func:`certkit.physics.calibration.calibrate_gear`): the points (SI, one row per start,
    the knobs' order), the cost each start's fit reached (None where its fit failed, the
    reason in ``failures``), the first fit's cost, and which start, if any, the kept
    estimate came from (its index in ``points``; None when the first fit was kept)."""

    points: tuple[tuple[float, ...], ...]
    start_costs: tuple[float | None, ...]
    first_cost: float               # the cost the fit from the first start reached
    kept: int | None
    failures: tuple[str, ...] = ()  # "start k: why", one per start whose fit failed


def sobol_starts(parameters, count: int) -> list[tuple[float, ...]]:
    """``count`` points spread over the box of the parameters' bounds: points 1 … count of
    Sobol's sequence (I. M. Sobol', USSR Comput. Math. Math. Phys. 7 (1967) 86-112;
    unscrambled, the direction numbers of S. Joe and F. Y. Kuo, SIAM J. Sci. Comput. 30
    (2008) 2635-2654, as :class:`scipy.stats.qmc.Sobol` has them; point 0, every
    coordinate on its lower bound, left out).  Each coordinate of points 0 … 2^m − 1 takes
    every value k/2^m once, so every knob is started in both halves of its range and more.
    A coordinate is placed on a log scale between two positive bounds (a pre-charge and a
    pad compression range over factors), on a linear one otherwise."""
    if not 0 <= count <= MOST_STARTS:
        raise ValueError(f"further starts: expected 0 to {MOST_STARTS}, got {count}")
    if count == 0:
        return []
    order = int(np.ceil(np.log2(count + 1)))
    unit = qmc.Sobol(len(parameters), scramble=False).random_base2(order)[1:count + 1]
    points = []
    for row in unit:
        point = []
        for q, parameter in zip(row, parameters):
            low, high = parameter.lower, parameter.upper
            if low > 0:
                point.append(float(np.exp(np.log(low) + q * (np.log(high) - np.log(low)))))
            else:
                point.append(float(low + q * (high - low)))
        points.append(tuple(point))
    return points


def best_of_starts(first: FitResult, parameters: list[FitParameter], single, many,
                   count: int, evaluations: int, tolerance: float, *, step: float):
    """The fit from the first start, or the fit from the best of ``count`` further starts
    when that reaches a cost lower by more than :data:`KEEP_MARGIN`.  Each further start is
    fitted with forward differences within :data:`START_EVALUATIONS`; the best (the
    earliest within :data:`KEEP_MARGIN` of the lowest cost) is fitted again from where it
    stopped, with central differences and the fit's own budget ``evaluations`` and
    ``tolerance``; ``single`` and ``many`` are the residuals of one parameter set and of a
    batch (as :func:`certkit.physics.fitting.fit` takes them).  Every fit differences over
    ``step`` of each parameter's size (the first fit's step: the caller gives it), and the
    sizes are the first start's wherever a fit starts.  A start whose fit fails (the model cannot be simulated there, or its residuals
    are not finite) is recorded so and passed over; when every start fails, or the final fit
    does, the first fit is kept.  The result keeps the first start's parameters and cost at
    the start (what the report calls "nominal") and counts every evaluation made, a failed
    fit's too."""
    points = sobol_starts(parameters, count)
    costs, fits, failures, spent = [], [], [], first.evaluations
    for index, point in enumerate(points):
        try:
            trial = fit(single, [replace(q, nominal=v) for q, v in zip(parameters, point)],
                        residuals_many=many, max_evaluations=START_EVALUATIONS,
                        tolerance=tolerance, relative_step=step, differences="forward")
        except (FitError, SimulationError) as error:
            spent += getattr(error, "evaluations", 0)
            costs.append(None)
            fits.append(None)
            failures.append(f"start {index + 1}: {error}")
            continue
        spent += trial.evaluations
        costs.append(float(trial.cost))
        fits.append(trial)
    done = [c for c in costs if c is not None]
    kept, result = None, first
    if done:
        lowest = min(done)
        best = next(i for i, c in enumerate(costs)
                    if c is not None and c <= lowest * (1.0 + KEEP_MARGIN))
        try:
            refined = fit(single, [replace(q, nominal=float(v)) for q, v in
                                   zip(parameters, fits[best].estimate)],
                          residuals_many=many, max_evaluations=evaluations,
                          tolerance=tolerance, relative_step=step)
        except (FitError, SimulationError) as error:
            spent += getattr(error, "evaluations", 0)
            failures.append(f"start {best + 1}, fitted again: {error}")
        else:
            spent += refined.evaluations
            if refined.cost < first.cost * (1.0 - KEEP_MARGIN):
                kept = best
                result = replace(refined, parameters=tuple(parameters),
                                 cost_nominal=first.cost_nominal)
    return (replace(result, evaluations=spent),
            StartSearch(tuple(points), tuple(costs), float(first.cost), kept,
                        tuple(failures)))


def starts_document(search: StartSearch | None) -> dict | None:
    """The further starts, JSON-ready (SI), or None when the fit had none; "kept_start"
    numbers the start whose fit was kept from 1, None when the fit from the first start
    was kept; a failed start's cost is None, its reason in "failures"."""
    if search is None:
        return None
    return {"points": [list(p) for p in search.points],
            "training_costs": list(search.start_costs),
            "first_training_cost": search.first_cost,
            "kept_start": None if search.kept is None else search.kept + 1,
            "failures": list(search.failures)}
