"""Where a tuning search looks, and whether what it found lies on the edge of that.

:func:`order_settings` reads the orders a search goes through: a grid, a grid with tied
orders (``{"na": [1, 2, 3], "nb": "na"}``) or a list of settings.

A search of (γ, σ²) over log ranges, or of orders over the values listed, can only find a
point inside what it covers.  When the chosen point lies on a boundary, the best may lie
beyond it: :func:`range_edges` and :func:`order_edges` find such a point's edges, each a
:class:`SearchEdge` that says which parameter, which end and which way to widen;
:func:`warn_of_edges` warns with a :class:`SearchEdgeWarning`.  The searches record the
edges with their result (:class:`certkit.ident.lssvm.TuningResult` ``edges``,
:class:`certkit.ident.tuning.CostSurface` ``edges``).
"""

from __future__ import annotations

import itertools
import math
import warnings
from dataclasses import dataclass
from numbers import Real

import numpy as np

from certkit.errors import CertkitWarning, DataInputError

#: A chosen γ or σ² within this many decades of a bound lies on it: the Nelder–Mead
#: refinement stops at a simplex of 0.02 decades (:func:`certkit.ident.lssvm.tune`'s
#: ``tolerance``), so it cannot tell a point this close from the bound itself.
EDGE_TOLERANCE = 0.02
#: How far the advice widens a range beyond the bound the point lies on [decades].
WIDEN_DECADES = 2


class SearchEdgeWarning(CertkitWarning):
    """The chosen point of a tuning search lies on a boundary of what was searched;
    ``edges``: the :class:`SearchEdge` s, for a caller that records them."""

    def __init__(self, message: str, edges: tuple = ()):
        super().__init__(message)
        self.edges = tuple(edges)


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
        warnings.warn(SearchEdgeWarning(
            f"{who}: the chosen point lies on the edge of the search, the best may lie "
            f"beyond it: " + "; ".join(e.advice for e in edges), edges), stacklevel=stacklevel)


@dataclass(frozen=True)
class OrderSettings:
    """The order settings a search goes through, read from ``orders`` by
    :func:`order_settings`: ``names`` (the orders set, in the order given), ``settings``
    (one dict per setting, each complete, in search order), ``values`` (each order's values
    over the settings: where its ends lie) and ``ties`` (tied order -> the order it
    follows)."""

    names: tuple[str, ...]
    settings: tuple[dict, ...]
    values: dict
    ties: dict


def order_settings(orders, parameters, who: str, ranged: tuple[str, ...] = ()
                   ) -> OrderSettings:
    """The settings of the orders (or other structure parameters) a search goes through.

    Parameters
    ----------
    orders : dict, list of dict or None
        A dict is a grid: each order's list of values, every combination searched in
        turn (the last order varying fastest); a value that is the *name* of another order
        of the grid ties this one to it (``{"na": [1, 2, 3], "nb": "na"}``: na = nb = 1, 2,
        3).  A list of dicts gives the settings one by one, each setting the same orders
        (``[{"na": 2, "nb": 1}, {"na": 4, "nb": 3}]``).  None: one setting, the
        estimator's own.
    parameters : collection of str
        The estimator's parameters.
    who : str
        The estimator, as messages name it.
    ranged : tuple of str
        Parameters searched by their ranges (γ, σ²), which ``orders`` may not set.

    Returns
    -------
    OrderSettings

    Raises
    ------
    certkit.errors.DataInputError
        Key ``orders``: what was expected and what was found.
    """
    if orders is None:
        return OrderSettings((), ({},), {}, {})
    if isinstance(orders, dict):
        return _grid(orders, parameters, who, ranged)
    if isinstance(orders, (list, tuple)):
        return _listed(orders, parameters, who, ranged)
    raise DataInputError("orders", f"expected a dict of value lists (a grid) or a list of "
                                   f"dicts (each a setting), found {type(orders).__name__}")


def _check_names(names, parameters, who: str, ranged: tuple[str, ...], where: str) -> None:
    for name in names:
        if name in ranged:
            raise DataInputError("orders", f"{where}expected orders or other structure "
                                           f"parameters, found {name!r}, which is searched "
                                           f"by its range ({name}=(low, high) or a value)")
        if name not in parameters:
            raise DataInputError("orders", f"{where}expected parameters of {who}, found "
                                           f"{name!r}")


def _grid(orders: dict, parameters, who: str, ranged: tuple[str, ...]) -> OrderSettings:
    _check_names(orders, parameters, who, ranged, "")
    ties, listed = {}, {}
    for name, spec in orders.items():
        if isinstance(spec, str):
            leader = orders.get(spec)
            if spec == name or leader is None or isinstance(leader, str):
                raise DataInputError("orders", f"{name}: expected the name of another order "
                                               f"of the grid with a list of values to tie "
                                               f"{name} to, found {spec!r}")
            ties[name] = spec
            continue
        try:
            listed[name] = list(spec)
        except TypeError:
            raise DataInputError("orders", f"{name}: expected a list of values, or the name "
                                           f"of another order to tie it to, found "
                                           f"{spec!r}") from None
        if not listed[name]:
            raise DataInputError("orders", f"{name}: expected at least one value, found an "
                                           f"empty list")
    leaders = list(listed)
    settings = []
    for combination in itertools.product(*listed.values()):
        chosen = dict(zip(leaders, combination))
        settings.append({name: chosen[ties.get(name, name)] for name in orders})
    values = {name: listed[ties.get(name, name)] for name in orders}
    return OrderSettings(tuple(orders), tuple(settings), values, ties)


def _listed(orders, parameters, who: str, ranged: tuple[str, ...]) -> OrderSettings:
    if not orders:
        raise DataInputError("orders", "expected at least one setting, found an empty list")
    seen: dict[str, int] = {}
    for k, setting in enumerate(orders):
        if not isinstance(setting, dict) or not setting:
            raise DataInputError("orders", f"orders[{k}]: expected a dict of parameter values, "
                                           f"found {setting!r}")
        _check_names(setting, parameters, who, ranged, f"orders[{k}]: ")
        if set(setting) != set(orders[0]):
            raise DataInputError("orders", f"orders[{k}]: expected the parameters of "
                                           f"orders[0] ({', '.join(orders[0])}), found "
                                           f"{', '.join(setting)}")
        key = repr(sorted(setting.items()))
        if key in seen:
            raise DataInputError("orders", f"orders[{k}]: expected settings that differ, "
                                           f"found a repeat of orders[{seen[key]}]")
        seen[key] = k
    names = tuple(orders[0])
    settings = tuple({name: setting[name] for name in names} for setting in orders)
    return OrderSettings(names, settings, {n: [s[n] for s in settings] for n in names}, {})
