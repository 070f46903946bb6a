"""A gain error of the platform's load cells: the load channel reads (1 + ε) times the force.

A force transducer's sensitivity is known only to its calibration class (ISO 376:2011,
*Calibration of force-proving instruments used for the verification of uniaxial testing
machines*; ASTM E74, *Calibration of force-measuring instruments*): a load chain calibrated
long ago, or with the wrong amplifier gain, scales every load sample alike while stroke and
tyre deflection are untouched.  The load chain's own group delay (its amplifier and
anti-alias filter), or a logger that samples its channels in turn, also makes the load
record lag or lead the others by a skew τ, a fraction of a millisecond: the gain's refit
fits that skew with it (within ±:data:`MAX_SKEW`), so that a gain with a skew is not taken
for a timing error of another kind (crosstalk through a frame, tens of milliseconds).  The
effect acts on the recorded load channel only; the mechanics are unchanged.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from certkit.physics.drop_model import Term
from certkit.physics.effects.base import Candidate, Effect, Knob, Truth, set_effect


#: The largest load-channel skew the gain's refit may fit [s]: a load chain's group delay
#: or a multiplexed logger's channel skew is a fraction of a millisecond.
MAX_SKEW = 1.0e-3


@dataclass(frozen=True)
class LoadCellGain(Term):
    """The load channel recorded as (1 + ε)·F(t − τ): a gain (sensitivity) error ε of the
    load cells, and a skew τ of the load record behind the other channels (negative: ahead),
    by linear interpolation between samples."""

    gain: float          # ε [1]
    skew: float = 0.0    # τ [s]
    name = "load-cell gain"
    fields = (("gain", "1", "gain error ε of the load channel (share)"),
              ("skew", "s", "skew τ of the load record behind the other channels"))

    def __post_init__(self):
        if not self.gain > -1:
            raise ValueError("a load-cell gain error must be above −100 %")

    def pack(self, p):
        pass  # recorded channels only

    def recorded(self, step: float, channel: str, signal: np.ndarray) -> np.ndarray:
        if channel != "load":
            return signal
        signal = (1.0 + self.gain) * np.asarray(signal, dtype=float)
        if self.skew == 0.0:
            return signal
        index = np.arange(signal.shape[-1], dtype=float)
        moved = index - self.skew / step
        if signal.ndim == 1:
            return np.interp(moved, index, signal)
        return np.stack([np.interp(moved, index, row) for row in signal])

    def record_delay(self, channel: str) -> float:
        return self.skew if channel == "load" else 0.0


#: The skews at which the gain's profile is taken (the refit starts from the best) [s].
SKEWS = (0.0, -0.6 * MAX_SKEW, -0.3 * MAX_SKEW, 0.3 * MAX_SKEW, 0.6 * MAX_SKEW)
#: The skew fitted with the gain when the gain's candidate is refitted.
SKEW = Knob("load-channel-skew", "load channel skew τ", "s",
            lambda m: m.effect("load-cell gain").skew,
            lambda m, v: set_effect(m, "load-cell gain", skew=v),
            lambda nominal: (-MAX_SKEW, MAX_SKEW), needs="load-cell gain")


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
                          form="reading high", memoryless_on="load", knobs=((SKEW, SKEWS),)),
                Candidate("load-cell gain", "a load channel reading 1/1.05 of the force "
                                            "(4.8 % low)",
                          lambda m, phi: m.with_effect(LoadCellGain(1 / (1 + 0.05 * phi) - 1)),
                          form="reading low", memoryless_on="load", knobs=((SKEW, SKEWS),))),
    truth=Truth("load-cell gain", "load cells reading (1 + 0.001·s) times the platform force "
                                  "(the candidate's own form)", (0.05, 100.0),
                mechanics=lambda m, s: m.with_effect(LoadCellGain(0.001 * s))))
