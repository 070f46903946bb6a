"""The effects simple drop models omit, as optional terms of the drop model: the registry.

Every effect is defined once, in its own module here, as an
:class:`~certkit.physics.effects.base.Effect` (its label, its name in a spec, how its term
is built from the spec, its calibration knobs, its candidate family for the gap diagnosis
and its truth form for the blind check), and registered once, in :data:`EFFECTS` below.
The gear model, calibration, the diagnosis and the blind check read the registry; none of
them names an effect.  Adding an effect is one module and one line in :data:`EFFECTS` (and
its name in the spec's ``Effect`` list, which the spec stage keeps so that a campaign is
validated without the physics; ``tests/test_effect_registry.py`` holds the two equal).

Each term is a small frozen dataclass with named SI parameters.  A mechanical term writes
them into the slots of the compiled equations of motion (:mod:`certkit.physics.dynamics`,
the one home of force laws); a term that acts on what the instruments record (sensor lag,
load-cell gain) changes the recorded channels instead (its ``recorded`` method).

The order of :data:`EFFECTS` is the order in which the gear model adds terms, the
diagnosis scores candidates and the blind check plans its cases.
"""

import copyreg
import pickle

from certkit.physics.effects import (heat_transfer, leg_flexibility, load_cell_gain, metering_pin,
                                     oil_compressibility, platform_compliance, rebound_orifice,
                                     seal_friction, sensor_dynamics, sensor_lag, tyre_hysteresis)
from certkit.physics.effects.base import Candidate, Effect, Knob, Truth
from certkit.physics.effects.heat_transfer import GasHeatTransfer
from certkit.physics.effects.leg_flexibility import LegFlexibility
from certkit.physics.effects.load_cell_gain import LoadCellGain
from certkit.physics.effects.metering_pin import MeteringPin
from certkit.physics.effects.oil_compressibility import OilCompressibility
from certkit.physics.effects.platform_compliance import PlatformCompliance
from certkit.physics.effects.rebound_orifice import ReboundOrifice
from certkit.physics.effects.seal_friction import SealFriction
from certkit.physics.effects.sensor_dynamics import SensorDynamics
from certkit.physics.effects.sensor_lag import SensorLag
from certkit.physics.effects.tyre_hysteresis import TyreHysteresis

#: The registry, one line an effect.
EFFECTS: tuple[Effect, ...] = (
    seal_friction.EFFECT,
    rebound_orifice.EFFECT,
    metering_pin.EFFECT,
    tyre_hysteresis.EFFECT,
    heat_transfer.EFFECT,
    oil_compressibility.EFFECT,
    leg_flexibility.EFFECT,
    platform_compliance.EFFECT,
    sensor_lag.EFFECT,
    sensor_dynamics.EFFECT,
    load_cell_gain.EFFECT,
)

#: The effects a spec can switch on, by their name in ``model.effects``.
BY_NAME: dict[str, Effect] = {effect.name: effect for effect in EFFECTS if effect.name}
#: Calibration knobs the effects add, in registry order.
KNOBS: tuple[Knob, ...] = tuple(knob for effect in EFFECTS for knob in effect.knobs)


#: The gap diagnosis's candidate families (every form of every effect), in registry order.
CANDIDATES: tuple[Candidate, ...] = tuple(c for e in EFFECTS for c in e.candidates)


def registered_candidate(key: str, unit_size: str) -> Candidate:
    """The candidate ``key`` of :data:`CANDIDATES`: how a pickled candidate (whose ``add``
    is a lambda) comes back; an error when this certkit has no such candidate."""
    for candidate in CANDIDATES:
        if candidate.key == key and candidate.unit_size == unit_size:
            return candidate
    raise pickle.UnpicklingError(f"no candidate effect {key!r} in this certkit")


copyreg.pickle(Candidate, lambda c: (registered_candidate, (c.key, c.unit_size)))

#: The blind check's truth forms, by the label of the candidate a right diagnosis names.
TRUTHS: dict[str, Truth] = {e.truth.candidate: e.truth for e in EFFECTS if e.truth}


__all__ = ["BY_NAME", "CANDIDATES", "EFFECTS", "KNOBS", "TRUTHS", "Candidate", "Effect", "GasHeatTransfer", "Knob",
           "LegFlexibility", "LoadCellGain", "MeteringPin", "OilCompressibility",
           "PlatformCompliance", "ReboundOrifice", "SealFriction", "SensorDynamics",
           "SensorLag", "Truth", "TyreHysteresis"]
