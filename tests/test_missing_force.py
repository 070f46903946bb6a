"""The model-free missing force reads the mark of an effect from records built by hand.

The records are not simulated: stroke and tyre deflection are smooth functions of time
(sin² pulses), and the load follows from force laws written out here, apart from
certkit.physics.dynamics: the lower mass's balance F_V = F_s + m2·(g − δ̈) with a strut
force that has a friction step the nominal law lacks, or a tyre law with a loop of
constant width it lacks.  The fitted shapes must find what was put in, and nothing else.
"""

import math

import numpy as np
import pytest

from certkit.gap.missing_force import missing_force, signatures

from .test_drop_model import seed_gear

G = 9.80665
P_ATM = 101325.0
RATE = 1000.0


def _motion():
    """Stroke and tyre deflection: a compression and extension (sin² over 0.2 s and 0.16 s)
    and a small second bounce, so that the drop's phases can be found."""
    t = np.arange(-0.05, 0.6, 1.0 / RATE)
    def pulse(start, length, height):
        inside = (t >= start) & (t <= start + length)
        return np.where(inside, height * np.sin(math.pi * (t - start) / length) ** 2, 0.0)
    stroke = pulse(0.0, 0.2, 0.06) + pulse(0.2, 0.1, 0.004)
    tyre = pulse(0.0, 0.16, 0.03) + pulse(0.2, 0.1, 0.003)
    return t, stroke, tyre


def _derivatives(t, x):
    first = np.gradient(x, t)
    return first, np.gradient(first, t)


def _nominal_strut(model, s, v):
    """Gas spring with absolute pressures and square-law damping, written out."""
    gas = model.gas
    pressure = gas.precharge * (gas.volume / (gas.volume - gas.area * s)) ** gas.exponent
    return gas.area * (pressure - P_ATM) + model.orifice.coefficient * v * np.abs(v)


def _nominal_tyre(model, d, rate):
    tyre = model.tyre
    static = tyre.reference_load * (np.maximum(d, 0) / tyre.reference_deflection) ** tyre.exponent
    return static * (1 + tyre.damping * rate)


def _model():
    from dataclasses import replace

    return replace(seed_gear(friction=False), effects=())


def _weight(model):
    return (model.upper_mass + model.lower_mass) * G


def test_a_friction_step_is_read_from_the_strut_balance():
    model = _model()
    t, s, d = _motion()
    v, _ = _derivatives(t, s)
    _, d_acc = _derivatives(t, d)
    friction = 300.0 * np.tanh(v / 0.002)
    strut = np.where(t >= 0, _nominal_strut(model, s, v) + friction, 0.0)
    load = np.where(t >= 0, strut + model.lower_mass * (G - d_acc), 0.0)
    found = missing_force("R1", t, load, s, d, model, _weight(model))
    assert found is not None and found.time.size > 100
    by_shape = {g.shape: g for g in signatures([found]) if g.force == "strut"}
    step = by_shape["step with sign(ṡ)"]
    assert step.seen and step.coefficient == pytest.approx(300.0, rel=0.1)
    assert not by_shape["ṡ|ṡ| on extension only"].seen


def test_a_constant_tyre_loop_is_read_from_the_tyre_balance():
    model = _model()
    t, s, d = _motion()
    rate, _ = _derivatives(t, d)
    loop = 250.0 * (1 - np.exp(-np.maximum(d, 0) / 0.002)) * np.tanh(rate / 0.005)
    load = np.where(t >= 0, _nominal_tyre(model, d, rate) + loop, 0.0)
    found = missing_force("R1", t, load, s, d, model, _weight(model))
    by_shape = {g.shape: g for g in signatures([found]) if g.force == "tyre"}
    constant = by_shape["loop of constant width × sign(δ̇)"]
    assert constant.seen and constant.coefficient == pytest.approx(250.0, rel=0.15)
    assert by_shape["loop of constant width × sign(δ̇)"].share > \
        by_shape["loop ∝ static curve × sign(δ̇)"].share


def test_records_the_nominal_laws_explain_show_no_mark():
    model = _model()
    t, s, d = _motion()
    v, _ = _derivatives(t, s)
    rate, d_acc = _derivatives(t, d)
    strut = _nominal_strut(model, s, v)
    load = np.where(t >= 0, strut + model.lower_mass * (G - d_acc), 0.0)
    found = missing_force("R1", t, load, s, d, model, _weight(model))
    assert not any(g.seen for g in signatures([found]) if g.force == "strut")
