"""Simulating drops: a reference path (scipy ``solve_ivp`` LSODA, tight tolerances, one drop)
and a fast batched path (fixed-step RK4 over many drops at once, numpy).

The output has the channels of a measured run (platform load, strut stroke, tyre
deflection, drop-mass acceleration and displacement) at the logger's sample rate, so
simulated and measured runs go through identical code downstream; it also carries the
simulator's own energy accounting, the truth that certkit's energy integrals are
checked against.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from .drop_model import DropModel
from .units import STANDARD_GRAVITY


class SimulationError(RuntimeError):
    """The integrator failed; the message names the run and the time it failed at."""


@dataclass
class SimulatedDrop:
    """Channels at the sample times (SI, the sign conventions of :mod:`certkit.rundata`).

    ``time`` is 0 at first contact; energies are cumulative works from contact [J].
    """

    time: np.ndarray
    load: np.ndarray
    stroke: np.ndarray
    tyre: np.ndarray
    acceleration: np.ndarray   # drop mass (m1), kinematic, positive upward
    displacement: np.ndarray   # drop mass (m1), positive downward, 0 at release
    dissipated: np.ndarray     # work of orifice, friction, stop and tyre damping
    mechanical: np.ndarray     # kinetic + stored − gravity work − lift work, from contact
    strut_work: np.ndarray     # ∫ F_s·ṡ dt from contact: work done on the strut
    tyre_work: np.ndarray      # ∫ F_V·δ̇ dt from contact: work done on the tyre

    def absorbed_on_loading(self) -> tuple[float, float]:
        """Truth of E_s and E_t: work done on strut and tyre up to each one's maximum travel."""
        return (float(self.strut_work[np.argmax(self.stroke)]),
                float(self.tyre_work[np.argmax(self.tyre)]))


# State: z1, v1, z2, v2, then three works integrated alongside: dissipated
# (∫(F_s − F_gas − F_stop,spring)·ṡ + tyre damping·δ̇), on the strut (∫F_s·ṡ), on the tyre (∫F_V·δ̇).


def _energy_parts(model: DropModel, state) -> tuple:
    z1, v1, z2, v2 = state[0], state[1], state[2], state[3]
    cos_theta = math.cos(model.inclination)
    stroke = (z1 - z2) / cos_theta
    kinetic = 0.5 * model.upper_mass * v1 ** 2 + 0.5 * model.lower_mass * v2 ** 2
    stops = model.stops
    stop_spring = np.where(stroke < 0, 0.5 * stops.stiffness * stroke ** 2,
                           np.where(stroke > stops.travel,
                                    0.5 * stops.stiffness * (stroke - stops.travel) ** 2, 0.0))
    stored = model.gas.energy(stroke) + model.tyre.energy(z2) + stop_spring
    gravity = STANDARD_GRAVITY * (model.upper_mass * z1 + model.lower_mass * z2)
    lift = model.lift * z1  # the lift acts from contact on (the simulation's start)
    return kinetic + stored - gravity + lift


def _rhs(model: DropModel):
    cos_theta = math.cos(model.inclination)

    def rhs(_t, y):
        motion = model.rates(y[:4])
        z1, v1, z2, v2 = y[0], y[1], y[2], y[3]
        stroke, rate = (z1 - z2) / cos_theta, (v1 - v2) / cos_theta
        parts = model.strut_parts(stroke, rate)
        stops = model.stops
        spring = np.where(stroke < 0, stops.stiffness * stroke,
                          np.where(stroke > stops.travel, stops.stiffness * (stroke - stops.travel),
                                   0.0))
        # everything in the strut but the gas spring and the stops' springs dissipates
        non_conservative = sum(parts.values()) - parts["gas"] - spring
        ground = model.ground_force(z2, v2)
        tyre_damping = ground - np.where(z2 > 0, model.tyre.static_force(z2), 0.0)
        power = non_conservative * rate + tyre_damping * v2
        strut_power = sum(parts.values()) * rate
        tyre_power = ground * v2
        return np.concatenate([motion, [power, strut_power, tyre_power]])

    return rhs


def simulate_reference(model: DropModel, contact_velocity: float, duration: float = 2.0,
                       sample_rate: float = 1000.0, lead: float = 0.1, rtol: float = 1e-9,
                       atol: float = 1e-12, run: str = "simulation") -> SimulatedDrop:
    """Simulate one drop with scipy's LSODA (stiff/non-stiff switching) at tight tolerances.

    Parameters
    ----------
    contact_velocity : float
        Vertical velocity at first tyre contact [m/s] (√(2·g·h) for an ideal free drop).
    duration : float
        Record length after contact [s].
    lead : float
        Free-fall record before contact [s] (the logger runs before impact).
    run : str
        Name used in error messages.
    """
    y0 = np.concatenate([model.initial_state(contact_velocity), [0.0, 0.0, 0.0]])
    samples = int(round(duration * sample_rate)) + 1
    t_eval = np.linspace(0.0, duration, samples)
    solution = solve_ivp(_rhs(model), (0.0, duration), y0, method="LSODA", t_eval=t_eval,
                         rtol=rtol, atol=atol, max_step=1e-3)
    if not solution.success:
        failed_at = solution.t[-1] if solution.t.size else 0.0
        raise SimulationError(f"run {run}: the integrator failed at t = {failed_at:.6g} s after "
                              f"contact: {solution.message}")
    y = solution.y
    cos_theta = math.cos(model.inclination)
    stroke = (y[0] - y[2]) / cos_theta
    load = model.ground_force(y[2], y[3])
    motion = model.rates(y[:4])
    mechanical = _energy_parts(model, y[:4])
    mechanical = mechanical - mechanical[0]

    # free fall before contact, sampled on the same grid
    lead_samples = int(round(lead * sample_rate))
    t_lead = -np.arange(lead_samples, 0, -1) / sample_rate
    fall_height = contact_velocity ** 2 / (2 * STANDARD_GRAVITY)
    velocity_lead = contact_velocity + STANDARD_GRAVITY * t_lead
    zeros = np.zeros(lead_samples)
    return SimulatedDrop(
        time=np.concatenate([t_lead, solution.t]),
        load=np.concatenate([zeros, load]),
        stroke=np.concatenate([zeros, stroke]),
        tyre=np.concatenate([zeros, np.maximum(y[2], 0.0)]),
        acceleration=np.concatenate([np.full(lead_samples, -STANDARD_GRAVITY), -motion[1]]),
        displacement=np.concatenate([fall_height - velocity_lead ** 2 / (2 * STANDARD_GRAVITY),
                                     fall_height + y[0]]),
        dissipated=np.concatenate([zeros, y[4]]),
        mechanical=np.concatenate([zeros, mechanical]),
        strut_work=np.concatenate([zeros, y[5]]),
        tyre_work=np.concatenate([zeros, y[6]]),
    )


@dataclass
class BatchDrops:
    """Channels of a batch of drops: arrays of shape (drops, samples); ``time`` is shared."""

    time: np.ndarray
    load: np.ndarray
    stroke: np.ndarray
    tyre: np.ndarray
    acceleration: np.ndarray
    displacement: np.ndarray


#: RK4 step of the batched path.  The stiffest rate in the model is the regularised seal
#: friction against the unsprung mass (about 3e4 1/s for a 2 mm/s smoothing width), which
#: RK4 integrates stably and accurately at 0.2 ms (test_fast_path_agrees_with_the_reference).
BATCH_STEP = 2.0e-4


def simulate_batch(model: DropModel, contact_velocity, duration: float = 2.0,
                   sample_rate: float = 1000.0, step: float = BATCH_STEP) -> BatchDrops:
    """Simulate many drops at once with classical RK4 at a fixed step.

    The model's parameters and ``contact_velocity`` may be arrays of one common length
    (one entry per drop): every force term is element-wise, so the batch runs through the
    same code as the reference path.  Output starts at contact (no free-fall lead).
    """
    velocity = np.atleast_1d(np.asarray(contact_velocity, dtype=float))
    state = model.initial_state(velocity)
    per_sample = int(round(1.0 / (sample_rate * step)))
    if not np.isclose(per_sample * step * sample_rate, 1.0):
        raise ValueError("the step must divide the sample interval")
    samples = int(round(duration * sample_rate)) + 1
    history = np.empty((samples,) + state.shape)
    history[0] = state
    for index in range(1, samples):
        for _ in range(per_sample):
            k1 = model.rates(state)
            k2 = model.rates(state + 0.5 * step * k1)
            k3 = model.rates(state + 0.5 * step * k2)
            k4 = model.rates(state + step * k3)
            state = state + step / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        history[index] = state
    z1, z2, v2 = history[:, 0].T, history[:, 2].T, history[:, 3].T  # (drops, samples)
    acceleration = np.array([model.rates(history[i])[1] for i in range(samples)]).T
    column = (-1, 1)  # per-drop values as a column, to broadcast over samples
    return BatchDrops(
        time=np.arange(samples) / sample_rate,
        load=model.ground_force(z2.T, v2.T).T,  # samples first, so per-drop parameters broadcast
        stroke=(z1 - z2) / np.reshape(np.cos(model.inclination), column),
        tyre=np.maximum(z2, 0.0), acceleration=-acceleration,
        displacement=z1 + np.reshape(velocity ** 2 / (2 * STANDARD_GRAVITY), column))
