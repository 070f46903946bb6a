"""The independent drop simulator of the blind check (benchmarks/truthgen): written apart
from certkit, checked here against hand-derived expectations (free fall, static
equilibrium from the gas law and the tyre's power law, a reference integrator, exact
delays and mixtures) and for the one rule that makes it independent: it imports nothing
from certkit."""

import ast
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCHMARKS))
import truthgen as tg  # noqa: E402

G, P_ATM = 9.80665, 101325.0
AREA = 2.82743e-3
ORIFICE = 0.6 * math.pi / 4 * 0.0094 ** 2
K = 860 * AREA ** 3 / (2 * ORIFICE ** 2)
GEAR = tg.Gear(upper_mass=283.5, lower_mass=9.0, piston_area=AREA, gas_volume=6.5031e-4,
               precharge_abs=0.901325e6, polytropic_exponent=1.2, compression_coefficient=K,
               rebound_coefficient=K, tyre_reference_load=12471.77,
               tyre_reference_deflection=0.040, tyre_exponent=1.26, tyre_damping=0.05)
V25 = math.sqrt(2 * G * 0.25)
BARE = tg.Nuisances.none()


def test_it_imports_nothing_from_certkit():
    for path in sorted((BENCHMARKS / "truthgen").glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import)
                     else [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            assert not any(n.split(".")[0] == "certkit" for n in names), (path, names)


def test_samples_and_free_fall_before_contact():
    record = tg.simulate(GEAR, V25, 500.0, duration=1.0, lead=0.1)
    assert record.time.size == round(1.1 * 500)
    assert record.time[0] == pytest.approx(-0.1)
    assert record.time[1] - record.time[0] == pytest.approx(0.002)
    before = record.time < -1e-9
    # in the air: no load, no tyre deflection, the drop mass falls freely
    assert np.all(record.load[before] == 0.0) and np.all(record.tyre[before] == 0.0)
    np.testing.assert_allclose(record.acceleration[before], G, rtol=1e-9)
    t = record.time[before]
    np.testing.assert_allclose(record.displacement[before], V25 * t + 0.5 * G * t ** 2,
                               atol=1e-9)
    np.testing.assert_allclose(record.stroke[before], 0.0, atol=1e-9)


def test_static_equilibrium_from_the_gas_and_tyre_laws():
    """At rest the tyre carries the whole weight, δ = δ_ref·(W/P)^(1/b), and the gas the
    upper mass's: p0·(V0/(V0 − A·s))^n − p_atm = m1·g/A.  The orifice's square law barely
    damps the last small oscillation of the upper mass, so the means over the last 5 s."""
    damped = tg.Gear(**{**GEAR.__dict__, "tyre_damping": 2.0})
    record = tg.simulate(damped, 0.05, 200.0, duration=20.0, nuisances=BARE)
    weight = (GEAR.upper_mass + GEAR.lower_mass) * G
    rest = record.time > 15.0
    assert record.load[rest].mean() == pytest.approx(weight, rel=1e-3)
    assert record.tyre[rest].mean() == pytest.approx(0.040 * (weight / 12471.77) ** (1 / 1.26),
                                            rel=1e-3)
    gas = GEAR.upper_mass * G / AREA + P_ATM
    stroke = GEAR.gas_volume / AREA * (1 - (0.901325e6 / gas) ** (1 / 1.2))
    # the stroke channel is zeroed where the strut hangs (5e-5 m into the near-rigid stop)
    assert record.stroke[rest].mean() == pytest.approx(stroke + 5e-5, abs=2e-4)


def _reference(contact_velocity, duration):
    """The same textbook two-mass equations, integrated by scipy's Radau method from
    contact, with a rigid top-out stop (stroke clipped at zero while the gas preload
    holds the strut extended)."""
    m1, m2 = GEAR.upper_mass, GEAR.lower_mass

    def strut(s, v):
        ratio = GEAR.gas_volume / (GEAR.gas_volume - AREA * s)
        return (GEAR.precharge_abs * ratio ** 1.2 - P_ATM) * AREA + K * v * abs(v)

    def rates(t, y):
        x1, v1, x2, v2 = y
        s, v = x1 - x2, v1 - v2
        tyre = 0.0
        if x2 > 0:
            tyre = max(12471.77 * (x2 / 0.04) ** 1.26 * (1 + 0.05 * v2), 0.0)
        force = strut(s, v)
        if s <= 0 and v <= 0 and force > tyre * m1 / (m1 + m2):
            a = G - tyre / (m1 + m2)          # strut locked at full extension
            return [v1, a, v2, a]
        return [v1, G - force / m1, v2, G + (force - tyre) / m2]

    t = np.arange(0, duration, 1e-3)
    solution = solve_ivp(rates, (0, duration), [0, contact_velocity, 0, contact_velocity],
                         method="Radau", t_eval=t, rtol=1e-8, atol=1e-10, max_step=2e-4)
    return solution.y


def test_first_compression_agrees_with_a_reference_integrator():
    record = tg.simulate(GEAR, V25, 1000.0, duration=0.15, lead=0.0, nuisances=BARE)
    x1, v1, x2, v2 = _reference(V25, 0.15)
    peak = int(np.argmax(record.load))
    load = np.maximum(12471.77 * (np.maximum(x2, 0) / 0.04) ** 1.26 * (1 + 0.05 * v2), 0)
    assert record.load[peak] == pytest.approx(load.max(), rel=0.01)
    assert record.stroke.max() == pytest.approx((x1 - x2).max(), abs=0.5e-3)


def test_crosstalk_and_gas_drift_are_what_they_say():
    plain = tg.simulate(GEAR, V25, 1000.0, duration=0.5)
    mixed = tg.simulate(GEAR, V25, 1000.0, duration=0.5, truths=(tg.Truth("crosstalk", 0.1),))
    expected = plain.load.copy()
    expected[12:] += 0.1 * plain.load[:-12]
    np.testing.assert_allclose(mixed.load, expected, atol=1e-9)
    np.testing.assert_array_equal(mixed.stroke, plain.stroke)
    # the gas charge drifts with the drop's place in the sequence only
    drift = (tg.Truth("gas-drift", 0.05),)
    first = tg.simulate(GEAR, V25, 1000.0, duration=0.5, truths=drift, drop_index=0)
    np.testing.assert_array_equal(first.load, plain.load)
    warmer = tg.Gear(**{**GEAR.__dict__, "precharge_abs": GEAR.precharge_abs * 1.1})
    np.testing.assert_allclose(
        tg.simulate(GEAR, V25, 1000.0, duration=0.5, truths=drift, drop_index=2).load,
        tg.simulate(warmer, V25, 1000.0, duration=0.5).load, rtol=1e-12)


@pytest.mark.parametrize("form, lag", [("bessel-delay", 1.5), ("butterworth-delay", None)])
def test_sensor_lag_delays_every_channel(form, lag):
    """A 4th-order Bessel low-pass normalised for delay delays low frequencies by 1/ωc =
    size, plus the pure delay size/2: the peak arrives 1.5·size later."""
    size = 0.004
    plain = tg.simulate(GEAR, V25, 1000.0, duration=0.5)
    lagged = tg.simulate(GEAR, V25, 1000.0, duration=0.5, truths=(tg.Truth(form, size),))
    for channel in ("load", "stroke", "tyre", "displacement"):
        shift = (np.argmax(getattr(lagged, channel)) - np.argmax(getattr(plain, channel)))
        assert shift > 0, channel
        if lag is not None:
            assert shift == pytest.approx(lag * size * 1000, abs=1.5), channel


def test_every_form_changes_the_drop_more_as_it_grows_and_is_deterministic():
    plain = tg.simulate(GEAR, V25, 1000.0, duration=0.6)
    for form_id, form in tg.FORMS.items():
        low, high = form.sizes
        changes = []
        for size in np.geomspace(low, high, 4):
            record = tg.simulate(GEAR, V25, 1000.0, duration=0.6,
                                 truths=(tg.Truth(form_id, float(size)),), drop_index=3)
            assert np.all(np.isfinite(record.load)), form_id
            changes.append(float(np.sqrt(np.mean((record.load - plain.load) ** 2))))
        assert all(b > a for a, b in zip(changes, changes[1:])), (form_id, changes)
    one = tg.simulate(GEAR, V25, 1000.0, truths=(tg.Truth("lugre", 50.0),))
    two = tg.simulate(GEAR, V25, 1000.0, truths=(tg.Truth("lugre", 50.0),))
    assert one.load.tobytes() == two.load.tobytes()


def test_dissipative_forms_take_energy_out_of_the_first_compression():
    """Seal friction and a tyre loop dissipate: the strut strokes less; a softer leg
    lowers the peak load."""
    plain = tg.simulate(GEAR, V25, 1000.0, duration=0.6)
    for form in ("lugre", "dahl"):
        rubbing = tg.simulate(GEAR, V25, 1000.0, duration=0.6, truths=(tg.Truth(form, 300.0),))
        assert rubbing.stroke.max() < plain.stroke.max() - 1e-3, form
    soft = tg.simulate(GEAR, V25, 1000.0, duration=0.6, truths=(tg.Truth("leg-above", 5e-6),))
    assert soft.load.max() < plain.load.max()


def test_unknown_form_is_refused():
    with pytest.raises(ValueError, match="unknown truth form"):
        tg.simulate(GEAR, V25, 1000.0, truths=(tg.Truth("magic", 1.0),))


def test_certkits_nominal_model_agrees_with_it_over_the_whole_drop():
    """Two codes written apart, the same textbook physics (no nuisances, no effect beyond
    the rebound orifice): certkit's drop model of the seed gear and the independent
    simulator agree over the whole 1.5 s drop, not only at the peaks: measured 2.3 N RMS
    on a 13.5 kN peak, 0.07 mm of stroke (the two top-out stops differ) and 0.006 mm of
    tyre deflection; held to 0.05 % of the peak, 0.1 mm and 0.02 mm."""
    from certkit.physics.simulation import simulate_reference

    from .test_drop_model import PISTON, seed_gear

    model = seed_gear(friction=False)
    rebound = 860.0 * PISTON ** 3 / (2 * (0.6 * math.pi * 0.00665 ** 2 / 4) ** 2)
    gear = tg.Gear(upper_mass=283.5, lower_mass=9.0, piston_area=PISTON,
                   gas_volume=PISTON * 0.230, precharge_abs=0.8e6 + P_ATM,
                   polytropic_exponent=1.2, compression_coefficient=model.orifice.coefficient,
                   rebound_coefficient=rebound,
                   tyre_reference_load=7.2e5 * 0.04 ** 1.26, tyre_reference_deflection=0.04,
                   tyre_exponent=1.26, tyre_damping=0.05)
    speed = math.sqrt(2 * G * 0.25)
    theirs = tg.simulate(gear, speed, 1000.0, duration=1.5, lead=0.0, nuisances=BARE)
    ours = simulate_reference(model, speed, duration=1.5, lead=0.0)
    n = min(theirs.time.size, ours.time.size)
    rms = lambda a, b: float(np.sqrt(np.mean((a[:n] - b[:n]) ** 2)))  # noqa: E731
    assert rms(theirs.load, ours.load) < 5e-4 * ours.load.max()
    # the stroke channels differ by where each zeroes it (the hanging strut's stop)
    assert rms(theirs.stroke - theirs.stroke[0], ours.stroke - ours.stroke[0]) < 1e-4
    assert rms(theirs.tyre, ours.tyre) < 2e-5


@pytest.mark.parametrize("phase", [0.0, 0.3, 0.85])
def test_contact_falls_between_two_samples_at_its_phase(phase):
    """The logger's samples lie at −lead − phase/rate + k/rate: the last one before contact
    is phase/rate before it, in free fall (x = v·t + g·t²/2 from contact, by hand), and the
    next one, (1 − phase)/rate after contact, already loads the platform."""
    rate = 1000.0
    record = tg.simulate(GEAR, V25, rate, duration=0.2, lead=0.1, phase=phase)
    step = 1.0 / rate
    np.testing.assert_allclose(np.diff(record.time), step, rtol=1e-9)
    last = int(np.flatnonzero(record.time <= 1e-12)[-1])
    t = -phase * step
    assert record.time[last] == pytest.approx(t, abs=1e-12)
    assert record.load[last] == 0.0
    assert record.displacement[last] == pytest.approx(V25 * t + 0.5 * G * t * t, abs=1e-12)
    assert record.load[last + 1] > 0.0
    # the tyre has deflected about v·(1 − phase)/rate (it has not yet slowed much)
    assert record.tyre[last + 1] == pytest.approx(V25 * (1 - phase) * step, rel=0.02)
    with pytest.raises(ValueError, match="phase"):
        tg.simulate(GEAR, V25, rate, duration=0.2, phase=1.0)


def test_a_channel_skew_samples_the_load_later_not_between_samples():
    """A load channel lagging the others by τ = 0.4 ms reads the platform force at t − τ:
    the record with contact at phase 0.1 and skew 0.4 ms holds (1 + ε) times the load of
    the same drop sampled with contact at phase 0.5 (its samples 0.4 ms later after
    contact), not an interpolation between the 1 kHz samples (which cuts the first
    sample's load across the contact's kink and the peak)."""
    rate, epsilon, skew = 1000.0, 0.02, 4e-4
    truth = (tg.Truth("gain-skew", epsilon, (("skew", skew), ("sign", 1.0))),)
    skewed = tg.simulate(GEAR, V25, rate, duration=0.3, truths=truth, phase=0.1)
    later = tg.simulate(GEAR, V25, rate, duration=0.3, phase=0.5)
    plain = tg.simulate(GEAR, V25, rate, duration=0.3, phase=0.1)
    # every channel but the load is the plain record's; the load is the later sampling's
    np.testing.assert_array_equal(skewed.stroke, plain.stroke)
    np.testing.assert_allclose(skewed.load, (1 + epsilon) * later.load, rtol=0,
                               atol=1e-4 * later.load.max())
    interpolated = (1 + epsilon) * np.interp(np.arange(plain.load.size) - 0.4,
                                             np.arange(plain.load.size), plain.load)
    assert np.max(np.abs(interpolated - (1 + epsilon) * later.load)) > 20.0     # N: the noise


def test_a_first_order_lag_acts_as_the_analog_filter_before_sampling():
    """A 1st-order Butterworth low-pass of cutoff 1/(2π·T) with no pure delay is the lag
    T·ẏ + y = x.  On the free fall before contact, x = a + b·s + c·s² from the record's
    start (steady there), its exact response is y = x − T·x' + 2·c·T² + (T·b − 2·c·T²)·e^(−s/T)
    (by hand: the particular solution x − T·x' + T²·x'' and the homogeneous term that starts
    y at x).  The digital filter designed at the logger's own 1 kHz (T = 2 ms, two samples)
    misses this by tenths of a millimetre; the recorder acting on the continuous signal
    does not."""
    rate, lag, lead = 1000.0, 0.002, 0.1
    truth = (tg.Truth("butterworth-delay", lag, (("order", 1.0), ("delay_share", 0.0))),)
    record = tg.simulate(GEAR, V25, rate, duration=0.05, lead=lead, truths=truth)
    before = record.time < -1e-9
    s = record.time[before] + lead               # time since the record's start
    v0 = V25 - G * lead                          # the free fall at the record's start
    a, b, c = -(V25 * lead - 0.5 * G * lead ** 2), v0, 0.5 * G
    x, dx = a + b * s + c * s ** 2, b + 2 * c * s
    expected = x - lag * dx + 2 * c * lag ** 2 + (lag * b - 2 * c * lag ** 2) * np.exp(-s / lag)
    np.testing.assert_allclose(record.displacement[before], expected, rtol=0, atol=1e-6)
