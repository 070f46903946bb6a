"""Where a tuning search looks, and whether what it found lies on the edge of that.

A search of (γ, σ²) over log ranges, or of orders over the values listed, can only find a
point inside what it covers.  When the chosen point lies on a boundary, the best may lie
beyond it: :func:`range_edges` and :func:`order_edges` find such a point's edges, each a
:class:`SearchEdge` that says which parameter, which end and which way to widen;
:func:`warn_of_edges` warns with a :class:`SearchEdgeWarning`.  The searches record the
edges with their result (:class:`certkit.ident.lssvm.TuningResult` ``edges``,
:class:`certkit.ident.tuning.CostSurface` ``edges``).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from numbers import Real

import numpy as np

from certkit.errors import CertkitWarning

#: A chosen γ or σ² within this many decades of a bound lies on it: the Nelder–Mead
#: refinement stops at a simplex of 0.02 decades (:func:`certkit.ident.lssvm.tune`'s
#: ``tolerance``), so it cannot tell a point this close from the bound itself.
EDGE_TOLERANCE = 0.02
#: How far the advice widens a range beyond the bound the point lies on [decades].
WIDEN_DECADES = 2


class SearchEdgeWarning(CertkitWarning):
    """The chosen point of a tuning search lies on a boundary of what was searched."""


@dataclass(frozen=True)
class SearchEdge:
    """A boundary of the search the chosen point lies on.

    ``parameter`` (``"gamma"``, ``"sigma2"`` or an order's name), ``side`` (``"lower"`` or
    ``"upper"``), ``value`` (the chosen value), ``bound`` (the range's end, or the smallest
    or largest value listed) and ``advice`` (in words: which way to widen the search).
    """

    parameter: str
    side: str
    value: object
    bound: object
    advice: str


def range_edges(point: dict, ranges: dict, tolerance: float = EDGE_TOLERANCE
                ) -> list[SearchEdge]:
    """The edges of log ranges that ``point`` lies on.

    Parameters
    ----------
    point : dict
        The chosen values, e.g. ``{"gamma": 1e7, "sigma2": 3.2}``.
    ranges : dict
        Each searched parameter's (low, high); a number (a fixed value) is not searched
        and has no edge.
    tolerance : float
        Decades from a bound within which the point lies on it.

    Returns
    -------
    list of SearchEdge
    """
    edges = []
    for name, spec in ranges.items():
        if name not in point or np.ndim(spec) != 1:
            continue
        low, high = (float(v) for v in spec)
        value = float(point[name])
        if math.log10(value) - math.log10(low) <= tolerance:
            wider = f"{name}=({low / 10 ** WIDEN_DECADES:.3g}, {high:.3g})"
            edges.append(SearchEdge(name, "lower", value, low, (
                f"{name} = {value:.3g} lies on the lower end of its range ({low:.3g}, "
                f"{high:.3g}): widen it downwards, e.g. {wider}")))
        elif math.log10(high) - math.log10(value) <= tolerance:
            wider = f"{name}=({low:.3g}, {high * 10 ** WIDEN_DECADES:.3g})"
            edges.append(SearchEdge(name, "upper", value, high, (
                f"{name} = {value:.3g} lies on the upper end of its range ({low:.3g}, "
                f"{high:.3g}): widen it upwards, e.g. {wider}")))
    return edges


def _is_number(value) -> bool:
    return isinstance(value, Real) and not isinstance(value, bool)


def order_edges(point: dict, values: dict, ties: dict | None = None) -> list[SearchEdge]:
    """The ends of the listed values that ``point`` lies on.

    Parameters
    ----------
    point : dict
        The chosen setting, e.g. ``{"na": 3, "nb": 3}``.
    values : dict
        Each order's values searched (over every setting).  Only numbers have ends; an
        order with fewer than two values, or with values that are not numbers
        (``output_bound``), has none; nor does a 0, the least an order can be.
    ties : dict, optional
        Tied order -> the order it follows: its edge is its leader's, named there.

    Returns
    -------
    list of SearchEdge
    """
    ties = ties or {}
    edges = []
    for name, listed in values.items():
        distinct = sorted(set(listed)) if all(_is_number(v) for v in listed) else []
        if name in ties or len(distinct) < 2 or name not in point:
            continue
        value = point[name]
        followers = [t for t, leader in ties.items() if leader == name]
        also = f" ({', '.join(followers)} follow{'s' * (len(followers) == 1)} it)" \
            if followers else ""
        if value == distinct[0] and value != 0:
            edges.append(SearchEdge(name, "lower", value, distinct[0], (
                f"{name} = {value} is the smallest value searched{also}: add smaller "
                f"values")))
        elif value == distinct[-1]:
            edges.append(SearchEdge(name, "upper", value, distinct[-1], (
                f"{name} = {value} is the largest value searched{also}: add larger "
                f"values")))
    return edges


def warn_of_edges(edges: list[SearchEdge], who: str, stacklevel: int = 3) -> None:
    """A :class:`SearchEdgeWarning` listing every edge's advice (none without edges)."""
    if edges:
        warnings.warn(f"{who}: the chosen point lies on the edge of the search, the best "
                      f"may lie beyond it: " + "; ".join(e.advice for e in edges),
                      SearchEdgeWarning, stacklevel=stacklevel)
