"""The equations of motion of one gear unit in a drop, compiled (numba): the one home of
the model's force laws.

The model objects of :mod:`certkit.physics.drop_model` and :mod:`certkit.physics.effects` hold the named
parameters, their units and their documentation; :meth:`DropModel.pack` writes them into
a flat parameter vector ``p`` with the slots below, and the functions here evaluate the
forces and state rates from it.  Both simulation paths (scipy's LSODA for one drop, the
batched fixed-step RK4) call the same :func:`rates`, so they differ only in the
integrator.  An optional effect that is off has its slots at their neutral values (zero
force, flag 0), so one compiled function serves every combination of effects.

Coordinates: z positive downward from the configuration at first tyre
contact.  z1 upper (sprung) mass, z2 lower (unsprung) mass, zw the third mass of a
flexible leg (the axle, or the strut's cylinder when the leg's flexibility lies above
the strut), zp the platform when it is compliant (else rigid at 0).  Stroke
s = (z1 − z2)/cos θ (with the leg above the strut: (zw − z2)/cos θ), compression
positive; tyre deflection δ = zw − zp (leg above the strut, or no leg: z2 − zp).
Equations (seed eqs. 6-7 corrected, as in :mod:`certkit.physics.drop_model`)::

    m1·z1'' = m1·g − L − F_s/cos θ
    m2·z2'' = m2·g + F_s/cos θ − F_leg          (F_leg = F_V without a flexible leg)
    mw·zw'' = mw·g + F_leg − F_V                 (flexible leg at the axle only)
    mp·zp'' = F_V − k_p·zp − c_p·zp'             (compliant platform only; zp from its
                                                  static position, so its weight cancels)

and with the leg's flexibility above the strut (F_leg = k_l·(z1 − zw) + c_l·(z1' − zw'))::

    m1·z1'' = m1·g − L − F_leg
    mw·zw'' = mw·g + F_leg − F_s/cos θ
    m2·z2'' = m2·g + F_s/cos θ − F_V

F_s is the sum of the strut terms (gas spring, hydraulic damping, end stops, seal
friction); F_V the tyre force, clipped at zero so the wheel may leave the platform.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from certkit.compliance.servicing import STANDARD_ATMOSPHERE

P_ATM = STANDARD_ATMOSPHERE  # Pa, standard atmosphere (ISO 2533)
G = 9.80665             # m/s^2, standard gravity
VOLUME_FLOOR = 0.02     # the gas volume never falls below 2 % of V0 (keeps the law finite)
PIN_POINTS = 16         # largest metering-pin table
#: LLVM fast-math flags of the compiled kernels: none, strict IEEE evaluation.  Contraction
#: (a fused multiply-add where the processor has one) and reassociation (sums reordered to
#: the processor's vector width) would make the last bits, and through a fit's path its
#: outcome, depend on the machine; measured on this code (numba 0.68, 40 drops of the seed
#: gear, one thread), they gained nothing: 0.161 s with them, 0.160 s without.
FAST = False

# --------------------------------------------------------------------------- parameter slots
M1, M2, LIFT, COS = 0, 1, 2, 3                       # kg, kg, N, 1
GAS_AREA, GAS_VOLUME, GAS_PRECHARGE, GAS_EXPONENT = 4, 5, 6, 7   # m^2, m^3, Pa abs, 1
THERMAL, GAS_GAMMA, GAS_COOLING = 8, 9, 10           # flag, c_p/c_v, 1/τ [1/s]
ORIFICE_K, REBOUND_EXTRA = 11, 12                    # N·s²/m², N·s²/m²
STOP_TRAVEL, STOP_STIFFNESS, STOP_DAMPING = 13, 14, 15
TYRE_LOAD, TYRE_DEFLECTION, TYRE_EXPONENT, TYRE_DAMPING = 16, 17, 18, 19
HYSTERESIS, HYSTERESIS_VELOCITY = 20, 21
FRICTION, FRICTION_PRESSURE, FRICTION_BREAKAWAY = 22, 23, 24
FRICTION_STRIBECK, FRICTION_SMOOTHING = 25, 26
LEG, LEG_MASS, LEG_STIFFNESS, LEG_DAMPING = 27, 28, 29, 30
PLATFORM, PLATFORM_MASS, PLATFORM_STIFFNESS, PLATFORM_DAMPING = 31, 32, 33, 34
OIL, OIL_STIFFNESS, OIL_SMOOTHING = 35, 36, 37
PIN, PIN_COUNT, PIN_COEFFICIENT = 38, 39, 40         # flag, n, ρ·A_h³/(2·C_d²) [N·s²]
PIN_STROKES = 41                                      # PIN_POINTS strokes [m]
PIN_AREAS = PIN_STROKES + PIN_POINTS                  # PIN_POINTS areas [m^2]
HYSTERESIS_CONSTANT = PIN_AREAS + PIN_POINTS          # N, a tyre loop of constant amplitude
HYSTERESIS_ONSET = HYSTERESIS_CONSTANT + 1            # m, deflection over which it builds up
REBOUND_LINEAR = HYSTERESIS_CONSTANT + 2              # N·s/m, linear rebound damping
LEG_ABOVE = HYSTERESIS_CONSTANT + 3                   # flag: the flexible leg above the strut
HYSTERESIS_MEMORY = HYSTERESIS_CONSTANT + 4           # flag: the loop switches with deflection
TOP_OUT_STIFFNESS = HYSTERESIS_CONSTANT + 5           # N/m, the top-out stop's spring
HANG = HYSTERESIS_CONSTANT + 6                        # m, recorded zero (< 0: compliant top-out)
SLOTS = HYSTERESIS_CONSTANT + 7

# --------------------------------------------------------------------------- state slots
Z1, V1, Z2, V2, ZW, VW, ZP, VP, THETA, OIL_FORCE = range(10)
DISSIPATED, STRUT_WORK, TYRE_WORK = 10, 11, 12       # works integrated alongside [J]
LOOP = 13                                            # the tyre loop's switch w ∈ [−1, 1]
STATES = 14

# --------------------------------------------------------------------------- output channels
LOAD, STROKE, TYRE, ACCELERATION, DISPLACEMENT, ENERGY = range(6)
CHANNELS = 6


@njit(cache=True, error_model="numpy", fastmath=FAST)
def _gas_pressure(p, stroke, theta):
    """Absolute gas pressure: polytropic (seed eq. 3 corrected) or with heat transfer."""
    v0 = p[GAS_VOLUME]
    volume = max(v0 - p[GAS_AREA] * stroke, VOLUME_FLOOR * v0)
    if p[THERMAL] > 0.0:
        return p[GAS_PRECHARGE] * (v0 / volume) * theta   # ideal gas, T/T0 = θ
    return p[GAS_PRECHARGE] * (v0 / volume) ** p[GAS_EXPONENT]


@njit(cache=True, error_model="numpy", fastmath=FAST)
def _hydraulic_coefficient(p, stroke, direction):
    """K of the square-law hydraulic damping F_h = K·ṡ|ṡ| for the flow's direction."""
    if p[PIN] > 0.0:
        count = int(p[PIN_COUNT])
        strokes = p[PIN_STROKES:PIN_STROKES + count]
        areas = p[PIN_AREAS:PIN_AREAS + count]
        area = np.interp(stroke, strokes, areas)
        k = p[PIN_COEFFICIENT] / (area * area)
    else:
        k = p[ORIFICE_K]
    if direction < 0.0:
        k += p[REBOUND_EXTRA]
    return k


@njit(cache=True, error_model="numpy", fastmath=FAST)
def _stop_force(p, stroke, rate):
    """Top-out (s < 0) and bottoming (s > s_max) stops: one-sided springs, with damping
    unless the top-out stop is compliant (an elastic pad: p[HANG] < 0)."""
    damping = p[STOP_DAMPING]
    if stroke < 0.0:
        penetration, stiffness = stroke, p[TOP_OUT_STIFFNESS]
        if p[HANG] < 0.0:
            damping = 0.0
    elif stroke > p[STOP_TRAVEL]:
        penetration, stiffness = stroke - p[STOP_TRAVEL], p[STOP_STIFFNESS]
    else:
        return 0.0, 0.0
    spring = stiffness * penetration
    force = spring + damping * rate
    force = min(force, 0.0) if penetration < 0.0 else max(force, 0.0)  # a stop never pulls
    return force, spring


@njit(cache=True, error_model="numpy", fastmath=FAST)
def _friction(p, rate, gas_force):
    """Seal friction: Coulomb plus Stribeck, regularised by tanh(ṡ/v_ε)."""
    level = p[FRICTION] + p[FRICTION_PRESSURE] * abs(gas_force)
    if p[FRICTION_BREAKAWAY] != 0.0:
        level += p[FRICTION_BREAKAWAY] * math.exp(-(rate / p[FRICTION_STRIBECK]) ** 2)
    return level * math.tanh(rate / p[FRICTION_SMOOTHING])


@njit(cache=True, error_model="numpy", fastmath=FAST)
def _tyre_static(p, deflection):
    if deflection <= 0.0:
        return 0.0
    return p[TYRE_LOAD] * (deflection / p[TYRE_DEFLECTION]) ** p[TYRE_EXPONENT]


@njit(cache=True, error_model="numpy", fastmath=FAST)
def _tyre_force(p, deflection, rate, loop):
    """F_V = max(0, f(δ)·(1 + C_T·δ̇) + (h·f(δ) + H·b(δ))·σ) (seed eq. 5 with a hysteresis
    loop whose half-width is a share h of the static curve, a constant H, or both).

    The loop's switch σ is tanh(δ̇/v_h) with b(δ) = 1 − e^(−δ/δ_H) (rate-switched), or,
    with memory, the state ``loop`` = w of Dahl's rate-independent law with b = 1 (see
    :func:`_loop_rate`), which keeps its value when the tyre comes to rest."""
    static = _tyre_static(p, deflection)
    force = static * (1.0 + p[TYRE_DAMPING] * rate)
    width = p[HYSTERESIS] * static
    memory = p[HYSTERESIS_MEMORY] > 0.0
    if p[HYSTERESIS_CONSTANT] != 0.0 and deflection > 0.0:
        width += p[HYSTERESIS_CONSTANT] * (
            1.0 if memory else 1.0 - math.exp(-deflection / p[HYSTERESIS_ONSET]))
    if width != 0.0:
        force += width * (loop if memory else math.tanh(rate / p[HYSTERESIS_VELOCITY]))
    return max(force, 0.0), static


@njit(cache=True, error_model="numpy", fastmath=FAST)
def _loop_rate(p, deflection, rate, loop):
    """Dahl's law for the loop's switch (P. R. Dahl, "A solid friction model", Aerospace
    Corp. TOR-0158(3107-18)-1, 1968, with the force normalised by its limit):
    w' = (δ̇/δ_H)·(1 − w·tanh(δ̇/v_h)) on the platform, so w runs to ±1 within a few δ_H
    of deflection in either direction; off it the switch relaxes to 0 within 5 ms."""
    if deflection <= 0.0:
        return -loop / 0.005
    return rate / p[HYSTERESIS_ONSET] * (1.0 - loop * math.tanh(rate / p[HYSTERESIS_VELOCITY]))


@njit(cache=True, error_model="numpy", fastmath=FAST)
def _stroke(p, y):
    """Stroke and stroke rate: between the upper and lower masses, or between the leg's
    mass and the lower mass when the leg's flexibility lies above the strut."""
    if p[LEG] > 0.0 and p[LEG_ABOVE] > 0.0:
        return (y[ZW] - y[Z2]) / p[COS], (y[VW] - y[V2]) / p[COS]
    return (y[Z1] - y[Z2]) / p[COS], (y[V1] - y[V2]) / p[COS]


@njit(cache=True, error_model="numpy", fastmath=FAST)
def _evaluate(p, y, dy, driven, drive_force):
    """State rates into ``dy``; returns the tyre (or applied) force on the axle [N].

    ``driven``: the tyre contact is replaced by the applied upward force ``drive_force``.
    """
    cos_t = p[COS]
    leg = p[LEG] > 0.0
    above = leg and p[LEG_ABOVE] > 0.0
    platform = p[PLATFORM] > 0.0
    stroke, rate = _stroke(p, y)
    z_axle, v_axle = (y[ZW], y[VW]) if leg and not above else (y[Z2], y[V2])

    # strut: gas spring, hydraulic damping, stops, friction
    pressure = _gas_pressure(p, stroke, y[THETA])
    gas = p[GAS_AREA] * (pressure - P_ATM)
    dissipation = 0.0
    if p[OIL] > 0.0:
        # oil column as a spring in series with the orifice: F_h is a state,
        # dF_h/dt = k_oil·(ṡ − q) with the orifice flow q from K·q|q| = F_h, regularised as
        # q = F_h/√(K·√(F_h² + F_ε²)) (relative error (F_ε/F_h)²/4 away from zero)
        hydraulic = y[OIL_FORCE]
        k = _hydraulic_coefficient(p, stroke, hydraulic)
        flow = (hydraulic / math.sqrt(k * math.hypot(hydraulic, p[OIL_SMOOTHING])) if k > 0.0
                else rate)
        dy[OIL_FORCE] = p[OIL_STIFFNESS] * (rate - flow)
        dissipation += hydraulic * flow
    else:
        k = _hydraulic_coefficient(p, stroke, rate)
        hydraulic = k * rate * abs(rate)
        dy[OIL_FORCE] = 0.0
        dissipation += hydraulic * rate
    if p[REBOUND_LINEAR] != 0.0 and rate < 0.0:
        linear = p[REBOUND_LINEAR] * rate          # laminar share of the rebound valve
        hydraulic += linear
        dissipation += linear * rate
    stop, stop_spring = _stop_force(p, stroke, rate)
    friction = 0.0
    if p[FRICTION] != 0.0 or p[FRICTION_PRESSURE] != 0.0 or p[FRICTION_BREAKAWAY] != 0.0:
        friction = _friction(p, rate, gas)
    strut = gas + hydraulic + stop + friction
    dissipation += (stop - stop_spring + friction) * rate

    if p[THERMAL] > 0.0:
        # gas energy equation, m·c_v·T' = −p·V' − hA·(T − T_w), with T/T0 = θ:
        # θ' = (γ − 1)·p·A·ṡ/(p0·V0) + (1 − θ)/τ.  Past the volume floor the piston's work
        # still heats the gas, so the energy balance stays exact there too.
        v0 = p[GAS_VOLUME]
        compression = p[GAS_AREA] * rate
        internal = p[GAS_PRECHARGE] * v0 / (p[GAS_GAMMA] - 1.0)       # m·c_v·T0
        dy[THETA] = (pressure * compression / internal
                     + (1.0 - y[THETA]) * p[GAS_COOLING])
        dissipation += internal * (y[THETA] - 1.0) * p[GAS_COOLING]   # heat to the walls
    else:
        dy[THETA] = 0.0

    # ground: tyre on the (rigid or compliant) platform, or a prescribed force
    deflection = z_axle - y[ZP]
    deflection_rate = v_axle - y[VP]
    if driven:
        ground = drive_force
        dy[TYRE_WORK] = 0.0
    else:
        ground, static = _tyre_force(p, deflection, deflection_rate, y[LOOP])
        dissipation += (ground - static) * deflection_rate            # tyre damping, loop
        dy[TYRE_WORK] = ground * deflection_rate
    dy[LOOP] = (_loop_rate(p, deflection, deflection_rate, y[LOOP])
                if p[HYSTERESIS_MEMORY] > 0.0 and not driven else 0.0)

    vertical = strut / cos_t
    dy[Z1] = y[V1]
    dy[V1] = G - (p[LIFT] + vertical) / p[M1]
    dy[Z2] = y[V2]
    if above:
        leg_force = (p[LEG_STIFFNESS] * (y[Z1] - y[ZW]) + p[LEG_DAMPING] * (y[V1] - y[VW]))
        dissipation += p[LEG_DAMPING] * (y[V1] - y[VW]) ** 2
        dy[V1] = G - (p[LIFT] + leg_force) / p[M1]
        dy[ZW] = y[VW]
        dy[VW] = G + (leg_force - vertical) / p[LEG_MASS]
        dy[V2] = G + (vertical - ground) / p[M2]
    elif leg:
        leg_force = (p[LEG_STIFFNESS] * (y[Z2] - y[ZW]) + p[LEG_DAMPING] * (y[V2] - y[VW]))
        dissipation += p[LEG_DAMPING] * (y[V2] - y[VW]) ** 2
        dy[V2] = G + (vertical - leg_force) / p[M2]
        dy[ZW] = y[VW]
        dy[VW] = G + (leg_force - ground) / p[LEG_MASS]
    else:
        dy[V2] = G + (vertical - ground) / p[M2]
        dy[ZW] = 0.0
        dy[VW] = 0.0
    if platform and not driven:
        dy[ZP] = y[VP]
        dy[VP] = (ground - p[PLATFORM_STIFFNESS] * y[ZP]
                  - p[PLATFORM_DAMPING] * y[VP]) / p[PLATFORM_MASS]
        dissipation += p[PLATFORM_DAMPING] * y[VP] ** 2
    else:
        dy[ZP] = 0.0
        dy[VP] = 0.0
    dy[DISSIPATED] = dissipation
    dy[STRUT_WORK] = strut * rate
    return ground


@njit(cache=True, error_model="numpy", fastmath=FAST)
def rates(p, y, dy):
    """Free drop: state rates of ``y`` into ``dy`` (both length STATES)."""
    _evaluate(p, y, dy, False, 0.0)


@njit(cache=True, error_model="numpy", fastmath=FAST)
def driven_rates(p, y, dy, force):
    """Ground-load drive: the tyre contact replaced by the applied upward ``force`` [N]."""
    _evaluate(p, y, dy, True, force)


@njit(cache=True, error_model="numpy", fastmath=FAST)
def stored_energy(p, y):
    """Kinetic + stored − gravity work + lift work, from the contact configuration [J]."""
    leg = p[LEG] > 0.0
    above = leg and p[LEG_ABOVE] > 0.0
    stroke, _ = _stroke(p, y)
    z_axle = y[ZW] if leg and not above else y[Z2]
    kinetic = 0.5 * (p[M1] * y[V1] ** 2 + p[M2] * y[V2] ** 2)
    gravity = G * (p[M1] * y[Z1] + p[M2] * y[Z2])
    stored = 0.0
    if leg:
        kinetic += 0.5 * p[LEG_MASS] * y[VW] ** 2
        gravity += G * p[LEG_MASS] * y[ZW]
        stored += 0.5 * p[LEG_STIFFNESS] * ((y[Z1] if above else y[Z2]) - y[ZW]) ** 2
    if p[PLATFORM] > 0.0:
        kinetic += 0.5 * p[PLATFORM_MASS] * y[VP] ** 2
        stored += 0.5 * p[PLATFORM_STIFFNESS] * y[ZP] ** 2
    # gas: polytropic work ∫p dV or, with heat transfer, the internal energy m·c_v·(T − T0)
    v0, p0 = p[GAS_VOLUME], p[GAS_PRECHARGE]
    if p[THERMAL] > 0.0:
        stored += p0 * v0 / (p[GAS_GAMMA] - 1.0) * (y[THETA] - 1.0)
    else:
        # ∫p dV down to the volume floor, then the floor's constant pressure times travel
        floor = (1.0 - VOLUME_FLOOR) * v0 / p[GAS_AREA]
        ratio = v0 / (v0 - p[GAS_AREA] * min(stroke, floor))
        n = p[GAS_EXPONENT]
        stored += (p0 * v0 * math.log(ratio) if n == 1.0
                   else p0 * v0 * (ratio ** (n - 1.0) - 1.0) / (n - 1.0))
        if stroke > floor:
            stored += p0 * ratio ** n * p[GAS_AREA] * (stroke - floor)
    stored -= P_ATM * p[GAS_AREA] * stroke
    if p[OIL] > 0.0:
        stored += 0.5 * y[OIL_FORCE] ** 2 / p[OIL_STIFFNESS]
    _, stop_spring = _stop_force(p, stroke, 0.0)
    if stroke < 0.0:
        stored += 0.5 * stop_spring * stroke
    elif stroke > p[STOP_TRAVEL]:
        stored += 0.5 * stop_spring * (stroke - p[STOP_TRAVEL])
    deflection = z_axle - y[ZP]
    if deflection > 0.0:
        stored += (p[TYRE_LOAD] * p[TYRE_DEFLECTION] / (p[TYRE_EXPONENT] + 1.0)
                   * (deflection / p[TYRE_DEFLECTION]) ** (p[TYRE_EXPONENT] + 1.0))
    return kinetic + stored - gravity + p[LIFT] * y[Z1]


@njit(cache=True, error_model="numpy", fastmath=FAST)
def channels(p, y, out, driven, drive_force):
    """The recorded channels at state ``y`` into ``out`` (length CHANNELS).

    LOAD is what the platform's load cells read (the tyre force on a rigid platform, the
    cells' spring and damper force on a compliant one, the applied force when driven);
    ACCELERATION is the drop mass's kinematic acceleration, positive upward; DISPLACEMENT
    the drop mass's travel from contact, positive downward; ENERGY the mechanical-energy
    balance (kinetic + stored − gravity work + lift work) from contact.
    """
    dy = np.empty(STATES)
    ground = _evaluate(p, y, dy, driven, drive_force)
    z_axle = y[ZW] if p[LEG] > 0.0 and p[LEG_ABOVE] == 0.0 else y[Z2]
    if driven:
        out[LOAD] = drive_force
        # quasi-static tyre: the deflection its static curve gives under the applied load
        out[TYRE] = (p[TYRE_DEFLECTION] * (drive_force / p[TYRE_LOAD]) ** (1.0 / p[TYRE_EXPONENT])
                     if drive_force > 0.0 else 0.0)
    else:
        out[LOAD] = (p[PLATFORM_STIFFNESS] * y[ZP] + p[PLATFORM_DAMPING] * y[VP]
                     if p[PLATFORM] > 0.0 else ground)
        out[TYRE] = max(z_axle - y[ZP], 0.0)
    # read from the hang on a compliant top-out, never below 0 on a rigid one
    # (EndStops.recorded_zero)
    out[STROKE] = _stroke(p, y)[0] - p[HANG] if p[HANG] < 0.0 else max(_stroke(p, y)[0], 0.0)
    out[ACCELERATION] = -dy[V1]
    out[DISPLACEMENT] = y[Z1]
    out[ENERGY] = stored_energy(p, y)


@njit(cache=True, error_model="numpy", fastmath=FAST)
def _rk4_step(p, y, step, driven, force0, force_half, force1, k1, k2, k3, k4, work):
    _evaluate(p, y, k1, driven, force0)
    for i in range(STATES):
        work[i] = y[i] + 0.5 * step * k1[i]
    _evaluate(p, work, k2, driven, force_half)
    for i in range(STATES):
        work[i] = y[i] + 0.5 * step * k2[i]
    _evaluate(p, work, k3, driven, force_half)
    for i in range(STATES):
        work[i] = y[i] + step * k3[i]
    _evaluate(p, work, k4, driven, force1)
    for i in range(STATES):
        y[i] += step / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])


@njit(cache=True, parallel=True, error_model="numpy", fastmath=FAST)
def integrate_batch(parameters, initial, step, per_sample, samples, drive):
    """Fixed-step classical RK4 over many drops at once (one row of ``parameters`` each).

    ``drive`` is empty for free drops, else the applied ground force at every step and
    half step (length 2·per_sample·(samples − 1) + 1), shared by all drops.  Returns the
    channels, shape (drops, samples, CHANNELS), and the final states.
    """
    drops = parameters.shape[0]
    out = np.empty((drops, samples, CHANNELS))
    final = np.empty((drops, STATES))
    driven = drive.size > 0
    for d in prange(drops):
        p = parameters[d]
        y = initial[d].copy()
        k1, k2, k3, k4 = np.empty(STATES), np.empty(STATES), np.empty(STATES), np.empty(STATES)
        work = np.empty(STATES)
        row = np.empty(CHANNELS)
        channels(p, y, row, driven, drive[0] if driven else 0.0)
        out[d, 0] = row
        index = 0
        for sample in range(1, samples):
            for _ in range(per_sample):
                f0 = drive[index] if driven else 0.0
                fh = drive[index + 1] if driven else 0.0
                f1 = drive[index + 2] if driven else 0.0
                _rk4_step(p, y, step, driven, f0, fh, f1, k1, k2, k3, k4, work)
                index += 2
            channels(p, y, row, driven, drive[index] if driven else 0.0)
            out[d, sample] = row
        final[d] = y
    return out, final


@njit(cache=True, error_model="numpy", fastmath=FAST)
def strut_and_tyre_forces(p, stroke, rate, deflection, deflection_rate, strut, gas_force,
                          tyre, tyre_static):
    """The strut's force law (gas spring at the pre-charge temperature, hydraulic damping
    as a square law, rebound damping, stops, seal friction) at given strokes and stroke
    rates, and the tyre's at given deflections and rates, into ``strut`` and ``tyre`` [N],
    with the gas spring's share and the static tyre curve into ``gas_force`` and
    ``tyre_static``: the force laws of :func:`rates` evaluated on recorded motion (the oil
    column, heat transfer, the extra degrees of freedom and the tyre loop's memory, which
    need states, are left out: a loop with memory is evaluated rate-switched)."""
    for i in range(stroke.size):
        s, v = stroke[i], rate[i]
        gas = p[GAS_AREA] * (_gas_pressure(p, s, 1.0) - P_ATM)
        k = _hydraulic_coefficient(p, s, v)
        force = gas + k * v * abs(v)
        if p[REBOUND_LINEAR] != 0.0 and v < 0.0:
            force += p[REBOUND_LINEAR] * v
        force += _stop_force(p, s, v)[0]
        if p[FRICTION] != 0.0 or p[FRICTION_PRESSURE] != 0.0 or p[FRICTION_BREAKAWAY] != 0.0:
            force += _friction(p, v, gas)
        strut[i], gas_force[i] = force, gas
        switch = (math.tanh(deflection_rate[i] / p[HYSTERESIS_VELOCITY])
                  if p[HYSTERESIS_VELOCITY] > 0.0 else 0.0)
        tyre[i], tyre_static[i] = _tyre_force(p, deflection[i], deflection_rate[i], switch)
