"""The effects with their own degrees of freedom or states (heat transfer, oil
compressibility, leg flexibility, platform compliance): each checked against a closed
form or a limit it must reduce to, against the reference path, and for energy closure."""

import math
from dataclasses import replace

import numpy as np
import pytest

from certkit.physics.effects import (GasHeatTransfer, LegFlexibility, OilCompressibility,
                                     PlatformCompliance, ReboundOrifice, SensorLag,
                                     TyreHysteresis)
from certkit.physics.simulation import simulate_batch, simulate_reference

from .test_drop_model import PISTON, seed_gear

G = 9.80665
V300 = math.sqrt(2 * G * 0.3)

EFFECTS = {
    "heat transfer": GasHeatTransfer(time_constant=1.0),
    "oil compressibility": OilCompressibility.from_oil(1.5e9, PISTON, 3e-4),
    "leg flexibility": LegFlexibility(axle_mass=5.0, stiffness=3e6, damping=300.0),
    "leg above the strut": LegFlexibility(axle_mass=18.0, stiffness=1e7, damping=800.0,
                                          above=True),
    "platform compliance": PlatformCompliance(mass=50.0, stiffness=5e7, damping=5000.0),
    "constant tyre loop": TyreHysteresis(0.0, constant=300.0),
    "tyre loop with memory": TyreHysteresis(0.05, constant=300.0, memory=True),
    "linear rebound": ReboundOrifice(0.0, linear=2000.0),
}


@pytest.fixture(scope="module")
def reference():
    base = seed_gear(friction=False)
    drops = {"none": simulate_reference(base, V300, duration=2.0)}
    for name, effect in EFFECTS.items():
        drops[name] = simulate_reference(replace(base, effects=base.effects + (effect,)), V300,
                                         duration=2.0)
    return drops


@pytest.mark.parametrize("name", list(EFFECTS))
def test_fast_path_agrees_with_the_reference_for_each_effect(name):
    base = seed_gear(friction=False)
    model = replace(base, effects=base.effects + (EFFECTS[name],))
    batch = simulate_batch(model, V300, duration=0.4)
    drop = simulate_reference(model, V300, duration=0.4, lead=0.0)
    assert batch.load[0].max() == pytest.approx(drop.load.max(), rel=1e-3)
    assert batch.stroke[0].max() == pytest.approx(drop.stroke.max(), rel=1e-3)


@pytest.mark.parametrize("name", list(EFFECTS))
def test_energy_lost_equals_the_dissipated_work(reference, name):
    drop = reference[name]
    assert drop.dissipated[-1] > 0
    assert abs(drop.mechanical[-1] + drop.dissipated[-1]) <= 1e-5 * drop.dissipated[-1]


def test_adiabatic_heat_transfer_is_the_polytropic_law_with_n_gamma():
    # τ → ∞: no heat leaves the gas, p·V^γ = const, the polytropic law with n = γ = 1.4.
    # The two laws start differently on the top-out stop's tiny compression (the gas at
    # rest is at wall temperature); a stiffer stop makes that start negligible.
    base = seed_gear(friction=False)
    base = replace(base, stops=replace(base.stops, stiffness=2e9))
    adiabatic = replace(base, effects=base.effects + (GasHeatTransfer(1e9, 1.4),))
    polytropic = replace(base, gas=replace(base.gas, exponent=1.4))
    a = simulate_reference(adiabatic, V300, duration=0.4)
    b = simulate_reference(polytropic, V300, duration=0.4)
    assert np.max(np.abs(a.load - b.load)) < 1e-4 * b.load.max()
    assert np.max(np.abs(a.stroke - b.stroke)) < 1e-6


def test_gas_at_wall_temperature_holds_the_isothermal_static_stroke():
    # at rest the gas is back at wall temperature (θ = 1), so the static stroke is the gas
    # law's with n = 1: s = V0/A·(1 − p_a0/p_st), p_st = p_atm + m1·g/A (no friction)
    from scipy.optimize import fsolve

    from certkit.physics.dynamics import V1, V2, Z1, Z2

    base = seed_gear(friction=False)
    model = replace(base, effects=base.effects + (GasHeatTransfer(0.02),))

    def accelerations(z):
        state = model.initial_state(0.0)
        state[[Z1, Z2]] = z
        return model.rates(state)[[V1, V2]]

    z1, z2 = fsolve(accelerations, [0.08, 0.01], xtol=1e-12)
    p_static = 101325.0 + 283.5 * G / PISTON
    isothermal = 0.230 * (1 - (0.8e6 + 101325.0) / p_static)
    # by hand: p_st = 101325 + 2780.19 N/2.82743e-3 m² = 1084615 Pa; 0.23·(1 − 901325/1084615)
    assert isothermal * 1000 == pytest.approx(38.868, abs=0.001)
    assert z1 - z2 == pytest.approx(isothermal, abs=1e-9)


def test_cooling_gas_lets_the_strut_sink_after_the_drop(reference):
    # polytropic n = 1.2 static stroke 32.88 mm, isothermal 38.87 mm: with τ = 1 s the gas
    # cools over the record and the strut sinks towards the isothermal position
    late = reference["none"].time > 1.5
    nominal = reference["none"].stroke[late].mean()
    cooled = reference["heat transfer"].stroke[late].mean()
    assert 2e-3 < cooled - nominal < 6.0e-3


@pytest.mark.parametrize("name, stiff", [
    ("oil compressibility", OilCompressibility(1e11)),
    ("leg flexibility", LegFlexibility(5.0, 1e9, 2e4)),
    ("leg above the strut", LegFlexibility(5.0, 1e9, 2e4, above=True)),
    ("platform compliance", PlatformCompliance(1.0, 1e9, 2e4)),
])
def test_a_very_stiff_element_reduces_to_the_nominal_model(reference, name, stiff):
    base = seed_gear(friction=False)
    drop = simulate_reference(replace(base, effects=base.effects + (stiff,)), V300, duration=2.0)
    nominal = reference["none"]
    assert drop.load.max() == pytest.approx(nominal.load.max(), rel=5e-3)
    assert drop.stroke.max() == pytest.approx(nominal.stroke.max(), rel=1e-3)


def test_platform_load_cells_read_what_the_tyre_carries(reference):
    # the cells read the tyre's force through the platform: averaged over the settling
    # oscillation both carry the unit's weight, (m1 + m2)·g = 292.5 kg·g
    late = reference["none"].time > 1.5
    cells = reference["platform compliance"].load[late].mean()
    assert cells == pytest.approx(reference["none"].load[late].mean(), rel=1e-3)
    assert cells == pytest.approx(292.5 * G, rel=1e-2)


def test_platform_mode_rings_on_load_not_on_stroke(reference):
    # the platform's mode √(k_p/m_p)/2π = √(5e7/50)/2π = 159 Hz shows on the load the cells
    # read; the stroke barely sees it.  Compare the high-pass content of both channels
    # with the nominal model's.
    from scipy.signal import butter, sosfiltfilt

    sos = butter(4, 100.0, "highpass", fs=1000.0, output="sos")

    def ripple(signal):
        return np.sqrt(np.mean(sosfiltfilt(sos, signal) ** 2))

    nominal, platform = reference["none"], reference["platform compliance"]
    assert ripple(platform.load) > 3 * ripple(nominal.load)
    assert ripple(platform.stroke) < 1.5 * ripple(nominal.stroke)


def test_oil_compressibility_delays_the_load_build_up(reference):
    # the oil column must be compressed before the orifice carries the hydraulic force,
    # so the load builds up later (physics.md §3 #7)
    nominal, oil = reference["none"], reference["oil compressibility"]
    level = 0.5 * nominal.load.max()
    assert (oil.time[np.argmax(oil.load > level)] >= nominal.time[np.argmax(nominal.load > level)])


# --- found by review: stiff corners the batched path's step must respect --------------
def _agree(model, height, duration=1.0):
    velocity = math.sqrt(2 * G * height)
    batch = simulate_batch(model, velocity, duration=duration)
    drop = simulate_reference(model, velocity, duration=duration, lead=0.0)
    assert batch.load[0].max() == pytest.approx(drop.load.max(), rel=1e-3)
    assert batch.stroke[0].max() == pytest.approx(drop.stroke.max(), rel=1e-3)
    # every sample, not only the peaks; and the same energy lost
    assert np.max(np.abs(batch.load[0] - drop.load)) <= 2e-3 * drop.load.max()
    assert batch.dissipated[0] == pytest.approx(drop.dissipated[-1], rel=5e-3)


def test_fast_path_follows_a_sharp_tyre_hysteresis_loop():
    from certkit.physics.effects import TyreHysteresis

    base = seed_gear(friction=False)
    _agree(replace(base, effects=(TyreHysteresis(0.1, smoothing_velocity=0.002),)), 0.1)


def test_fast_path_follows_friction_on_a_strut_that_never_breaks_out():
    base = seed_gear()
    _agree(replace(base, gas=replace(base.gas, precharge=8e6)), 0.1)


def test_fast_path_follows_oil_compressibility_behind_a_metering_pin():
    from certkit.physics.effects import MeteringPin

    base = seed_gear(friction=False)
    nominal = math.pi * 0.0094 ** 2 / 4
    pin = MeteringPin((0.0, 0.05, 0.1, 0.2), tuple(f * nominal for f in (2, 1.5, 1, 0.8)),
                      PISTON, nominal, 0.6, 860.0)
    oil = OilCompressibility.from_oil(1.5e9, PISTON, 3e-4)
    _agree(replace(base, effects=base.effects + (pin, oil)), 0.3)


def test_resting_state_with_heat_transfer_is_isothermal():
    from certkit.physics.simulation import simulate_driven

    base = seed_gear(friction=False)
    model = replace(base, effects=base.effects + (GasHeatTransfer(0.5),))
    assert model.static_stroke() == pytest.approx(0.038868, abs=1e-6)  # the hand value above
    time = np.arange(0.0, 2.0, 0.001)
    rest = simulate_driven(model, time, np.full(time.size, 292.5 * G))
    assert np.allclose(rest.stroke, 0.038868, atol=2e-6)


@pytest.mark.parametrize("change", [{"lower_mass": 0.0}, {"upper_mass": -1.0},
                                    {"inclination": math.pi / 2}])
def test_degenerate_models_are_refused(change):
    with pytest.raises(ValueError):
        replace(seed_gear(), **change)


@pytest.mark.parametrize("above", [False, True])
def test_the_resting_state_with_a_flexible_leg_is_an_equilibrium(above):
    # static_state (the small-signal plant's start, the ground replaced by an applied
    # force) puts the strut at the gas law's equilibrium and the leg's spring at the
    # deflection its load gives (the weight below it at the axle, the weight above it when
    # the leg is above the strut): under the unit's weight every acceleration is zero
    from certkit.physics import dynamics as dyn
    from certkit.physics.simulation import static_state

    base = replace(seed_gear(friction=False), effects=())
    model = replace(base, effects=(LegFlexibility(5.0, 3e6, 300.0, above=above),))
    rates = np.empty(dyn.STATES)
    dyn.driven_rates(model.pack(), static_state(model), rates, model.total_mass * G)
    for slot in (dyn.V1, dyn.V2, dyn.VW):
        assert abs(rates[slot]) < 1e-6 * G


def test_a_constant_tyre_loop_has_the_same_width_at_any_load(reference):
    # F = f(δ)·(1 + C_T·δ̇) + H·(1 − e^(−δ/δ_H))·tanh(δ̇/v): past the onset the loop adds
    # +H while the tyre is compressed fast and −H while it extends fast, whatever f(δ).
    # Compare the load with the nominal model's tyre law evaluated on the same deflection.
    drop = reference["constant tyre loop"]
    model = seed_gear(friction=False)
    tyre = model.tyre
    rate = np.gradient(drop.tyre, drop.time)
    law = tyre.static_force(drop.tyre) * (1 + tyre.damping * rate)
    excess = drop.load - law
    fast = (drop.tyre > 0.01) & (np.abs(rate) > 0.1)          # δ ≫ δ_H, |δ̇| ≫ v
    loading, unloading = excess[fast & (rate > 0)], excess[fast & (rate < 0)]
    assert loading.size > 5 and unloading.size > 5
    assert np.median(loading) == pytest.approx(300.0, rel=0.05)
    assert np.median(unloading) == pytest.approx(-300.0, rel=0.05)


@pytest.mark.parametrize("rate, extra", [(-0.5, 2000.0 * -0.5), (0.5, 0.0)])
def test_linear_rebound_damping_acts_on_extension_only(rate, extra):
    # c·ṡ added to the strut force when ṡ < 0: at a state with the strut extending at
    # 0.5 m/s the upper mass's acceleration changes by −c·ṡ/m1 (its force is −F_s/m1);
    # compressing, not at all
    from certkit.physics import dynamics as dyn

    base = replace(seed_gear(friction=False), effects=())
    linear = replace(base, effects=(ReboundOrifice(0.0, linear=2000.0),))
    state = base.initial_state(0.0)
    state[dyn.Z1] = 0.05                       # 50 mm of stroke, inside the stops
    state[dyn.V1] = rate
    change = linear.rates(state)[dyn.V1] - base.rates(state)[dyn.V1]
    assert change == pytest.approx(-extra / base.upper_mass, abs=1e-9)


def test_a_second_order_sensor_lag_is_two_first_order_lags_in_cascade():
    # a unit step through two lags of τ: 1 − (1 + t/τ)·e^(−t/τ) (the critically damped
    # second-order step response), sampled at 1 kHz; the first-order one: 1 − e^(−t/τ)
    step, tau = 1e-3, 2e-3
    signal = np.r_[np.zeros(5), np.ones(40)]
    t = np.arange(40) * step
    second = SensorLag(tau, order=2).apply(step, signal)[5:]
    first = SensorLag(tau).apply(step, signal)[5:]
    # y[n] = a·y[n−1] + (1 − a)·x[n], a = e^(−Δt/τ): after a unit step at sample 0,
    # y[k] = 1 − a^(k+1)
    assert first == pytest.approx(1 - np.exp(-(t + step) / tau), abs=1e-12)
    # two in cascade: impulse response (1 − a)²·(n + 1)·aⁿ, so the step response is
    # y[k] = 1 − (k + 2)·a^(k+1) + (k + 1)·a^(k+2)
    a, k = np.exp(-step / tau), np.arange(40)
    assert second == pytest.approx(1 - (k + 2) * a ** (k + 1) + (k + 1) * a ** (k + 2),
                                   abs=1e-12)
    with pytest.raises(ValueError):
        SensorLag(tau, order=3)


def test_a_tyre_loop_with_memory_follows_dahls_law_and_holds_at_rest():
    """w' = (δ̇/δ_H)·(1 − w·tanh(δ̇/v_ε)); F = f(δ)·(1 + C_T·δ̇) + (h·f(δ) + H)·w, by hand
    at δ = 20 mm, with w = 0 (the switch runs at δ̇/δ_H), w = 1 loading (saturated), and
    at rest (δ̇ = 0: w keeps its value and the loop holds its force)."""
    from certkit.physics import dynamics as dyn

    base = seed_gear(friction=False)
    model = replace(base, effects=(TyreHysteresis(0.05, constant=300.0, memory=True),))
    tyre = model.tyre
    static = tyre.reference_load * (0.02 / tyre.reference_deflection) ** tyre.exponent
    for w, rate in ((0.0, 0.1), (1.0, 0.1), (0.6, 0.0), (-1.0, -0.2)):
        y = np.zeros(dyn.STATES)
        y[dyn.Z1] = y[dyn.Z2] = 0.02
        y[dyn.V1] = y[dyn.V2] = rate
        y[dyn.THETA], y[dyn.LOOP] = 1.0, w
        dy = model.rates(y)
        expected = rate / 0.002 * (1 - w * math.tanh(rate / 0.01))
        assert dy[dyn.LOOP] == pytest.approx(expected, abs=1e-9)
        force = static * (1 + tyre.damping * rate) + (0.05 * static + 300.0) * w
        # the lower mass: m2·a = m2·g + F_s − F_V, so F_V = m2·(g − a) + F_s
        strut = (model.upper_mass * (G - dy[dyn.V1]) - model.lift)
        assert model.lower_mass * (G - dy[dyn.V2]) + strut == pytest.approx(force, rel=1e-9)
