"""A gain error of the platform's load cells: the load channel reads (1 + ε) times the force.

A force transducer's sensitivity is known only to its calibration class (ISO 376:2011,
*Calibration of force-proving instruments used for the verification of uniaxial testing
machines*; ASTM E74, *Calibration of force-measuring instruments*): a load chain calibrated
long ago, or with the wrong amplifier gain, scales every load sample alike while stroke and
tyre deflection are untouched.  The effect acts on the recorded load channel only; the
mechanics are unchanged.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from certkit.physics.drop_model import Term
from certkit.physics.effects.base import Candidate, Effect, Knob, Truth, set_effect


@dataclass(frozen=True)
class LoadCellGain(Term):
    """The load channel recorded as (1 + ε)·F: a gain (sensitivity) error ε of the load cells."""

    gain: float  # ε [1]
    name = "load-cell gain"
    fields = (("gain", "1", "gain error ε of the load channel (share)"),)

    def __post_init__(self):
        if not self.gain > -1:
            raise ValueError("a load-cell gain error must be above −100 %")

    def pack(self, p):
        pass  # recorded channels only

    def recorded(self, step: float, channel: str, signal: np.ndarray) -> np.ndarray:
        return (1.0 + self.gain) * signal if channel == "load" else signal


EFFECT = Effect(
    label="load-cell gain", name="load-cell-gain",
    # the gain is not typed: it starts at 0 and the calibration estimates it
    build=lambda gear: LoadCellGain(0.0),
    knobs=(Knob("load-cell-gain", "load-cell gain error ε", "1",
                lambda m: m.effect("load-cell gain").gain,
                lambda m, v: set_effect(m, "load-cell gain", gain=v),
                lambda nominal: (-0.1, 0.1), needs="load-cell gain"),),
    # a chain may read high or low; the low form divides by (1 + 0.05·φ), so that no
    # strength the diagnosis may fit reaches a gain of −100 %
    candidates=(Candidate("load-cell gain", "a load channel reading 5 % high",
                          lambda m, phi: m.with_effect(LoadCellGain(0.05 * phi)),
                          form="reading high", memoryless_on="load"),
                Candidate("load-cell gain", "a load channel reading 1/1.05 of the force "
                                            "(4.8 % low)",
                          lambda m, phi: m.with_effect(LoadCellGain(1 / (1 + 0.05 * phi) - 1)),
                          form="reading low", memoryless_on="load")),
    truth=Truth("load-cell gain", "load cells reading (1 + 0.001·s) times the platform force "
                                  "(the candidate's own form)", (0.05, 100.0),
                mechanics=lambda m, s: m.with_effect(LoadCellGain(0.001 * s))))
