"""The compiled NARX free run (certkit.ident.free_run) and the LS-SVM dual solve against the
plain implementations they replaced, kept here as the references: the Python recursions of
the input filter and of the output (numpy per step), the initial filter state found one
grid value at a time, the dual system factorised in row-major order and solved for one
right-hand side at a time, and the full bordered system solved by numpy."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import linalg
from threadpoolctl import threadpool_limits

from certkit.ident import NARX
from certkit.ident.dynamic_model import input_lags
from certkit.ident.lssvm import (LSSVMRegressor, rbf_kernel, squared_distances,
                                 training_distances)
from certkit.ident.narx import FILTER_STATE_GRID, input_filter, narx_regressors

from .conftest import saturating_plant


@pytest.fixture(autouse=True, scope="module")
def one_blas_thread():
    with threadpool_limits(limits=1):
        yield


# --------------------------------------------------------------------------- references
def reference_filter(u, pole, z0=None, delay=1, cap=np.inf):
    """The Python recursion the compiled filter replaced."""
    u = np.asarray(u, dtype=float)
    z = np.empty(u.size)
    source = np.concatenate([np.full(delay, u[0]), u])[:u.size]
    gain = 1.0 - pole
    z[0] = min(u[0] if z0 is None else z0, cap)
    for t in range(1, u.size):
        z[t] = min(pole * z[t - 1] + gain * source[t], cap)
    return z


def reference_filter_state(model, regressor, u, y_init):
    """The initial filter state found one grid value at a time (rows made per value)."""
    n0, start = y_init.size, model.init_length
    if n0 <= start:
        return None
    X, target = narx_regressors([u[:n0]], [y_init], model._na, model._nb, model._delay)
    z0 = u[0].copy()
    for c in range(u.shape[1]):
        grid = np.linspace(*model.u_range_[c], FILTER_STATE_GRID)
        rows = []
        for value in grid:
            z0[c] = value
            states = np.column_stack([
                reference_filter(u[:n0, k], model.filter_pole, z0[k], model._delay[k],
                                 model.filter_cap_[k]) for k in range(u.shape[1])])
            rows.append(np.hstack([X, states[start:]]))
        error = regressor.predict(np.vstack(rows)).reshape(grid.size, -1) - target
        z0[c] = grid[int(np.argmin(np.einsum("ij,ij->i", error, error)))]
    return z0


def reference_free_run(model, u, y_init):
    """The free run in standardised units as the numpy loop computed it, step by step."""
    (u,), (y_init,) = model._scaled([u], [y_init])
    regressor = model.regressor_
    n, start, na = u.shape[0], y_init.size, model._na
    centres, coef, bias, s2 = (regressor.support_, regressor.alpha_, regressor.b_,
                               regressor.sigma2)
    c_y, c_u = centres[:, :na], centres[:, na:]
    lags = input_lags(model._nb, model._delay)
    states = None
    if model.filter_pole is not None:
        z0 = reference_filter_state(model, regressor, u, y_init)
        starts = u[0] if z0 is None else z0
        states = np.column_stack([
            reference_filter(u[:, k], model.filter_pole, starts[k], model._delay[k],
                             model.filter_cap_[k]) for k in range(u.shape[1])])
    low, high = model._low, model._high
    beta = getattr(regressor, "linear_", np.zeros(centres.shape[1]))
    beta_y, beta_u = beta[:na][::-1], beta[na:]
    theta = getattr(regressor, "cubic_", np.zeros(0))
    monomials = na - 1 - getattr(regressor, "monomials_", np.zeros((0, 3), dtype=int))
    y = np.empty(n)
    y[:start] = y_init
    lin = 2.0 * c_y[:, ::-1] / s2
    offset = -np.sum(c_y * c_y, axis=1) / s2
    t = np.arange(start, n)
    window = np.column_stack([u[t - lag, c] for c, lag in lags]
                             + ([] if states is None else [states[t]]))
    weights = rbf_kernel(window, c_u, s2) * coef
    shift = bias + window @ beta_u
    for row, step in enumerate(t):
        history = y[step - na:step]
        z = lin @ history + offset - (history @ history) / s2
        value = weights[row] @ np.exp(np.minimum(z, 0.0)) + shift[row] + beta_y @ history
        if theta.size:
            value += theta @ np.prod(history[monomials], axis=1)
        y[step] = min(max(value, low), high)
    return y * model.y_std_ + model.y_mean_


# --------------------------------------------------------------------------- the filter
@pytest.mark.parametrize("delay, cap", [(1, np.inf), (2, 0.4), (0, -0.2)])
def test_compiled_filter_gives_the_bytes_of_the_python_recursion(delay, cap):
    u = np.random.default_rng(3).standard_normal(300)
    for z0 in (None, 0.7, -5.0):
        ours = input_filter(u, 0.93, z0, delay, cap)
        assert np.array_equal(ours, reference_filter(u, 0.93, z0, delay, cap))
    # several starting states at once: the columns are the single runs
    starts = np.linspace(-2.0, 2.0, 7)
    both = input_filter(u, 0.93, starts, delay, cap)
    assert both.shape == (300, 7)
    for k, z0 in enumerate(starts):
        assert np.array_equal(both[:, k], reference_filter(u, 0.93, z0, delay, cap))
    assert input_filter(np.zeros(0), 0.9).shape == (0,)


# --------------------------------------------------------------------------- the free run
def _hidden_state_record(n, seed):
    """A record with a slow input state (the reason for the filter) and a saturation."""
    rng = np.random.default_rng(seed)
    u = np.repeat(rng.uniform(0.0, 3.0, n // 20 + 1), 20)[:n] + 0.1 * rng.standard_normal(n)
    x = np.zeros(n)
    y = np.zeros(n)
    for t in range(1, n):
        x[t] = 0.95 * x[t - 1] + 0.05 * u[t - 1]
        y[t] = min(0.8 * y[t - 1] + 0.2 * math.sqrt(max(x[t], 0.0)) + 0.05 * u[t - 1], 2.0)
    return u, y + 0.005 * rng.standard_normal(n)


CASES = {
    "NARX na=2 nb=2": dict(na=2, nb=2, gamma=50.0, sigma2=4.0),
    "filter, cap, output bound": dict(na=2, nb=1, gamma=100.0, sigma2=8.0, filter_pole=0.95,
                                      filter_cap=0.97, output_bound="upper"),
    "filter, range bound, delay 2": dict(na=3, nb=1, delay=2, gamma=20.0, sigma2=10.0,
                                         filter_pole=0.9, output_bound="range"),
    "fixed-size, linear and cubic": dict(na=2, nb=1, gamma=100.0, sigma2=5.0,
                                         engine="fixed-size", prototypes=40, linear=True,
                                         cubic=2, cubic_terms="all"),
}


@pytest.mark.parametrize("settings", CASES.values(), ids=CASES.keys())
def test_compiled_free_run_gives_the_numbers_of_the_numpy_loop(settings):
    u, y = _hidden_state_record(700, seed=5)
    model = NARX(**settings).fit(u[:500], y[:500])
    u_val, y_val = u[500:], y[500:]
    ours = model.simulate(u_val, y_val[:10])
    reference = reference_free_run(model, u_val[:, None], y_val[:10])
    reference[:10] = y_val[:10]
    # the kernel sum is compensated where the loop used BLAS dot products: the same
    # numbers up to rounding, far below any error that matters (1e-12 of the output range)
    scale = np.ptp(y_val)
    assert np.max(np.abs(ours - reference)) <= 1e-12 * scale
    assert np.std(ours[10:] - y_val[10:]) < 0.5 * np.std(y_val)     # a working model


def test_initial_filter_state_gives_the_bytes_of_the_one_value_at_a_time_search():
    u, y = _hidden_state_record(600, seed=8)
    model = NARX(na=2, nb=1, gamma=100.0, sigma2=8.0, filter_pole=0.95,
                 filter_cap=0.97).fit(u[:400], y[:400])
    (us,), (ys,) = model._scaled([u[400:, None]], [y[400:410]])
    ours = model._initial_filter_state(model.regressor_, us, ys)
    assert np.array_equal(ours, reference_filter_state(model, model.regressor_, us, ys))


def test_a_diverging_free_run_stays_not_finite():
    # an unbounded model fed back far outside its training range: NaN or inf, never a
    # finite number made up by the compiled clipping or the kernel's exp(min(z, 0))
    u, y = saturating_plant(300, seed=2, pole=0.7)
    model = NARX(na=1, nb=1, gamma=1e3, sigma2=0.5).fit(u, y)
    regressor = model.regressor_
    regressor.alpha_ = regressor.alpha_.copy()
    regressor.alpha_[:] = np.nan
    assert not np.any(np.isfinite(model.simulate(u[:50], y[:1])[1:]))


# --------------------------------------------------------------------------- the dual solve
def test_training_distances_are_the_lower_triangle_mirrored():
    x = np.random.default_rng(0).standard_normal((120, 3))
    full = squared_distances(x, x)
    ours = training_distances(x)
    assert np.array_equal(ours, ours.T)
    assert np.array_equal(np.tril(ours), np.tril(full))


@pytest.mark.parametrize("bias", [True, False])
def test_dual_solve_gives_the_bytes_of_the_row_major_two_solve_path(bias):
    # the factorisation of H.T in place (column-major, no copy) and one solve for both
    # right-hand sides: the same bytes as the row-major factor and two separate solves
    rng = np.random.default_rng(2)
    X = rng.uniform(-2.0, 2.0, (300, 3))
    y = np.sin(X).sum(axis=1) + 0.05 * rng.standard_normal(300)
    for gamma, sigma2 in [(10.0, 1.0), (1e6, 30.0)]:
        model = LSSVMRegressor(gamma=gamma, sigma2=sigma2, bias=bias).fit(X, y)
        H = np.exp(-training_distances(X) / sigma2)
        H[np.diag_indices_from(H)] += 1.0 / gamma
        factor = linalg.cho_factor(H, lower=True, check_finite=False)
        nu = linalg.cho_solve(factor, y, check_finite=False)
        if bias:
            eta = linalg.cho_solve(factor, np.ones_like(y), check_finite=False)
            b = float(nu.sum() / eta.sum())
            nu = nu - b * eta
        assert np.array_equal(model.alpha_, nu)
        assert model.b_ == (b if bias else 0.0)


@pytest.mark.parametrize("bias", [True, False])
def test_dual_solve_matches_numpy_on_the_full_system(bias):
    # independent: the whole (bordered) system assembled and solved by numpy's LU
    rng = np.random.default_rng(6)
    X = rng.uniform(-3.0, 3.0, (80, 2))
    y = np.cos(X[:, 0]) * X[:, 1] + 1.5
    gamma, sigma2 = 30.0, 2.0
    model = LSSVMRegressor(gamma=gamma, sigma2=sigma2, bias=bias).fit(X, y)
    H = np.exp(-((X[:, None, :] - X[None, :, :]) ** 2).sum(axis=2) / sigma2)
    H += np.eye(80) / gamma
    if bias:
        system = np.block([[np.zeros((1, 1)), np.ones((1, 80))], [np.ones((80, 1)), H]])
        solution = np.linalg.solve(system, np.concatenate([[0.0], y]))
        np.testing.assert_allclose(model.b_, solution[0], rtol=1e-10)
        np.testing.assert_allclose(model.alpha_, solution[1:], rtol=1e-9, atol=1e-10)
    else:
        np.testing.assert_allclose(model.alpha_, np.linalg.solve(H, y), rtol=1e-9,
                                   atol=1e-10)
