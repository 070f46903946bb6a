"""Wiener models (linear block, then a static nonlinearity) of a gear unit.

Two routes to the linear block:

* the seed paper's small-signal method (§4, steps 1-10): excite the plant with a small
  random force, repeat it scaled by K, and accept linearity when the response scales by
  K within a stated tolerance, else shrink the amplitude; the linear block (ARX, orders
  of the seed: 6 poles, 4 input terms) is fitted to the accepted small-signal records;
* the best linear approximation (Schoukens & Tiels, arXiv 1607.01217): the linear model
  fitted to the plant's response to a Gaussian excitation at the operating amplitude.

Either block is scaled to unit static gain, so its output z carries the input's unit
(N) and the static nonlinearity y = f(z) (LS-SVM regression from z to the measured
output) is the gear's quasi-static load-travel curve.  The plant is any callable taking
a force deviation [N] and returning output deviations; :func:`physics_plant` makes one
from a drop model driven by a prescribed ground load.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy.signal import butter, sosfiltfilt

from certkit.ident.linear_models import ARX
from certkit.physics.simulation import simulate_driven
from certkit.units import STANDARD_GRAVITY

Plant = Callable[[np.ndarray], dict]


@dataclass(frozen=True)
class LinearityStep:
    """One K-scaling check of the small-signal method."""

    amplitude: float        # RMS of the small force [N]
    mismatch: dict          # output -> ‖y_K − K·y_1‖/‖K·y_1‖
    accepted: bool


@dataclass
class SmallSignalExperiment:
    """The accepted small-signal records and the checks that led to them."""

    force: list                       # the excitations applied [N]
    responses: dict                   # output -> list of response records
    steps: list = field(default_factory=list)
    accepted: bool = False


def excitation(samples: int, sample_rate: float, bandwidth: float, seed: int) -> np.ndarray:
    """Zero-mean random force of unit RMS, low-passed to ``bandwidth`` [Hz] (a small random
    signal, step 1), starting and ending at zero."""

    rng = np.random.default_rng(seed)
    signal = sosfiltfilt(butter(4, bandwidth, fs=sample_rate, output="sos"),
                         rng.standard_normal(samples))
    taper = np.minimum(1.0, np.minimum(np.arange(samples), np.arange(samples)[::-1])
                       / (0.02 * samples))
    signal = signal * taper
    signal = signal - taper * (signal.sum() / taper.sum())   # zero mean, still 0 at the ends
    return signal / np.sqrt(np.mean(signal ** 2))


def small_signal_records(plant: Plant, outputs: list[str], samples: int, sample_rate: float,
                         amplitude: float, gain: float = 2.0, tolerance: float = 0.05,
                         shrink: float = 0.5, max_steps: int = 8, bandwidth: float = 30.0,
                         seed: int = 0) -> SmallSignalExperiment:
    """Steps 1-4: find an amplitude at which the plant responds linearly.

    Applies ``amplitude``·r and ``gain``·``amplitude``·r (r: :func:`excitation`) and
    checks that every output scales by ``gain`` within ``tolerance``.  While it does, the
    amplitude grows by ``gain`` and the largest linear one is kept (steps 2-3); if the
    first check fails the amplitude shrinks by ``shrink`` until one passes (step 4); at
    most ``max_steps`` checks.
    """
    base = excitation(samples, sample_rate, bandwidth, seed)
    experiment = SmallSignalExperiment(force=[], responses={name: [] for name in outputs})

    def check(level: float):
        first, second = level * base, gain * level * base
        y1, y2 = plant(first), plant(second)
        mismatch = {}
        for name in outputs:
            reference = gain * y1[name]
            norm = float(np.linalg.norm(reference))
            mismatch[name] = (float(np.linalg.norm(y2[name] - reference)) / norm
                              if norm > 0 else float("inf"))
        accepted = all(m <= tolerance for m in mismatch.values())
        experiment.steps.append(LinearityStep(level, mismatch, accepted))
        return accepted, (first, second, y1, y2)

    def keep(records) -> None:
        first, second, y1, y2 = records
        experiment.force = [first, second]
        experiment.responses = {name: [y1[name], y2[name]] for name in outputs}
        experiment.accepted = True

    accepted, records = check(amplitude)
    if accepted:
        # steps 2-3: while the response stays linear, apply the scaled signal again; keep
        # the largest amplitude that was still linear
        for _ in range(max_steps - 1):
            keep(records)
            amplitude *= gain
            accepted, records = check(amplitude)
            if not accepted:
                return experiment
        keep(records)
        return experiment
    # step 4: not linear: bring the amplitude back within the margin until it is
    for _ in range(max_steps - 1):
        amplitude *= shrink
        accepted, records = check(amplitude)
        if accepted:
            keep(records)
            return experiment
    return experiment


def best_linear_records(plant: Plant, outputs: list[str], samples: int, sample_rate: float,
                        amplitude: float, realisations: int = 2, bandwidth: float = 30.0,
                        seed: int = 100) -> SmallSignalExperiment:
    """Records for the best linear approximation: Gaussian-like excitations at the
    operating amplitude (several realisations), no linearity check."""
    experiment = SmallSignalExperiment(force=[], responses={name: [] for name in outputs},
                                       accepted=True)
    for index in range(realisations):
        force = amplitude * excitation(samples, sample_rate, bandwidth, seed + index)
        response = plant(force)
        experiment.force.append(force)
        for name in outputs:
            experiment.responses[name].append(response[name])
    return experiment


@dataclass
class WienerModel:
    """A unit-static-gain linear block followed by a static nonlinearity (LS-SVM).

    Learned: ``linear_`` (ARX with unit static gain; z in the input's unit),
    ``raw_linear_`` (as fitted, gain included), ``nonlinearity_`` (an LS-SVM regressor
    from z to y).
    """

    na: int = 6
    nb: int = 4
    gamma: float | None = None
    sigma2: float | None = None

    def fit_linear(self, force: list, response: list) -> WienerModel:
        """Step 5: the linear block from records where the plant is linear."""
        self.raw_linear_ = ARX(self.na, self.nb).fit(force, response)
        self.linear_ = self.raw_linear_.normalised()
        return self

    def fit_nonlinearity(self, inputs: list, outputs: list, tune) -> WienerModel:
        """Steps 6-9: z = G(q)·u for large-amplitude inputs, then y = f(z) by LS-SVM.

        ``tune(X, y) -> fitted regressor`` chooses the hyper-parameters (cross-validation);
        the regressor is fitted on all samples of ``inputs``/``outputs``.
        """
        z = np.concatenate([self.linear_.simulate(u) for u in inputs])
        y = np.concatenate([np.asarray(o, dtype=float) for o in outputs])
        if not np.all(np.isfinite(z)):
            raise ValueError("the linear block's output is not finite (unstable block)")
        self.z_range_ = (float(z.min()), float(z.max()))
        self.nonlinearity_ = tune(z[:, None], y)
        return self

    def simulate(self, u: np.ndarray) -> np.ndarray:
        """Free-run simulation from rest: y = f(G(q)·u)."""
        z = self.linear_.simulate(u)
        return self.nonlinearity_.predict(z[:, None])


def physics_plant(model, samples: int, sample_rate: float, outputs=("stroke", "tyre")) -> Plant:
    """The drop model driven by a prescribed ground load around its resting point.

    The applied force is the unit's weight less lift plus the excitation; the outputs are
    the departures of stroke and tyre deflection from their resting values."""

    time = np.arange(samples) / sample_rate
    weight = model.total_mass * STANDARD_GRAVITY - model.lift
    rest = simulate_driven(model, time, np.full(samples, weight))
    base = {"stroke": rest.stroke, "tyre": rest.tyre}

    def plant(force: np.ndarray) -> dict:
        response = simulate_driven(model, time, weight + np.asarray(force, dtype=float))
        values = {"stroke": response.stroke, "tyre": response.tyre}
        return {name: values[name] - base[name] for name in outputs}

    return plant
