"""The corrected two-mass drop model against conservation laws, the gas law and an
independently written simulator."""

import math

import numpy as np
import pytest

from certkit.physics.dynamics import V1, V2, Z1, Z2
from certkit.physics.drop_model import P_ATM, DropModel, EndStops, GasSpring, Orifice, Tyre
from certkit.physics.effects import ReboundOrifice, SealFriction
from certkit.physics.simulation import simulate_reference

G = 9.80665
PISTON = math.pi * 0.060 ** 2 / 4


def seed_gear(damping=True, friction=True, tyre_damping=0.05, stop_damping=13416.4):
    """One main gear of the seed amphibian, the parameter set fitted to Tables 2-3 at
    250/300 mm (60 mm piston, 0.8 MPa gauge pre-charge, V0 = 650 cm3, n = 1.2, C_d 0.6,
    9.4/6.65 mm orifices, tyre 7.2e5*delta^1.26 N, m1 + m2 = 292.5 kg)."""
    orifice = Orifice(PISTON, math.pi * 0.0094 ** 2 / 4, 0.6, 860.0) if damping else None
    effects = []
    if damping:
        rebound = 860.0 * PISTON ** 3 / (2 * (0.6 * math.pi * 0.00665 ** 2 / 4) ** 2)
        effects.append(ReboundOrifice(rebound - orifice.coefficient))
    if friction:
        effects.append(SealFriction(constant=80.0, pressure_factor=0.03, smoothing_velocity=0.002))
    return DropModel(
        upper_mass=283.5, lower_mass=9.0,
        gas=GasSpring(PISTON, PISTON * 0.230, 0.8e6 + P_ATM, 1.2), orifice=orifice,
        stops=EndStops(0.200, 2.0e7, stop_damping),
        tyre=Tyre(7.2e5 * 0.04 ** 1.26, 0.04, 1.26, tyre_damping), effects=tuple(effects))


@pytest.fixture(scope="module")
def drops():
    model = seed_gear()
    return {h: simulate_reference(model, math.sqrt(2 * G * h)) for h in (0.200, 0.250, 0.300)}


@pytest.mark.parametrize("height, peak_kgf, stroke_mm, tyre_mm", [
    (0.200, 1227, 88.9, 38.8), (0.250, 1384, 94.1, 42.7), (0.300, 1530, 98.5, 46.3)])
def test_agrees_with_an_independently_written_simulator(drops, height, peak_kgf, stroke_mm, tyre_mm):
    # expected values: a separate scratch implementation of the same corrected equations
    # (Radau with an analytic Jacobian, rtol 1e-8), written without this module
    drop = drops[height]
    assert drop.load.max() / G == pytest.approx(peak_kgf, abs=1.0)
    assert drop.stroke.max() * 1000 == pytest.approx(stroke_mm, abs=0.1)
    assert drop.tyre.max() * 1000 == pytest.approx(tyre_mm, abs=0.1)


@pytest.mark.parametrize("inclination, lift", [(0.0, 0.0), (0.15, 0.0), (0.15, 2 / 3)])
def test_energy_is_conserved_without_damping_or_friction(inclination, lift):
    from dataclasses import replace

    model = replace(seed_gear(damping=False, friction=False, tyre_damping=0.0, stop_damping=0.0),
                    inclination=inclination, lift_ratio=lift)
    v0 = math.sqrt(2 * G * 0.3)
    drop = simulate_reference(model, v0, duration=1.0)
    scale = 0.5 * model.total_mass * v0 ** 2
    assert np.max(np.abs(drop.mechanical)) / scale < 1e-4


def test_dissipated_energy_equals_the_integrated_damping_and_friction_work(drops):
    for drop in drops.values():
        # mechanical energy lost = work of the dissipative terms (integrated alongside)
        assert abs(drop.mechanical[-1] + drop.dissipated[-1]) <= 5e-3 * drop.dissipated[-1]
        assert drop.dissipated[-1] > 0


def test_static_position_matches_the_closed_form_gas_law():
    from scipy.optimize import fsolve

    model = seed_gear(friction=False)

    def accelerations(z):
        state = model.initial_state(0.0)
        state[[Z1, Z2]] = z
        return model.rates(state)[[V1, V2]]

    z1, z2 = fsolve(accelerations, [0.08, 0.01], xtol=1e-14)
    # p_st = p_atm + m1 g/A_a; s = V0/A_a (1 - (p_a0/p_st)^(1/n))
    p_static = P_ATM + 283.5 * G / PISTON
    closed_form = 0.230 * (1 - ((0.8e6 + P_ATM) / p_static) ** (1 / 1.2))
    assert closed_form * 1000 == pytest.approx(32.879, abs=1e-3)
    assert model.static_stroke() == pytest.approx(closed_form, rel=1e-12)
    assert z1 - z2 == pytest.approx(closed_form, abs=1e-9)
    # tyre: 7.2e5 delta^1.26 = 292.5 g
    assert z2 == pytest.approx((292.5 * G / 7.2e5) ** (1 / 1.26), abs=1e-9)


def test_strut_stays_topped_out_until_the_load_exceeds_its_preload(drops):
    drop = drops[0.300]
    preload = PISTON * 0.8e6  # A_a (p_a0 - p_atm) with the gauge pre-charge
    below = (drop.time >= 0) & (np.cumsum(drop.load >= preload) == 0)
    assert below.sum() >= 3
    # only the top-out stop's own compression: preload/k_stop = 2262 N/2e7 N/m = 0.113 mm
    assert np.all(np.abs(drop.stroke[below]) <= 0.114e-3)
    breakout = drop.time[np.flatnonzero(drop.stroke > 0.0005)[0]]
    assert 0.005 < breakout < 0.015  # 5-15 ms tyre-only phase (physics.md §3)


def test_foundation_energy_integrals_match_the_simulators_truth(drops):
    # certkit E1 works from the channels a lab records (platform load, stroke, tyre
    # deflection) and the declared unsprung mass; the simulator integrates the true forces
    from certkit.compliance.measures import measure_gear

    for drop in drops.values():
        measured = measure_gear(drop.time, drop.load, drop.stroke, drop.tyre, 292.5 * G,
                                unsprung_mass=9.0)
        strut_truth, tyre_truth = drop.absorbed_on_loading()
        # the issue asks for 2 %; without the unsprung-mass correction the error is 3.2 %
        assert measured.tyre_energy == pytest.approx(tyre_truth, rel=0.005)
        assert measured.strut_energy == pytest.approx(strut_truth, rel=0.005)


def metering_pin():
    from certkit.physics.effects import MeteringPin

    nominal = math.pi * 0.0094 ** 2 / 4
    # the pin closes the orifice to 60 % of its area over the stroke
    return MeteringPin((0.0, 0.05, 0.10, 0.20), (nominal, 0.8 * nominal, 0.6 * nominal,
                                                 0.6 * nominal), PISTON, nominal, 0.6, 860.0)


@pytest.mark.parametrize("effects", ["none", "seal friction", "rebound orifice",
                                     "metering pin", "tyre hysteresis", "both"])
def test_fast_path_agrees_with_the_reference(effects):
    from dataclasses import replace

    from certkit.physics.effects import TyreHysteresis
    from certkit.physics.simulation import simulate_batch

    full = seed_gear()
    chosen = {"none": (), "seal friction": full.effects[1:], "rebound orifice": full.effects[:1],
              "metering pin": (metering_pin(),), "tyre hysteresis": (),
              "both": full.effects}[effects]
    if effects == "tyre hysteresis":
        chosen = (TyreHysteresis(0.05),)
    model = replace(full, effects=tuple(chosen))
    velocities = np.sqrt(2 * G * np.array([0.2, 0.3]))
    batch = simulate_batch(model, velocities, duration=0.4)
    for index, velocity in enumerate(velocities):
        reference = simulate_reference(model, float(velocity), duration=0.4, lead=0.0)
        assert batch.load[index].max() == pytest.approx(reference.load.max(), rel=1e-3)
        assert batch.stroke[index].max() == pytest.approx(reference.stroke.max(), rel=1e-3)


def test_batch_of_parameter_sets_matches_single_runs():
    from dataclasses import replace

    from certkit.physics.simulation import simulate_batch

    base = seed_gear(friction=False)
    volumes = np.array([0.95, 1.0, 1.05]) * base.gas.volume
    models = [replace(base, gas=replace(base.gas, volume=float(v))) for v in volumes]
    batch = simulate_batch(models, math.sqrt(2 * G * 0.25), duration=0.3)
    for index, model in enumerate(models):
        single = simulate_batch(model, math.sqrt(2 * G * 0.25), duration=0.3)
        assert np.allclose(batch.load[index], single.load[0], rtol=1e-12, atol=1e-9)
        assert np.allclose(batch.stroke[index], single.stroke[0], rtol=1e-12, atol=1e-12)
    # a larger gas volume is a softer spring: more stroke
    assert batch.stroke[0].max() < batch.stroke[1].max() < batch.stroke[2].max()


def test_metering_pin_raises_the_load_late_in_the_stroke():
    from dataclasses import replace

    base = seed_gear()
    pinned = replace(base, effects=base.effects + (metering_pin(),))
    v0 = math.sqrt(2 * G * 0.3)
    plain, with_pin = simulate_reference(base, v0, 0.4), simulate_reference(pinned, v0, 0.4)
    # a smaller orifice late in the stroke: more damping, less stroke, higher load
    assert with_pin.stroke.max() < plain.stroke.max()
    assert with_pin.load.max() > plain.load.max()
    assert abs(with_pin.mechanical[-1] + with_pin.dissipated[-1]) <= 1e-6 * with_pin.dissipated[-1]


def test_tyre_hysteresis_dissipates_and_is_accounted():
    from dataclasses import replace

    from certkit.physics.effects import TyreHysteresis

    base = seed_gear(damping=False, friction=False, tyre_damping=0.0, stop_damping=0.0)
    lossy = replace(base, effects=(TyreHysteresis(0.05),))
    drop = simulate_reference(lossy, math.sqrt(2 * G * 0.3), duration=1.0)
    assert drop.dissipated[-1] > 0  # the only dissipation in this model is the tyre loop
    assert abs(drop.mechanical[-1] + drop.dissipated[-1]) <= 1e-6 * drop.dissipated[-1]


def test_sensor_dynamics_delays_and_attenuates_a_contact_spike():
    from scipy.signal import butter, group_delay

    from certkit.physics.effects import SensorDynamics

    time = np.arange(0.0, 0.5, 0.001)
    spike = np.where((time > 0.1) & (time < 0.14), np.sin(math.pi * (time - 0.1) / 0.04), 0.0)
    sensor = SensorDynamics(cutoff=100.0, order=2, delay=0.002)
    recorded = sensor.apply(time, spike)
    # independent figure: the filter's group delay at low frequency plus the pure delay
    b, a = butter(2, 100.0, fs=1000.0)
    _, delay_samples = group_delay((b, a), w=[1.0], fs=1000.0)
    shift = time[np.argmax(recorded)] - time[np.argmax(spike)]
    assert shift == pytest.approx(delay_samples[0] / 1000.0 + 0.002, abs=0.0015)
    assert 0.8 < recorded.max() < 1.0  # attenuated, not amplified
    assert np.allclose(SensorDynamics(100.0).apply(time, np.ones_like(time)), 1.0)  # DC passes


def test_a_prescribed_ground_load_holds_the_static_stroke_and_follows_the_gas_stiffness():
    from certkit.physics.simulation import simulate_driven

    model = seed_gear(friction=False)
    weight = 292.5 * G
    time = np.arange(0.0, 8.0, 0.001)
    at_rest = simulate_driven(model, time, np.full(time.size, weight))
    assert np.allclose(at_rest.stroke, 0.032879, atol=1e-6)  # the closed form of the test above
    # the tyre reads the static curve's deflection under the weight: (W/7.2e5)^(1/1.26)
    assert np.allclose(at_rest.tyre, (weight / 7.2e5) ** (1 / 1.26), rtol=1e-9)
    # a slow 100 N sine on top: both masses accelerate together, the strut carries
    # m1/(m1 + m2) of the extra force against the gas spring's local stiffness
    # k_g = n·p_st·A²/V_st at the static point (by hand, not from the model).  At 0.25 Hz,
    # far below the relative mode √(k_g/μ)/2π ≈ 7 Hz, the response is quasi-static
    # (dynamic amplification 1/(1 − (0.25/7)²) = 1.001).
    driven = simulate_driven(model, time, weight + 100.0 * np.sin(2 * math.pi * 0.25 * time))
    p_static = P_ATM + 283.5 * G / PISTON
    volume = PISTON * 0.230 - PISTON * 0.032879
    k_gas = 1.2 * p_static * PISTON ** 2 / volume
    expected = 283.5 / 292.5 * 100.0 / k_gas
    amplitude = 0.5 * np.ptp(driven.stroke[time > 2.0])
    assert amplitude == pytest.approx(expected, rel=0.005)


def test_a_compliant_top_out_stop_gives_by_hand_and_the_stroke_reads_zero_at_the_hang():
    """A 2 mm top-out pad (k_top = F_0/2 mm, linear) under half the preload F_0 = A·0.8 MPa:
    the stop carries F_0/2 less what the gas loses as the strut extends past s = 0
    (F_gas(s) = A·(p_a0·(V0/(V0 − A·s))^1.2 − p_atm), solved here by hand), and the
    transducer reads s from where the strut hangs under F_0: s + 2 mm (on the rigid stop,
    0: its penalty spring's give is no stroke)."""
    from dataclasses import replace

    from certkit.physics.simulation import simulate_driven

    preload, precharge, volume = PISTON * 0.8e6, 0.8e6 + P_ATM, PISTON * 0.230
    base = seed_gear(friction=False)
    for stops, k_top, zero in ((base.stops, 2.0e7, None),
                               (replace(base.stops, top_out=0.002), preload / 0.002, -0.002)):
        stroke = 0.0
        for _ in range(50):     # F_gas(s) + k_top·s = F_0/2, s < 0
            gas = PISTON * (precharge * (volume / (volume - PISTON * stroke)) ** 1.2 - P_ATM)
            stroke = (0.5 * preload - gas) / k_top
        lift = 283.5 * G - 0.5 * preload          # the strut carries half its preload
        model = replace(base, stops=stops, lift_ratio=lift / (292.5 * G))
        time = np.arange(0.0, 3.0, 0.001)
        rest = simulate_driven(model, time, np.full(time.size, 292.5 * G - lift))
        # a rigid stop reads 0 however far its penalty spring gives; the pad has no damping
        # of its own and the oil's (square law) fades as the strut slows, so the strut still
        # rings about its rest: its mean over the last second is the rest
        expected = 0.0 if zero is None else stroke - zero
        assert np.mean(rest.stroke[time >= 2.0]) == pytest.approx(expected, abs=1e-8), stops


def test_the_step_follows_a_top_out_stop_stiffer_than_the_bottoming_stop():
    from dataclasses import replace

    from certkit.physics.simulation import fastest_rate

    base = seed_gear()
    stiff = replace(base, stops=replace(base.stops, top_out=1e-5))   # F_0/1e-5 m ≈ 2.3e8 N/m
    assert fastest_rate(stiff, 2.4) >= math.sqrt(PISTON * 0.8e6 / 1e-5 / 9.0)
