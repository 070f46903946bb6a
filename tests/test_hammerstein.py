"""Hammerstein LS-SVM identification: KKT system, recovery of a known system, diagnostics.

Expected values come from the definitions (a KKT matrix assembled here element by element
with an independent kernel), from the known synthetic system, or from hand algebra
(poles of z^2 - 1.2 z + 0.5 have modulus sqrt(0.5); the static gain of b/(1 - a) is
1.5/0.3 = 5).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from certkit.errors import DataInputError
from certkit.ident.hammerstein import HammersteinLSSVM, ar_poles, is_stable

A_TRUE = np.array([1.2, -0.5])        # poles 0.6 ± 0.374i, |p| = sqrt(0.5)
B_TRUE = np.array([1.0, 0.5])
STATIC_GAIN = B_TRUE.sum() / (1.0 - A_TRUE.sum())    # 1.5 / 0.3 = 5


def f_true(u):
    return u + 0.5 * u**3


def arx(x, a, b):
    """y_t = sum_i a_i y_{t-i} + sum_j b_j x_{t-j}, starting from rest (plain loop)."""
    y = np.zeros_like(x)
    for t in range(x.size):
        y[t] = sum(a[i] * y[t - 1 - i] for i in range(a.size) if t - 1 - i >= 0)
        y[t] += sum(b[j] * x[t - j] for j in range(b.size) if t - j >= 0)
    return y


def hammerstein(u):
    return arx(f_true(u), A_TRUE, B_TRUE)


def wiener(u):
    return np.tanh(0.5 * arx(u, A_TRUE, B_TRUE))


def inputs(seed, count, length=200):
    rng = np.random.default_rng(seed)
    return [rng.uniform(-1.0, 1.0, length) for _ in range(count)]


def nrmse(estimate, reference):
    return math.sqrt(np.mean((estimate - reference) ** 2)) / np.std(reference)


def kkt_system(experiments, na, nb, gamma, sigma2):
    """The dual KKT matrix and right-hand side, assembled entry by entry from the definitions.

    Rows t = r .. N_e - 1 of every experiment (r = max(na, nb - 1)), global sample index;
    centering over all samples.  Unknowns ordered (d, a_1..a_na, alpha_t..., beta_0..beta_{nb-1}).
    """
    u = np.concatenate([e[0] for e in experiments])
    y = np.concatenate([e[1] for e in experiments])
    r = max(na, nb - 1)
    rows, start = [], 0
    for ue, _ in experiments:
        rows += list(range(start + r, start + ue.size))
        start += ue.size
    n, nt = u.size, len(rows)

    def kern(p, q):
        return math.exp(-(u[p] - u[q]) ** 2 / sigma2)

    column_sum = [sum(kern(k, q) for k in range(n)) for q in range(n)]
    size = 1 + na + nt + nb
    ia, ial, ibe = 1, 1 + na, 1 + na + nt
    m = np.zeros((size, size))
    rhs = np.zeros(size)
    for p, t in enumerate(rows):
        m[0, ial + p] = m[ial + p, 0] = 1.0
        for i in range(1, na + 1):
            m[ia + i - 1, ial + p] = m[ial + p, ia + i - 1] = y[t - i]
        for q, s in enumerate(rows):
            m[ial + p, ial + q] = sum(kern(t - j, s - j) for j in range(nb))
        m[ial + p, ial + p] += 1.0 / gamma
        for j in range(nb):
            m[ial + p, ibe + j] = m[ibe + j, ial + p] = column_sum[t - j]
        rhs[ial + p] = y[t]
    for j in range(nb):
        m[ibe + j, ibe + j] = sum(column_sum)
    return m, rhs


def solution_vector(model):
    return np.concatenate(([model.d_], model.a_, model.dual_coef_, model.centering_coef_))


@pytest.fixture(scope="module")
def two_short_experiments():
    rng = np.random.default_rng(7)
    experiments = []
    for length in (24, 31):
        u = rng.uniform(-1.0, 1.0, length)
        y = hammerstein(u) + 0.01 * rng.standard_normal(length)
        experiments.append((u, y))
    return experiments


@pytest.fixture(scope="module")
def hammerstein_data():
    us = inputs(1, 4)
    rng = np.random.default_rng(11)
    ys = [hammerstein(u) + 1e-3 * rng.standard_normal(u.size) for u in us]
    return us, ys


@pytest.fixture(scope="module")
def hammerstein_fit(hammerstein_data):
    us, ys = hammerstein_data
    return HammersteinLSSVM(na=2, nb=2, gamma=1e6, sigma2=1.0).fit(us[:3], ys[:3])


def test_dual_solution_satisfies_the_kkt_system(two_short_experiments):
    na, nb, gamma, sigma2 = 2, 3, 50.0, 0.7
    model = HammersteinLSSVM(na=na, nb=nb, gamma=gamma, sigma2=sigma2, input_scale=1.0)
    model.fit([e[0] for e in two_short_experiments], [e[1] for e in two_short_experiments])
    m, rhs = kkt_system(two_short_experiments, na, nb, gamma, sigma2)
    assert np.allclose(m, m.T)
    residual = m @ solution_vector(model) - rhs
    assert np.max(np.abs(residual)) < 1e-9
    # the stationarity conditions in words: sum alpha = 0, sum alpha y_{t-i} = 0
    assert abs(model.dual_coef_.sum()) < 1e-9


def test_experiments_are_not_mixed(two_short_experiments):
    na, nb, gamma, sigma2 = 2, 3, 50.0, 0.7
    us = [e[0] for e in two_short_experiments]
    ys = [e[1] for e in two_short_experiments]
    separate = HammersteinLSSVM(na=na, nb=nb, gamma=gamma, sigma2=sigma2,
                                input_scale=1.0).fit(us, ys)
    joined = HammersteinLSSVM(na=na, nb=nb, gamma=gamma, sigma2=sigma2, input_scale=1.0).fit(
        np.concatenate(us), np.concatenate(ys))
    # rows by hand (no lag crosses the boundary): the separate fit is exactly that system
    m, rhs = kkt_system(two_short_experiments, na, nb, gamma, sigma2)
    by_hand = np.linalg.solve(m, rhs)
    assert np.allclose(solution_vector(separate), by_hand, rtol=1e-7, atol=1e-9)
    assert separate.n_rows_ == (24 - 2) + (31 - 2)
    assert joined.n_rows_ == 55 - 2
    # the second drop starts from rest: rows straddling the joint are wrong equations
    assert np.max(np.abs(separate.a_ - joined.a_)) > 1e-3


def test_recovers_a_known_hammerstein_system(hammerstein_fit, hammerstein_data):
    us = hammerstein_data[0]
    model = hammerstein_fit
    assert model.stable_
    np.testing.assert_allclose(model.a_, A_TRUE, rtol=0.01)
    # unit static gain: b_hat = b / 5, f_hat = 5 (f - mean of f over the training inputs)
    np.testing.assert_allclose(model.b_, B_TRUE / STATIC_GAIN, rtol=0.01)
    grid = np.linspace(-1.0, 1.0, 201)
    training_mean = np.mean(f_true(np.concatenate(us[:3])))
    expected = STATIC_GAIN * (f_true(grid) - training_mean)
    error = model.nonlinearity(grid) - expected
    assert math.sqrt(np.mean(error**2)) < 0.01 * math.sqrt(np.mean(expected**2))
    assert model.singular_value_ratio_ < 0.05


def test_free_run_on_a_held_out_drop(hammerstein_fit, hammerstein_data):
    us, ys = hammerstein_data
    simulated = hammerstein_fit.simulate(us[3], ys[3][:2])
    assert np.array_equal(simulated[:2], ys[3][:2])
    assert nrmse(simulated[2:], ys[3][2:]) < 0.01
    one_step = hammerstein_fit.predict(us[3], ys[3])
    assert nrmse(one_step[2:], ys[3][2:]) < 0.01


def test_other_normalisations(hammerstein_data):
    us, ys = hammerstein_data
    grid = np.linspace(-1.0, 1.0, 101)
    centred = f_true(grid) - np.mean(f_true(np.concatenate(us[:3])))
    b0 = HammersteinLSSVM(na=2, nb=2, gamma=1e6, normalisation="b0").fit(us[:3], ys[:3])
    np.testing.assert_allclose(b0.b_, [1.0, 0.5], rtol=0.01)
    np.testing.assert_allclose(b0.nonlinearity(grid), centred, atol=0.01)
    unit = HammersteinLSSVM(na=2, nb=2, gamma=1e6, normalisation="unit_norm").fit(us[:3], ys[:3])
    np.testing.assert_allclose(unit.b_, B_TRUE / math.sqrt(1.25), rtol=0.01)


def test_refine_linear_keeps_the_recovery(hammerstein_data):
    us, ys = hammerstein_data
    model = HammersteinLSSVM(na=2, nb=2, gamma=1e4, refine_linear=True).fit(us[:3], ys[:3])
    np.testing.assert_allclose(model.a_, A_TRUE, rtol=0.01)
    np.testing.assert_allclose(model.b_.sum(), 1.0 - model.a_.sum(), rtol=1e-12)
    np.testing.assert_allclose(model.b_, B_TRUE / STATIC_GAIN, rtol=0.01)


def test_wiener_data_raise_the_singular_value_ratio(hammerstein_fit):
    us = inputs(1, 3)
    model = HammersteinLSSVM(na=2, nb=2, gamma=1e6).fit(us, [wiener(u) for u in us])
    assert model.singular_value_ratio_ > 0.02
    assert model.singular_value_ratio_ > 100 * hammerstein_fit.singular_value_ratio_


def test_pole_check():
    # z^2 - 1.2 z + 0.5: complex pair with |p|^2 = 0.5
    np.testing.assert_allclose(np.abs(ar_poles(A_TRUE)), [math.sqrt(0.5)] * 2)
    assert is_stable(A_TRUE)
    # z^2 - 2.5 z + 1 = (z - 2)(z - 0.5)
    np.testing.assert_allclose(np.sort(ar_poles([2.5, -1.0]).real), [0.5, 2.0])
    assert not is_stable([2.5, -1.0])
    assert not is_stable([1.0])                  # integrator: pole on the unit circle


def test_unstable_system_is_flagged():
    u = inputs(3, 1, length=80)[0]
    y = arx(f_true(u), np.array([1.05]), np.array([1.0]))
    model = HammersteinLSSVM(na=1, nb=1, gamma=1e6, normalisation="b0").fit(u, y)
    assert model.a_[0] > 1.0
    assert not model.stable_
    assert np.abs(model.poles_).max() > 1.0


@pytest.mark.parametrize("u, y, message", [
    (np.zeros(20), np.zeros(19), "same number of samples, found 20 and 19"),
    (np.zeros((20, 1, 1)), np.zeros(20), r"\(n_samples, n_inputs\), found shape \(20, 1, 1\)"),
    (np.r_[np.zeros(19), np.nan], np.zeros(20), "NaN"),
    ([np.zeros(20), np.zeros(3)], [np.zeros(20), np.zeros(3)], r"u\[1\]: expected at least"),
    ([np.zeros(20)], np.zeros(20), "both as one experiment"),
])
def test_bad_data_raise(u, y, message):
    with pytest.raises(DataInputError, match=message):
        HammersteinLSSVM(na=3, nb=2).fit(u, y)


@pytest.mark.parametrize("kwargs, message", [
    ({"na": -1}, "na: expected an integer >= 0"),
    ({"nb": 2.0}, "integer"),
    ({"gamma": 0.0}, "gamma"),
    ({"sigma2": np.inf}, "sigma2"),
    ({"normalisation": "gain"}, "static_gain, b0, unit_norm"),
])
def test_bad_hyperparameters_raise(kwargs, message):
    u = np.linspace(-1.0, 1.0, 30)
    with pytest.raises(ValueError, match=message):
        HammersteinLSSVM(**kwargs).fit(u, u)


def test_simulate_checks_its_inputs(hammerstein_fit):
    with pytest.raises(ValueError, match="y_init"):
        hammerstein_fit.simulate(np.zeros(10), np.zeros(1))
    with pytest.raises(ValueError, match="not fitted"):
        HammersteinLSSVM().simulate(np.zeros(10), np.zeros(6))
