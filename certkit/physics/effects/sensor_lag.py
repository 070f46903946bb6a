"""A first-order lag of every recorded channel: the diagnosis's form of sensor dynamics."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.signal import lfilter

from certkit.physics.drop_model import Term
from certkit.physics.effects.base import Candidate, Effect, Truth
from certkit.physics.effects.sensor_dynamics import SensorDynamics


@dataclass(frozen=True)
class SensorLag(Term):
    """A lag of every recorded channel: ``order`` identical first-order lags of time
    constant τ in cascade (1: the simplest form of transducer and logger dynamics; 2: a
    critically damped second-order low-pass, closer to an anti-alias filter), as a model
    term (compare like with like: the simulation sees what the transducer and logger
    would record).

    It acts on the channels the simulation records, not on the mechanics (``pack`` writes
    nothing); :func:`certkit.physics.simulation.simulate_batch` and ``simulate_reference`` apply
    it.  Exact discretisation of τ·ẏ + y = x for a piecewise-constant input, ``order``
    times.
    """

    time_constant: float  # τ [s]
    order: int = 1
    name = "sensor lag"
    fields = (("time_constant", "s", "time constant τ of each first-order lag"),
              ("order", "1", "number of first-order lags in cascade"))

    def __post_init__(self):
        if not self.time_constant >= 0:
            raise ValueError("the sensor lag's time constant must not be negative")
        if self.order not in (1, 2):
            raise ValueError("the sensor lag's order must be 1 or 2")

    def pack(self, p):
        pass  # recorded channels only

    def recorded(self, step: float, channel: str, signal: np.ndarray) -> np.ndarray:
        return self.apply(step, signal)      # every channel alike

    def apply(self, step: float, signal: np.ndarray) -> np.ndarray:
        """The lagged signal (last axis is time), starting at the signal's first value."""
        if self.time_constant == 0:
            return np.asarray(signal, dtype=float)
        a = np.exp(-step / self.time_constant)
        signal = np.asarray(signal, dtype=float)
        for _ in range(self.order):
            signal = lfilter([1 - a], [1, -a], signal, axis=-1, zi=(a * signal[..., :1]))[0]
        return signal


EFFECT = Effect(
    label="sensor lag",
    candidates=(
        Candidate("sensor lag", "a first-order lag of 2 ms on every recorded channel",
                  lambda m, phi: m.with_effect(SensorLag(0.002 * phi)), probe=0.1,
                  form="first order", quantities=(("2 ms", 0.002, "s"),)),
        Candidate("sensor lag", "two first-order lags of 1 ms in cascade on every recorded "
                                "channel", lambda m, phi: m.with_effect(SensorLag(0.001 * phi, 2)),
                  probe=0.1, form="second order", quantities=(("1 ms", 0.001, "s"),))),
    truth=Truth("sensor lag", "a 2nd-order Butterworth low-pass (cut-off 300 Hz/s) plus a pure "
                              "delay (0.1 ms·s) on every channel, sized by what remains with the "
                              "touchdowns aligned (the candidate: a first-order lag)",
                (0.7, 20.0), sensor=lambda s: SensorDynamics(300.0 / s, 2, 0.0001 * s)))
