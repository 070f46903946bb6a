"""Transducer and logger dynamics on recorded channels: a low-pass and a delay."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.signal import butter, lfilter, lfilter_zi

from certkit.physics.drop_model import Parameter
from certkit.physics.effects.base import Effect


@dataclass(frozen=True)
class SensorDynamics:
    """Transducer and logger dynamics on measured channels (the logger's filter applied
    to the simulation, so the two are compared through the same instrument).

    A causal Butterworth low-pass of the given order and cut-off (an anti-alias or
    smoothing filter) followed by a pure delay (channel skew, transducer lag).  It acts on
    the recorded signals, not on the mechanics: apply it to a simulated channel to compare
    like with like.  Group delay of a 2nd-order 100 Hz Butterworth at 1 kHz: about 2.2 ms.
    """

    cutoff: float          # [Hz]
    order: int = 2         # 0: no low-pass, a pure delay
    delay: float = 0.0     # [s]
    name = "sensor dynamics"

    def parameters(self):
        return [Parameter("cutoff", self.cutoff, "Hz", "low-pass cut-off frequency"),
                Parameter("order", self.order, "1", "Butterworth order"),
                Parameter("delay", self.delay, "s", "pure delay")]

    def apply(self, time: np.ndarray, signal: np.ndarray) -> np.ndarray:
        """The signal as the logger records it (time uniform, starting before contact)."""
        step = float(np.mean(np.diff(time)))
        filtered = np.asarray(signal, dtype=float)
        if self.order:                      # order 0: no low-pass, a pure delay
            b, a = butter(self.order, self.cutoff, fs=1.0 / step)
            filtered = lfilter(b, a, filtered, zi=lfilter_zi(b, a) * filtered[0])[0]
        if self.delay:
            filtered = np.interp(time - self.delay, time, filtered, left=filtered[0])
        return filtered


#: Built from the spec's model.sensor by the synthetic campaigns, which apply it to the
#: simulated channels; it is no term of the drop model.
EFFECT = Effect(label="sensor dynamics", name="sensor-dynamics")
