"""Simulating drops: a reference path (scipy ``solve_ivp`` LSODA, tight tolerances, one drop)
and a fast batched path (fixed-step RK4 over many drops at once, compiled).  Both call
the same compiled equations of motion (:mod:`certkit.physics.dynamics`).

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

from certkit.errors import CampaignError
from certkit.physics import dynamics as dyn
from certkit.physics.drop_model import DropModel, orifice_coefficient
from certkit.units import STANDARD_GRAVITY

#: The channels a logger records (what sensor effects act on).
RECORDED = ("load", "stroke", "tyre", "acceleration", "displacement")


class SimulationError(CampaignError, RuntimeError):
    """The integrator failed; the message names the run and the time it failed at."""


@dataclass
class SimulatedDrop:
    """Channels at the sample times (SI, the sign conventions of :mod:`certkit.spec.rundata`).

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


def _free_fall(contact_velocity: float, lead: float, sample_rate: float):
    """Sample times and drop-mass displacement of the free fall before contact."""
    lead_samples = int(round(lead * sample_rate))
    t_lead = -np.arange(lead_samples, 0, -1) / sample_rate
    fall_height = contact_velocity ** 2 / (2 * STANDARD_GRAVITY)
    velocity = contact_velocity + STANDARD_GRAVITY * t_lead
    return t_lead, velocity ** 2 / (2 * STANDARD_GRAVITY), fall_height


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
    p = model.pack()
    dy = np.empty(dyn.STATES)

    def rhs(t, y):
        dyn.rates(p, y, dy)
        if not np.all(np.isfinite(dy)):
            raise SimulationError(f"run {run}: the model's rates are not finite at t = {t:.6g} s "
                                  f"after contact (check the gear parameters)")
        return dy.copy()

    samples = int(round(duration * sample_rate)) + 1
    t_eval = np.linspace(0.0, duration, samples)
    solution = solve_ivp(rhs, (0.0, duration), model.initial_state(contact_velocity),
                         method="LSODA", t_eval=t_eval, rtol=rtol, atol=atol, max_step=1e-3)
    if not solution.success:
        failed_at = solution.t[-1] if solution.t.size else 0.0
        raise SimulationError(f"run {run}: the integrator failed at t = {failed_at:.6g} s after "
                              f"contact: {solution.message}")
    y = solution.y
    recorded = np.empty((samples, dyn.CHANNELS))
    for index in range(samples):
        dyn.channels(p, y[:, index], recorded[index], False, 0.0)
    energy = recorded[:, dyn.ENERGY] - recorded[0, dyn.ENERGY]

    t_lead, fall, fall_height = _free_fall(contact_velocity, lead, sample_rate)
    zeros = np.zeros(t_lead.size)
    drop = SimulatedDrop(
        time=np.concatenate([t_lead, solution.t]),
        load=np.concatenate([zeros, recorded[:, dyn.LOAD]]),
        stroke=np.concatenate([zeros, recorded[:, dyn.STROKE]]),
        tyre=np.concatenate([zeros, recorded[:, dyn.TYRE]]),
        acceleration=np.concatenate([np.full(t_lead.size, -STANDARD_GRAVITY),
                                     recorded[:, dyn.ACCELERATION]]),
        displacement=np.concatenate([fall, fall_height + recorded[:, dyn.DISPLACEMENT]
                                     - recorded[0, dyn.DISPLACEMENT]]),
        dissipated=np.concatenate([zeros, y[dyn.DISSIPATED]]),
        mechanical=np.concatenate([zeros, energy]),
        strut_work=np.concatenate([zeros, y[dyn.STRUT_WORK]]),
        tyre_work=np.concatenate([zeros, y[dyn.TYRE_WORK]]),
    )
    for effect in model.effects:   # those acting on the recorded channels (sensor lag, ...)
        for name in RECORDED:
            setattr(drop, name, effect.recorded(1.0 / sample_rate, name, getattr(drop, name)))
    return drop


@dataclass
class BatchDrops:
    """Channels of a batch of drops: arrays of shape (drops, samples); ``time`` is shared,
    0 at contact.  ``dissipated`` is the total work of the dissipative terms per drop [J]."""

    time: np.ndarray
    load: np.ndarray
    stroke: np.ndarray
    tyre: np.ndarray
    acceleration: np.ndarray
    displacement: np.ndarray
    mechanical: np.ndarray
    dissipated: np.ndarray


#: Longest RK4 step of the batched path [s].  The step is otherwise set by the model's
#: fastest rate (:func:`fastest_rate`): RK4 is accurate far beyond the 0.1 % the fast
#: path must match the reference to (test_fast_path_agrees_with_the_reference), so
#: stability, not accuracy, limits it.
MAX_STEP = 5.0e-4
#: Largest step·rate accepted (RK4's stability limit is 2.78 on the real axis and 2.83
#: on the imaginary axis).
STABILITY = 2.5


def _peak_tyre_force(model: DropModel, contact_velocity: float) -> float:
    """Upper estimate of the tyre force in a drop: the static curve at the deflection where
    the tyre alone would absorb the kinetic energy plus the fall over the design stroke."""
    tyre = model.tyre
    energy = model.total_mass * (0.5 * contact_velocity ** 2
                                 + STANDARD_GRAVITY * model.stops.travel)
    b = tyre.exponent
    deflection = ((b + 1) * energy * tyre.reference_deflection ** b
                  / tyre.reference_load) ** (1 / (b + 1))
    return float(tyre.static_force(deflection))


def fastest_rate(model: DropModel, contact_velocity: float) -> float:
    """Estimate of the model's fastest persistent rate [1/s] in a drop at ``contact_velocity``.

    Against the unsprung mass: the stops (the stiffer of top-out and bottoming), orifice
    damping at the contact velocity, the tyre's stiffness, damping and hysteresis near its
    peak force, and seal friction while the strut sticks (level F_0 + μ·max(preload, static
    load) over v_ε·m2; near maximum stroke the friction's steep zone is crossed within a
    step, which RK4 follows accurately); the oil column, the platform and the leg.
    """
    m2 = model.lower_mass
    leg = model.effect("leg flexibility")
    if leg is not None and not leg.above:
        m2 = min(m2 - leg.axle_mass, leg.axle_mass)
    tyre = model.tyre
    peak = _peak_tyre_force(model, contact_velocity)
    stop = max(model.stops.stiffness, model.stops.top_out_stiffness(model.gas.preload))
    rates = [math.sqrt(stop / m2), model.stops.damping / m2,
             2.0 * math.sqrt(tyre.exponent * tyre.reference_load / tyre.reference_deflection / m2),
             tyre.damping * peak / m2]
    hysteresis = model.effect("tyre hysteresis")
    if hysteresis is not None:
        rates.append((hysteresis.share * peak + hysteresis.constant)
                     / (hysteresis.smoothing_velocity * m2))
    pin = model.effect("metering pin")
    rebound = model.effect("rebound orifice")
    largest = smallest = model.orifice.coefficient if model.orifice is not None else 0.0
    if pin is not None:
        pinned = [orifice_coefficient(pin.hydraulic_area, area, pin.discharge, pin.density)
                  for area in pin.areas]
        largest, smallest = max(pinned), min(pinned)
    if rebound is not None:
        largest += rebound.extra_coefficient
        rates.append(rebound.linear / m2)
    rates.append(2.0 * largest * abs(contact_velocity) / m2)
    if leg is not None:
        mass = min(leg.axle_mass, m2) if leg.above else m2
        rates += [math.sqrt(leg.stiffness / mass), leg.damping / mass]
    friction = model.effect("seal friction")
    if friction is not None:
        resting = (model.upper_mass * STANDARD_GRAVITY - model.lift) * math.cos(model.inclination)
        level = (friction.constant + abs(friction.breakaway)
                 + friction.pressure_factor * max(model.gas.preload, resting))
        rates.append(level / (friction.smoothing_velocity * m2))
    oil = model.effect("oil compressibility")
    if oil is not None and smallest > 0:
        rates.append(oil.stiffness / math.sqrt(smallest * oil.smoothing_force))
    platform = model.effect("platform compliance")
    if platform is not None:
        rates += [math.sqrt(platform.stiffness / platform.mass),
                  platform.damping / platform.mass]
    return max(rates)


#: Below this step the batched path refuses to run: the model is too stiff for it.
MIN_STEP = 1.0e-6


def batch_step(models, contact_velocities, sample_rate: float) -> float:
    """The batched path's step: the longest whole fraction of the sample interval within
    MAX_STEP and the stability limit of every drop's fastest rate."""
    rate = max(fastest_rate(m, v) for m, v in zip(models, contact_velocities))
    step = min(MAX_STEP, STABILITY / rate)
    if step < MIN_STEP:
        raise SimulationError(f"the model is too stiff for the batched path: its fastest rate "
                              f"{rate:.3g} 1/s needs a step of {step:.2g} s (below "
                              f"{MIN_STEP:g} s); check very small masses or very stiff "
                              f"elements")
    return 1.0 / (sample_rate * math.ceil(1.0 / (sample_rate * step) - 1e-9))


def simulate_batch(models, contact_velocity, duration: float = 2.0,
                   sample_rate: float = 1000.0, step: float | None = None) -> BatchDrops:
    """Simulate many drops at once with classical RK4 at a fixed step (compiled, parallel).

    Parameters
    ----------
    models : DropModel or sequence of DropModel
        One model for every drop, or one per drop (parameter sets, effects may differ).
    contact_velocity : float or array
        One per drop (broadcast against ``models``).
    step : float, optional
        Integration step [s]; default :func:`batch_step`.  Must divide the sample interval.

    Output starts at contact (no free-fall lead).
    """
    models = [models] if isinstance(models, DropModel) else list(models)
    velocity = np.atleast_1d(np.asarray(contact_velocity, dtype=float))
    count = max(len(models), velocity.size)
    if len(models) == 1:
        models = models * count
    if velocity.size == 1:
        velocity = np.full(count, velocity[0])
    if len(models) != count or velocity.size != count:
        raise ValueError("give one model, or one per contact velocity")
    step = batch_step(models, velocity, sample_rate) if step is None else step
    per_sample = int(round(1.0 / (sample_rate * step)))
    if not np.isclose(per_sample * step * sample_rate, 1.0):
        raise ValueError("the step must divide the sample interval")
    samples = int(round(duration * sample_rate)) + 1
    parameters = np.array([m.pack() for m in models])
    initial = np.array([m.initial_state(v) for m, v in zip(models, velocity)])
    out, final = dyn.integrate_batch(parameters, initial, step, per_sample, samples,
                                     np.empty(0))
    fall = velocity ** 2 / (2 * STANDARD_GRAVITY)
    drops = BatchDrops(
        time=np.arange(samples) / sample_rate, load=out[:, :, dyn.LOAD],
        stroke=out[:, :, dyn.STROKE], tyre=out[:, :, dyn.TYRE],
        acceleration=out[:, :, dyn.ACCELERATION],
        displacement=out[:, :, dyn.DISPLACEMENT] - out[:, :1, dyn.DISPLACEMENT] + fall[:, None],
        mechanical=out[:, :, dyn.ENERGY] - out[:, :1, dyn.ENERGY],
        dissipated=final[:, dyn.DISSIPATED])
    for index, model in enumerate(models):   # effects on the recorded channels
        for effect in model.effects:
            for name in RECORDED:
                values = getattr(drops, name)
                values[index] = effect.recorded(1.0 / sample_rate, name, values[index])
    return drops



@dataclass
class DrivenResponse:
    """Response of one gear to a prescribed ground load (shared sample times [s], SI)."""

    time: np.ndarray
    load: np.ndarray      # the applied ground load [N]
    stroke: np.ndarray    # strut stroke [m]
    tyre: np.ndarray      # quasi-static tyre deflection under the applied load [m]
    acceleration: np.ndarray
    displacement: np.ndarray


def static_state(model: DropModel) -> np.ndarray:
    """State of the unit resting on its wheel, friction-free, velocities zero.

    The strut sits at the gas law's equilibrium under the upper mass's weight less lift
    (or on its top-out stop when the preload holds that); a flexible leg carries the
    weight above it.  Positions are measured from this configuration's axle.
    """
    y = np.zeros(dyn.STATES)
    cos_theta = math.cos(model.inclination)
    load = (model.upper_mass * STANDARD_GRAVITY - model.lift) * cos_theta
    stroke = model.static_stroke()
    if stroke == 0.0:  # topped out: the stop carries preload − load
        stroke = -(model.gas.preload - load) / model.stops.top_out_stiffness(model.gas.preload)
    y[dyn.Z1] = stroke * cos_theta
    y[dyn.THETA] = 1.0
    leg = model.effect("leg flexibility")
    if leg is not None and leg.above:      # the strut below the leg's mass, the spring above
        y[dyn.ZW] = y[dyn.Z1]
        y[dyn.Z1] += ((model.upper_mass - leg.axle_mass) * STANDARD_GRAVITY
                      - model.lift) / leg.stiffness
    elif leg is not None:
        above = model.total_mass * STANDARD_GRAVITY - model.lift - leg.axle_mass * STANDARD_GRAVITY
        y[dyn.Z2] = above / leg.stiffness
        y[dyn.Z1] += y[dyn.Z2]
    return y


def simulate_driven(model: DropModel, time: np.ndarray, force: np.ndarray,
                    step: float | None = None) -> DrivenResponse:
    """The gear driven by a prescribed ground load (the tyre contact replaced by it).

    The plant of the small-signal (Wiener) identification: input the vertical load
    ``force`` [N] at the uniformly spaced ``time`` [s], outputs stroke and tyre deflection
    on the same grid.  The unit starts at rest in :func:`static_state`; the tyre
    deflection is the static curve's inverse at the applied load (tyre damping and
    hysteresis act on the platform contact, which the drive replaces).
    """
    time = np.asarray(time, dtype=float)
    force = np.asarray(force, dtype=float)
    if time.ndim != 1 or time.shape != force.shape or time.size < 2:
        raise ValueError("give time and force as 1-D arrays of the same length (two or more)")
    interval = float(time[1] - time[0])
    if not np.allclose(np.diff(time), interval, rtol=1e-9, atol=0.0) or interval <= 0:
        raise ValueError("the drive's time must be uniformly spaced and increasing")
    if not np.all(np.isfinite(force)):
        raise ValueError("the drive force must be finite")
    sample_rate = 1.0 / interval
    velocity = 0.0
    step = batch_step([model], [velocity + 0.5], sample_rate) if step is None else step
    per_sample = int(round(interval / step))
    if not np.isclose(per_sample * step, interval):
        raise ValueError("the step must divide the sample interval")
    fine = np.linspace(time[0], time[-1], 2 * per_sample * (time.size - 1) + 1)
    drive = np.interp(fine, time, force)
    out, _ = dyn.integrate_batch(model.pack()[None, :], static_state(model)[None, :], step,
                                 per_sample, time.size, drive)
    out = out[0]
    return DrivenResponse(time=time, load=out[:, dyn.LOAD], stroke=out[:, dyn.STROKE],
                          tyre=out[:, dyn.TYRE], acceleration=out[:, dyn.ACCELERATION],
                          displacement=out[:, dyn.DISPLACEMENT])
