"""The gas law of an oleo-pneumatic strut at rest: the stroke its servicing gives under a load.

The audit compares it with the declared static stroke, and the physics model's gas spring
uses the same closed form (one home for the rule).
"""

from __future__ import annotations

#: Standard atmosphere [Pa] (ISO 2533:1975), the reference of gauge pressures.
STANDARD_ATMOSPHERE = 101325.0


def absolute_pressure(pressure: float, reference: str) -> float:
    """``pressure`` [Pa] as an absolute pressure, ``reference`` being 'gauge' or 'absolute'."""
    return pressure + (STANDARD_ATMOSPHERE if reference == "gauge" else 0.0)


def gas_equilibrium_stroke(volume: float, area: float, precharge: float, load: float,
                           exponent: float) -> float:
    """Stroke [m] at which the gas carries ``load`` [N]: p0·V0ⁿ = p·(V0 − A·s)ⁿ with
    p = p_atm + load/A (absolute pressures; the atmosphere pushes on the piston's outer
    face), so s = V0/A·(1 − (p0/p)^(1/n)); 0 when the pre-charge alone holds the load.

    ``precharge`` is the absolute pressure p0 at full extension [Pa]; ``exponent`` n is 1 for
    gas at rest at wall temperature (isothermal), the polytropic exponent for a fast stroke.
    """
    pressure = STANDARD_ATMOSPHERE + load / area
    if pressure <= precharge:
        return 0.0
    return volume / area * (1.0 - (precharge / pressure) ** (1.0 / exponent))
