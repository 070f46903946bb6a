"""Robust free-run tuning (blocked folds, rejection of unstable candidates, ensembles) and the
NARX structure options it tunes (input low-pass regressor, output bound) — issue 17."""

import math

import numpy as np
import pytest
from scipy.signal import lfilter, lfilter_zi
from sklearn.base import clone

from certkit.errors import DataInputError
from certkit.ident import NARX, EnsembleModel, FoldOutcome, FreeRunCV, tune_free_run
from certkit.ident.dynamic_model import DynamicModel


# ------------------------------------------------------------------ helpers
class SwitchedFirstOrder(DynamicModel):
    """y_t = a(u_{t−1})·y_{t−1} + u_{t−1}: pole ``low`` for |u| ≤ 1.5, ``high`` above (a
    model whose stability depends on the input level, so on the fold)."""

    def __init__(self, low=0.5, high=0.5):
        self.low = low
        self.high = high

    def _fit(self, pairs):
        self.fitted_ = True

    @property
    def init_length(self):
        return 1

    def _step(self, y_prev, u_prev):
        return (self.high if abs(u_prev) > 1.5 else self.low) * y_prev + u_prev

    def _simulate_one(self, u, y_init):
        y = np.empty(u.shape[0])
        y[:y_init.size] = y_init
        for t in range(y_init.size, y.size):
            y[t] = self._step(y[t - 1], u[t - 1, 0])
        return y

    def _one_step(self, u, y):
        out = y.copy()
        for t in range(1, y.size):
            out[t] = self._step(y[t - 1], u[t - 1, 0])
        return out


def switched_record(n=1024, seed=0):
    """Input in [−1, 1] except one block of 128 samples at 1.6-2.0 (the 4th of 8)."""
    rng = np.random.default_rng(seed)
    u = rng.uniform(-1.0, 1.0, n)
    u[384:512] = rng.uniform(1.6, 2.0, 128)
    y = SwitchedFirstOrder(0.5, 0.5).fit(u, np.zeros(n)).simulate(u, np.zeros(1))
    return u, y


def hidden_state_record(n, pole=0.9, seed=1):
    """y_t = 0.3·y_{t−1} + 4·x_t² + noise, x the first-order low-pass of u with pole
    ``pole``: x's sign never shows in y, so no lag of u or y gives the state."""
    rng = np.random.default_rng(seed)
    u = np.repeat(rng.uniform(-1.0, 1.0, n // 8 + 1), 8)[:n]       # slow steps
    x, y = np.zeros(n), np.zeros(n)
    for t in range(1, n):
        x[t] = pole * x[t - 1] + (1 - pole) * u[t - 1]
        y[t] = 0.3 * y[t - 1] + 4.0 * x[t] ** 2
    return u, y + 0.005 * rng.standard_normal(n)


# ------------------------------------------------------------------ tuning
@pytest.mark.slow   # 20 s of fold fits: CI runs it
def test_blocked_fold_tuning_finds_the_hidden_filter_pole():
    u, y = hidden_state_record(800)
    model, surface = tune_free_run(
        NARX(na=1, nb=1, delay=1, filter_pole=0.5), u, y,
        orders={"filter_pole": [0.5, 0.9, 0.99]}, gamma=(1e1, 1e4), sigma2=(1.0, 100.0),
        grid=3, refine=False, cost=FreeRunCV(folds=8, n_init=5))
    assert surface.best["filter_pole"] == 0.9
    assert model.filter_pole == 0.9
    # the tuned model on a fresh record of the same system, against the best of the grid
    u2, y2 = hidden_state_record(400, seed=7)
    errors = []
    for row in surface.rows:
        params = {k: v for k, v in row.items() if k not in ("cost", "stage")}
        other = clone(model).set_params(**params).fit(u, y)
        errors.append(np.sqrt(np.mean((other.simulate(u2, y2[:5]) - y2)[5:] ** 2)))
    chosen = np.sqrt(np.mean((model.simulate(u2, y2[:5]) - y2)[5:] ** 2))
    assert chosen <= np.quantile(errors, 0.25)          # among the best quarter


def test_a_candidate_unstable_on_one_fold_is_rejected():
    u, y = switched_record()
    pairs = [(u[:, None], y)]
    # exact on 7 folds, diverging on the block of large inputs
    unstable = SwitchedFirstOrder(0.5, 1.1)
    assert math.isinf(FreeRunCV(folds=8, n_init=1)(unstable, pairs))
    assert math.isfinite(FreeRunCV(folds=8, n_init=1, divergence=None)(unstable, pairs))
    model, surface = tune_free_run(
        SwitchedFirstOrder(), u, y, orders={"high": [1.1, 0.6, 0.7]},
        cost=FreeRunCV(folds=8, n_init=1), ensemble=3)
    costs = {r["high"]: r["cost"] for r in surface.rows}
    assert math.isinf(costs[1.1]) and math.isfinite(costs[0.6])
    assert [m["high"] for m in surface.members] == [0.6, 0.7]      # 1.1 is no member
    assert isinstance(model, EnsembleModel) and len(model.estimators_) == 2


def test_median_smoothing_prefers_a_good_region_to_an_isolated_minimum():
    u, y = hidden_state_record(200)
    isolated = {(1.0, 1.0): 0.10, (1.0, 10.0): 5.0, (10.0, 1.0): 5.0, (10.0, 10.0): 5.0}

    def table(estimator, pairs):            # a made-up surface: one lucky corner point
        key = (round(estimator.gamma, 6), round(estimator.sigma2, 6))
        return isolated.get(key, 0.2 + 0.01 * key[0] / 100)

    ranges = {"gamma": (1.0, 100.0), "sigma2": (1.0, 100.0), "grid": 3, "refine": False}
    _, raw = tune_free_run(NARX(na=1, nb=1), u, y, cost=table, **ranges)
    assert (raw.best["gamma"], raw.best["sigma2"]) == (1.0, 1.0)
    _, smoothed = tune_free_run(NARX(na=1, nb=1), u, y, cost=table, smoothing="median",
                                **ranges)
    chosen = (smoothed.best["gamma"], smoothed.best["sigma2"])
    assert chosen != (1.0, 1.0) and table(NARX(**smoothed.best), None) < 1.0


# ------------------------------------------------------------------ ensemble
def test_ensemble_simulate_and_predict_are_the_members_means():
    u, y = hidden_state_record(400)
    members = [NARX(na=1, nb=1, gamma=1e2, sigma2=3.0),
               NARX(na=2, nb=1, gamma=1e3, sigma2=10.0, filter_pole=0.9)]
    ensemble = EnsembleModel(members).fit(u, y)
    alone = [clone(m).fit(u, y) for m in members]
    u2, y2 = hidden_state_record(300, seed=3)
    expected = (alone[0].simulate(u2, y2[:4]) + alone[1].simulate(u2, y2[:4])) / 2
    np.testing.assert_allclose(ensemble.simulate(u2, y2[:4]), expected, rtol=0, atol=1e-12)
    np.testing.assert_allclose(ensemble.predict(u2),
                               (alone[0].predict(u2) + alone[1].predict(u2)) / 2, atol=1e-12)
    np.testing.assert_allclose(ensemble.predict(u2, y2),
                               (alone[0].predict(u2, y2) + alone[1].predict(u2, y2)) / 2,
                               atol=1e-12)
    assert ensemble.init_length == 2
    copy = clone(ensemble)
    assert [m.get_params() for m in copy.estimators] == [m.get_params() for m in members]


# ------------------------------------------------------------------ NARX structure options
def test_input_filter_regressor_is_a_first_order_low_pass():
    rng = np.random.default_rng(4)
    u = rng.uniform(0.0, 3.0, 300)
    y = np.convolve(u, [0.0, 0.3, 0.2], mode="full")[:300]
    pole = 0.8
    model = NARX(na=1, nb=1, delay=1, gamma=1e2, sigma2=5.0, filter_pole=pole).fit(u, y)
    us = (u - u.mean()) / u.std()
    b, a = [0.0, 1.0 - pole], [1.0, -pole]       # z_t = p z_{t−1} + (1 − p) u_{t−1}
    z, _ = lfilter(b, a, us, zi=lfilter_zi(b, a) * us[0])      # starts at rest at u_0
    np.testing.assert_allclose(model.regressor_.support_[:, -1], z[1:], atol=1e-12)
    # saturating at a training quantile of the filter state
    capped = NARX(na=1, nb=1, delay=1, gamma=1e2, sigma2=5.0, filter_pole=pole,
                  filter_cap=0.9).fit(u, y)
    cap = np.quantile(z, 0.9)
    expected = np.empty_like(us)
    expected[0] = min(us[0], cap)
    for t in range(1, us.size):
        expected[t] = min(pole * expected[t - 1] + (1 - pole) * us[t - 1], cap)
    np.testing.assert_allclose(capped.regressor_.support_[:, -1], expected[1:], atol=1e-12)


def test_filter_state_is_estimated_from_the_initialisation_window():
    u, y = hidden_state_record(800)
    model = NARX(na=1, nb=1, gamma=1e3, sigma2=10.0, filter_pole=0.9).fit(u, y)
    # a record starting away from rest: the first-input start is wrong, the window tells
    start = 400
    u2, y2 = u[start:], y[start:]
    estimated = model.simulate(u2, y2[:10])
    naive = NARX(na=1, nb=1, gamma=1e3, sigma2=10.0, filter_pole=0.9).fit(u, y)
    first_input = naive.simulate(u2, y2[:1])          # no row in the window: z_0 = u_0
    err = [np.sqrt(np.mean((s - y2)[10:60] ** 2)) for s in (estimated, first_input)]
    assert err[0] < err[1]


@pytest.mark.parametrize("bound", ["upper", "range"])
def test_output_bound_holds_in_free_run(bound):
    rng = np.random.default_rng(5)
    u = rng.uniform(-1.0, 1.0, 400)
    y = np.zeros(400)
    for t in range(1, 400):
        y[t] = 0.8 * y[t - 1] + u[t - 1]
    model = NARX(na=1, nb=1, gamma=1e4, sigma2=50.0, output_bound=bound).fit(u, y)
    loud = 3.0 * np.sign(np.sin(np.arange(400) / 15.0))      # far beyond the training input
    sim = model.simulate(loud, y[:1])
    assert sim[1:].max() <= y.max() + 1e-12
    free = NARX(na=1, nb=1, gamma=1e4, sigma2=50.0).fit(u, y).simulate(loud, y[:1])
    assert free.max() > y.max()                    # the bound is what keeps it inside
    if bound == "range":
        assert sim[1:].min() >= y.min() - 1e-12
    assert model.output_bounds_[1] == pytest.approx(y.max())


# ------------------------------------------------------------------ one-standard-error rule
class ScriptedFolds(FreeRunCV):
    """Fold errors written here by hand for each γ (NRMSE² per fold, 100 samples each)."""

    TABLE = {1e1: [1.2, 1.2, 1.2, 1.2],
             1e2: [1.0, 1.06, 1.02, 1.08],        # mean 1.04
             1e3: [0.9, 1.1, 0.95, 1.05]}         # mean 1.00, SE 0.0456

    def outcomes(self, estimator, pairs):
        variance = float(np.var(np.concatenate([y for _, y in pairs])))
        gamma = min(self.TABLE, key=lambda g: abs(math.log10(g / estimator.gamma)))
        return [FoldOutcome(k, "scored", v * 100 * variance, 100)
                for k, v in enumerate(self.TABLE[gamma])]


def test_one_standard_error_rule_takes_the_most_regularised_candidate_within_one_se():
    # best: γ = 1e3, cost 1.00; its SE = sqrt((0.1² + 0.1² + 0.05² + 0.05²)/3)/2 = 0.0456
    # γ = 1e2 (cost 1.04) is within it, γ = 1e1 (1.20) is not: the rule takes γ = 1e2
    u, y = switched_record(512)
    options = dict(gamma=(1e1, 1e3), sigma2=5.0, grid=(3, 1), refine=False,
                   cost=ScriptedFolds())
    _, least = tune_free_run(NARX(na=1, nb=1), u, y, **options)
    _, parsimonious = tune_free_run(NARX(na=1, nb=1), u, y, rule="one-se", **options)
    assert least.best["gamma"] == pytest.approx(1e3)
    assert parsimonious.best["gamma"] == pytest.approx(1e2)
    assert [r["cost"] for r in parsimonious.rows] == pytest.approx([1.2, 1.04, 1.0])
    _, pair = tune_free_run(NARX(na=1, nb=1), u, y, rule="one-se", ensemble=2, **options)
    assert [m["gamma"] for m in pair.members] == pytest.approx([1e2, 1e3])


def test_fold_errors_pool_to_the_cost():
    u, y = switched_record(512)
    cost = FreeRunCV(folds=4, n_init=1)
    model = NARX(na=1, nb=1, gamma=10.0, sigma2=2.0)
    errors = cost.fold_errors(model, [(u[:, None], y)])
    assert len(errors) == 4 and all(n == 127 for _, n in errors)
    by_hand = sum(q for q, _ in errors) / (4 * 127 * np.var(y))
    assert cost(model, [(u[:, None], y)]) == pytest.approx(by_hand, rel=1e-12)


@pytest.mark.parametrize("options, message", [
    (dict(rule="best"), "min, one-se"),
    (dict(rule="one-se", cost=lambda e, p: 1.0), "FreeRunCV"),
    (dict(rule="one-se", smoothing="median"), "no smoothing"),
])
def test_bad_rules_get_certkit_input_errors(options, message):
    u, y = switched_record(512)
    with pytest.raises(DataInputError, match=message):
        tune_free_run(NARX(na=1, nb=1), u, y, gamma=10.0, sigma2=5.0, **options)


def test_a_wrong_structure_in_the_search_gets_its_own_message():
    # every fold's fit fails on cubic > na; the user must read why, not "diverged"
    u, y = switched_record(512)
    with pytest.raises(DataInputError, match="at most na = 1 output lags, found 2"):
        tune_free_run(NARX(na=1, nb=1, engine="fixed-size", prototypes=20, linear=True), u, y,
                      orders={"cubic": [2]}, gamma=10.0, sigma2=5.0)


def test_a_structure_unstable_everywhere_does_not_stop_the_search_of_the_others():
    # na = 1 with cubic = 2 fails every fit; na = 2 with cubic = 2 is a valid structure
    u, y = switched_record(512)
    model, surface = tune_free_run(
        NARX(na=1, nb=1, engine="fixed-size", prototypes=20, linear=True, cubic=0), u, y,
        orders={"na": [1, 2], "cubic": [0, 2]}, gamma=10.0, sigma2=5.0,
        cost=FreeRunCV(folds=4, n_init=2))
    costs = {(r["na"], r["cubic"]): r["cost"] for r in surface.rows}
    assert math.isinf(costs[(1, 2)])
    assert all(math.isfinite(costs[k]) for k in [(1, 0), (2, 0), (2, 2)])
    assert (surface.best["na"], surface.best["cubic"]) != (1, 2)


@pytest.mark.parametrize("ensemble", [0, 2.5, True])
def test_a_bad_ensemble_size_is_refused_before_any_candidate_is_fitted(ensemble):
    u, y = switched_record(512)
    calls = []
    with pytest.raises(DataInputError, match="ensemble"):
        tune_free_run(NARX(na=1, nb=1), u, y, gamma=10.0, sigma2=5.0, ensemble=ensemble,
                      cost=lambda estimator, pairs: calls.append(estimator) or 1.0)
    assert calls == []
