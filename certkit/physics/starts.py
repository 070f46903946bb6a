"""Further starts of a calibration: where a bounded least-squares fit of a drop model is
tried from besides its nominal values, and how the result is chosen.

A fit of a drop model can stop in a basin of its cost far from the best one: a stiff
top-out pad barely moves the load until it is much softer, so a trust-region step from the
stiff pad sees almost no slope.  Fitting again from points spread over the bounds finds the
other basins; the points are fixed (Halton's sequence), so the answer is the same on every
machine.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from certkit.physics.fitting import FitParameter, FitResult, fit


@dataclass(frozen=True)
class StartSearch:
    """The further starts of a calibration (``starts`` of
    :func:`certkit.physics.calibration.calibrate_gear`): the
    points of the Halton design (SI, one row per start, the knobs' order), the cost each
    start's fit reached, and which start, if any, the kept estimate came from (its
    index in ``points``; None when the fit from the first start was kept)."""

    points: tuple[tuple[float, ...], ...]
    start_costs: tuple[float, ...]
    first_cost: float               # the cost the fit from the first start reached
    kept: int | None


#: Each further start is fitted with forward differences (half the cost of central ones,
#: enough to tell basins apart, whose costs differ by factors) within this many residual
#: evaluations; the best is then fitted again with the fit's own settings.
START_EVALUATIONS = 60
#: The best further start replaces the first fit only when its converged cost is lower by
#: more than this share: below it the two are one minimum reached to the fit's tolerance,
#: and the first fit's estimate is kept (so an answer never hangs on rounding).
KEEP_MARGIN = 1e-3
_PRIMES = (2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61, 67, 71)


def _radical_inverse(index: int, base: int) -> float:
    """The ``index``-th term of van der Corput's sequence in ``base`` (its digits
    mirrored about the point): one coordinate of Halton's sequence."""
    value, weight = 0.0, 1.0
    while index > 0:
        weight /= base
        value += weight * (index % base)
        index //= base
    return value


def halton_starts(parameters, count: int) -> list[tuple[float, ...]]:
    """``count`` points spread over the box of the parameters' bounds: the Halton sequence
    (J. H. Halton, Numer. Math. 2 (1960) 84-90; coordinate j in the j-th prime base,
    points 1 … count), placed on a log scale between bounds of one sign and a linear one
    otherwise (a pre-charge and a pad compression range over factors).  Fixed, so a
    calibration is the same on every machine."""
    if len(parameters) > len(_PRIMES):
        raise ValueError(f"halton_starts: {len(parameters)} parameters, at most "
                         f"{len(_PRIMES)}")
    points = []
    for index in range(1, count + 1):
        point = []
        for parameter, base in zip(parameters, _PRIMES):
            q, low, high = _radical_inverse(index, base), parameter.lower, parameter.upper
            if low > 0:
                point.append(float(np.exp(np.log(low) + q * (np.log(high) - np.log(low)))))
            else:
                point.append(float(low + q * (high - low)))
        points.append(tuple(point))
    return points


def best_of_starts(first: FitResult, parameters: list[FitParameter], single, many,
                   count: int, evaluations: int, tolerance: float):
    """The fit from the first start, or the fit from the best of ``count`` further starts
    when that reaches a cost lower by more than :data:`KEEP_MARGIN`.  Each further start is
    fitted with forward differences within :data:`START_EVALUATIONS`; the one with the
    lowest cost (the earliest on a tie) is fitted again from where it stopped, with central
    differences and the fit's own budget ``evaluations``
    and ``tolerance``; ``single`` and ``many`` are the residuals of one parameter set and
    of a batch (as :func:`certkit.physics.fitting.fit` takes them).  The result keeps
    the first start's parameters and cost at the start (what the report calls "nominal")."""
    points = halton_starts(parameters, count)
    screened = [fit(single, [replace(q, nominal=v) for q, v in zip(parameters, p)],
                    residuals_many=many, max_evaluations=START_EVALUATIONS,
                    tolerance=tolerance, differences="forward") for p in points]
    costs = [trial.cost for trial in screened]
    best = int(np.argmin(costs))
    refined = fit(single, [replace(q, nominal=float(v))
                              for q, v in zip(parameters, screened[best].estimate)],
                  residuals_many=many, max_evaluations=evaluations, tolerance=tolerance)
    spent = first.evaluations + sum(t.evaluations for t in screened) + refined.evaluations
    kept = refined.cost < first.cost * (1.0 - KEEP_MARGIN)
    result = replace(refined if kept else first, evaluations=spent)
    if kept:
        result = replace(result, parameters=tuple(parameters), cost_nominal=first.cost_nominal)
    return result, StartSearch(tuple(points), tuple(float(c) for c in costs), float(first.cost),
                               best if kept else None)


def starts_document(search: StartSearch | None) -> dict | None:
    """The further starts, JSON-ready (SI), or None when the fit had none; "kept_start"
    numbers the start whose fit was kept from 1, None when the fit from the first start
    was kept."""
    if search is None:
        return None
    return {"points": [list(p) for p in search.points],
            "training_costs": list(search.start_costs),
            "first_training_cost": search.first_cost,
            "kept_start": None if search.kept is None else search.kept + 1}
