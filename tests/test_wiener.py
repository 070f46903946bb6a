"""Linear blocks (ARX) and the seed paper's small-signal Wiener method on plants whose
linear block and nonlinearity are known by construction."""

import numpy as np
import pytest
from scipy.signal import lfilter

from certkit.ident.linear_models import ARX
from certkit.ident.wiener import best_linear_records, excitation, small_signal_records

# a stable second-order block with static gain (0.3 + 0.2)/(1 − 1.2 + 0.5) = 5/3
B, A = [0.3, 0.2], [1.0, -1.2, 0.5]


def test_arx_recovers_a_known_linear_system_from_several_experiments():
    rng = np.random.default_rng(0)
    u = [rng.standard_normal(400) for _ in range(3)]
    y = [lfilter(B, A, x) for x in u]
    model = ARX(2, 2).fit(u, y)
    assert model.a_ == pytest.approx([1.2, -0.5], abs=1e-10)
    assert model.b_ == pytest.approx([0.3, 0.2], abs=1e-10)
    assert model.static_gain_ == pytest.approx(5 / 3)
    assert model.stable_
    assert np.allclose(model.simulate(u[0]), y[0], atol=1e-10)
    assert model.normalised().static_gain_ == pytest.approx(1.0, rel=1e-12)
    assert np.allclose(model.normalised().simulate(u[1]), y[1] * 3 / 5, atol=1e-10)


def test_experiments_are_not_joined_at_their_boundaries():
    rng = np.random.default_rng(1)
    u = [rng.standard_normal(50) for _ in range(2)]
    y = [lfilter(B, A, x) for x in u]
    # joined, the second record's first samples would be explained by the first's end
    joined_u, joined_y = np.concatenate(u), np.concatenate(y)
    assert ARX(2, 2).fit(u, y).a_ == pytest.approx([1.2, -0.5], abs=1e-10)
    assert not np.allclose(ARX(2, 2).fit(joined_u, joined_y).a_, [1.2, -0.5], atol=1e-3)


def _wiener_plant(nonlinearity):
    def plant(force):
        return {"y": nonlinearity(lfilter(B, A, force))}
    return plant


def test_small_signal_method_shrinks_until_the_plant_is_linear():
    # f(z) = z + z^3/100 is linear within 1 % only for |z| of a few units: the method must
    # shrink the amplitude from 10 until the K-scaled response matches within 2 %
    plant = _wiener_plant(lambda z: z + z ** 3 / 100.0)
    experiment = small_signal_records(plant, ["y"], 1000, 100.0, amplitude=10.0, gain=2.0,
                                      tolerance=0.02, bandwidth=10.0)
    assert experiment.accepted
    assert [s.accepted for s in experiment.steps][-1] and not experiment.steps[0].accepted
    assert experiment.steps[-1].amplitude < 10.0
    linear = ARX(2, 2).fit(experiment.force, experiment.responses["y"])
    # the small-signal block is G times f'(0) = 1: the plant's own block, nearly exactly
    assert linear.a_ == pytest.approx([1.2, -0.5], abs=0.01)
    assert linear.static_gain_ == pytest.approx(5 / 3, rel=0.01)


def test_a_plant_that_is_never_linear_is_reported_not_accepted():
    plant = _wiener_plant(lambda z: np.sign(z) * np.sqrt(np.abs(z)))  # no linear range
    experiment = small_signal_records(plant, ["y"], 500, 100.0, amplitude=1.0, max_steps=4)
    assert not experiment.accepted and len(experiment.steps) == 4


def test_excitation_is_zero_mean_unit_rms_and_reproducible():
    r = excitation(2000, 1000.0, 30.0, seed=3)
    assert np.sqrt(np.mean(r ** 2)) == pytest.approx(1.0)
    assert abs(r.mean()) < 1e-12 and r[0] == 0.0 and r[-1] == 0.0
    assert np.array_equal(r, excitation(2000, 1000.0, 30.0, seed=3))
    records = best_linear_records(_wiener_plant(np.tanh), ["y"], 500, 100.0, amplitude=1.0)
    assert len(records.force) == 2 and records.accepted


def test_small_signal_method_grows_the_amplitude_while_the_plant_stays_linear():
    # f(z) = z + z^3/100: linear within 2 % up to |z| of about 1; starting small, the
    # method doubles the amplitude while the K-check passes and keeps the last linear one
    plant = _wiener_plant(lambda z: z + z ** 3 / 100.0)
    experiment = small_signal_records(plant, ["y"], 1000, 100.0, amplitude=0.05, gain=2.0,
                                      tolerance=0.02, bandwidth=10.0)
    decisions = [s.accepted for s in experiment.steps]
    assert decisions[0] and not decisions[-1] and experiment.accepted
    kept = max(s.amplitude for s in experiment.steps if s.accepted)
    assert kept > 0.05 and np.allclose(experiment.force[0], kept * excitation(1000, 100.0, 10.0, 0))


def test_a_gain_that_is_not_determined_is_scaled_by_the_norm_of_b():
    # a differentiator-like block: Σb = 0, so the static gain is 0 and cannot normalise it
    rng = np.random.default_rng(2)
    u = rng.standard_normal(500)
    y = lfilter([1.0, -1.0], [1.0, -0.5], u)
    model = ARX(1, 2).fit(u, y)
    assert not model.gain_determined
    scaled = model.normalised()
    assert np.linalg.norm(scaled.b_) == pytest.approx(1.0)
    assert np.isnan(scaled.static_gain_) and np.all(np.isfinite(scaled.simulate(u)))
