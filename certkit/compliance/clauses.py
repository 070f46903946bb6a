"""Regulatory formulas of the drop-test clauses, one function each, SI in and out.

Each docstring cites the clause it implements.  The coefficients (3.6, 9.2 in,
1.44, ...) are not written here: they come from the requirement-set data files
(:mod:`certkit.spec.requirement_sets`) and are passed in, so a set with other values
(an SI transcription, a later edition) needs no code change.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from certkit.units import STANDARD_GRAVITY, ureg


@dataclass(frozen=True)
class DropHeight:
    """Required free drop height and how it was bounded.

    Attributes
    ----------
    formula : float
        Height given by the formula alone [m].
    required : float
        Height after the clause's bounds [m].
    bound : str or None
        ``"minimum"`` or ``"maximum"`` when a bound replaced the formula value.
    """

    formula: float
    required: float
    bound: str | None


def required_drop_height(wing_loading: float, coefficient: float, wing_loading_unit: str,
                         height_unit: str, minimum: float | None,
                         maximum: float | None) -> DropHeight:
    """Required limit free drop height, 14 CFR 23.725(a).

    Parameters
    ----------
    wing_loading : float
        W/S [Pa], W the maximum weight as a force.
    coefficient : float
        3.6 in 23.725(a), for W/S in ``wing_loading_unit`` and h in ``height_unit``.
    wing_loading_unit, height_unit : str
        Units the clause's formula is written in (``"lbf/ft^2"``, ``"in"``).
    minimum, maximum : float or None
        Bounds [m]: "may not be less than 9.2 inches and need not be more than 18.7 inches".

    Notes
    -----
    h = coefficient · √(W/S), then h_req = max(h, minimum) and, because the
    height "need not" exceed the maximum, h_req = min(h_req, maximum).
    """
    if wing_loading <= 0:
        raise ValueError("wing loading must be positive")
    formula = float(drop_height_formula(wing_loading, coefficient, wing_loading_unit,
                                        height_unit))
    required = float(bounded_drop_height(formula, minimum, maximum))
    bound = (None if required == formula
             else "minimum" if minimum is not None and required == minimum else "maximum")
    return DropHeight(formula, required, bound)


def drop_height_formula(wing_loading, coefficient: float, wing_loading_unit: str,
                        height_unit: str):
    """h = coefficient·√(W/S) of 14 CFR 23.725(a) in m, W/S [Pa] a number or an array (the
    formula's units converted by constant factors)."""
    to_rule = ureg.Quantity(1.0, "Pa").to(wing_loading_unit).magnitude
    to_metre = ureg.Quantity(1.0, height_unit).to("m").magnitude
    return coefficient * np.sqrt(np.asarray(wing_loading) * to_rule) * to_metre


def bounded_drop_height(height, minimum: float | None, maximum: float | None):
    """The drop height after 23.725(a)'s bounds: not less than ``minimum``, and not more
    than ``maximum`` since the height "need not" exceed it (numbers or arrays) [m]."""
    if minimum is not None:
        height = np.maximum(height, minimum)
    if maximum is not None:
        height = np.minimum(height, maximum)
    return height


def effective_weight(weight: float, drop_height: float, deflection: float,
                     lift_ratio: float) -> float:
    """Effective drop weight with wing lift simulated by reduced mass, 14 CFR 23.725(b).

    W_e = W·(h + (1 − L)·d)/(h + d)

    Parameters
    ----------
    weight : float
        W, static weight on the gear unit [N].
    drop_height : float
        h, free drop height [m].
    deflection : float
        d, tyre deflection plus vertical axle travel relative to the drop mass [m];
        23.725(d): not more than the value measured in the drop.
    lift_ratio : float
        L, assumed wing lift / weight (not more than 0.667 in 23.725(b)).
    """
    return weight * (drop_height + (1.0 - lift_ratio) * deflection) / (drop_height + deflection)


def reserve_effective_weight(weight: float, drop_height: float, deflection: float) -> float:
    """Effective weight of the reserve energy drop, 14 CFR 23.727(b): W_e = W·h/(h + d)."""
    return weight * drop_height / (drop_height + deflection)


def drop_test_load_factor(peak_acceleration: float, reference: str) -> float:
    """n_j, "the acceleration (dv/dt) in g's recorded in the drop test plus 1.0", 23.725(e).

    Parameters
    ----------
    peak_acceleration : float
        Peak upward acceleration of the drop mass [m/s^2].
    reference : {"kinematic", "specific_force"}
        ``kinematic``: dv/dt (so n_j = a/g + 1); ``specific_force``: an accelerometer
        reading, which already contains the 1 g (so n_j = f/g).
    """
    if reference == "kinematic":
        return peak_acceleration / STANDARD_GRAVITY + 1.0
    if reference == "specific_force":
        return peak_acceleration / STANDARD_GRAVITY
    raise ValueError(f"unknown acceleration reference {reference!r}")


def inertia_load_factor(drop_load_factor: float, effective: float, weight: float,
                        lift_ratio: float) -> float:
    """Limit inertia load factor from a drop, 14 CFR 23.725(e): n = n_j·W_e/W + L."""
    return drop_load_factor * effective / weight + lift_ratio


def energy_method_load_factor(drop_height: float, tyre_travel: float, shock_travel: float,
                              lift_ratio: float, tyre_efficiency: float,
                              shock_efficiency: float) -> float:
    """Ground-reaction load factor by the energy method (seed paper; Currey §3.2).

    n_j = (h + (1 − L)·d)/(η_t·d_t + η_s·d_s), with d = d_t + d_s.  With L = 2/3 this
    is the seed paper's n_j = (h + d/3)/(0.5·d_tire + 0.65·d_shock).  It follows from
    W·(h + d) − L·W·d = F·(η_t·d_t + η_s·d_s); the inertia factor is n = n_j + L.
    """
    deflection = tyre_travel + shock_travel
    denominator = tyre_efficiency * tyre_travel + shock_efficiency * shock_travel
    if denominator <= 0:
        raise ValueError("tyre and shock-absorber travel must not both be zero")
    return (drop_height + (1.0 - lift_ratio) * deflection) / denominator


def ideal_impact_velocity(drop_height: float) -> float:
    """Contact velocity of a free drop without losses, v = √(2·g·h) [m/s]."""
    return math.sqrt(2.0 * STANDARD_GRAVITY * drop_height)


def limit_descent_velocity(wing_loading: float) -> tuple[float, float]:
    """Limit descent velocity of 14 CFR 23.473(d), returning (formula, bounded) [m/s].

    V = 4.4·(W/S)^(1/4) ft/s with W/S in lb/ft²; V need not be more than 10 ft/s and
    may not be less than 7 ft/s.
    """
    loading = ureg.Quantity(wing_loading, "Pa").to("lbf/ft^2").magnitude
    formula = 4.4 * loading ** 0.25
    bounded = min(max(formula, 7.0), 10.0)
    to_si = ureg.Quantity(1.0, "ft/s").to("m/s").magnitude
    return formula * to_si, bounded * to_si


def available_energy(weight: float, drop_height: float, deflection: float,
                     lift_ratio: float) -> float:
    """Energy to be absorbed at maximum compression: W·(h + d) − L·W·d [J].

    Potential energy of the free drop plus the travel d, less the work of a wing
    lift L·W acting through d (zero when lift is not simulated by a device).
    """
    return weight * (drop_height + deflection) - lift_ratio * weight * deflection
