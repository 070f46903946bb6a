"""What a drop represents: the lift it simulates and the weight each gear unit carries.

One home for these rules so the compliance engine, the audit and the physics model
cannot drift apart.
"""

from __future__ import annotations

import math

from certkit.spec.schema import CampaignSpec, Run
from certkit.units import STANDARD_GRAVITY


def lift_ratio(run: Run) -> float:
    """L the drop represents (0 when lift is not simulated)."""
    return 0.0 if run.lift.method == "none" else run.lift.ratio.si


def lift_force_ratio(run: Run) -> float:
    """L of a lift force acting during the drop: only a lift device applies one; a reduced
    drop mass represents lift by having less weight, with no force acting."""
    return run.lift.ratio.si if run.lift.method == "lift_device" else 0.0


def drop_weight_share(spec: CampaignSpec, run: Run, gear_id: str) -> float:
    """Weight the unit carries in the drop [N], certkit W1: the whole drop weight for a
    single-unit rig; for a complete-airplane drop the unit's share W_unit·m_drop·g/W_max."""
    drop_weight = run.drop_mass.si * STANDARD_GRAVITY
    if len(run.gear_units) == 1:
        return drop_weight
    unit = next(g for g in spec.gear_units if g.id == gear_id)
    return unit.static_weight.si * drop_weight / spec.aircraft.maximum_weight.si


def static_strut_load(static_weight: float, unsprung_mass: float, inclination: float) -> float:
    """Axial load on the strut at rest [N]: the unit's static weight W [N] less the weight
    of the unsprung mass below the strut [kg], along a strut inclined θ [rad] from vertical."""
    return (static_weight - unsprung_mass * STANDARD_GRAVITY) * math.cos(inclination)
