"""The partially linear fixed-size LS-SVM and its NARX (issue 17: extrapolation).

Expected values are worked out here, apart from the code under test: numpy's least squares
of the parametric columns written out by hand, difference equations written as loops, and
the model's own one-step predictor (a separate code path from the free-run loop).
"""

import numpy as np
import pytest
from threadpoolctl import threadpool_limits

from certkit.errors import DataInputError
from certkit.ident import NARX, FixedSizeLSSVM


@pytest.fixture(autouse=True, scope="module")
def one_blas_thread():
    with threadpool_limits(limits=1):
        yield


def test_a_penalised_away_kernel_part_leaves_the_least_squares_polynomial():
    rng = np.random.default_rng(0)
    X = rng.uniform(-1.0, 1.0, (500, 3))
    y = 0.5 * X[:, 0] - 0.3 * X[:, 1] + 0.2 * X[:, 2] + 0.4 * X[:, 0] ** 3 \
        - 0.1 * X[:, 0] * X[:, 1] ** 2 + 1.0 + 0.01 * rng.standard_normal(500)
    # every degree-3 monomial of the first two columns: x0³, x0²x1, x0x1², x1³
    design = np.column_stack([X, X[:, 0] ** 3, X[:, 0] ** 2 * X[:, 1], X[:, 0] * X[:, 1] ** 2,
                              X[:, 1] ** 3, np.ones(500)])
    expected = np.linalg.lstsq(design, y, rcond=None)[0]
    model = FixedSizeLSSVM(gamma=1e-12, sigma2=1.0, prototypes=50, linear=True, cubic=2,
                           cubic_terms="all").fit(X, y)
    fitted = np.concatenate([model.linear_, model.cubic_, [model.b_]])
    assert fitted == pytest.approx(expected, abs=1e-6)
    assert model.monomials_.tolist() == [[0, 0, 0], [0, 0, 1], [0, 1, 1], [1, 1, 1]]
    assert model.predict(X) == pytest.approx(design @ expected, abs=1e-6)


def test_the_parametric_part_carries_the_trend_beyond_the_training_range():
    rng = np.random.default_rng(1)
    x = rng.uniform(-1.0, 1.0, 400)
    y = 2.0 * x + 0.3 * np.sin(3.0 * x)
    far = np.array([[2.5], [3.0]])
    truth = 2.0 * far[:, 0] + 0.3 * np.sin(3.0 * far[:, 0])
    plain = FixedSizeLSSVM(gamma=1e4, sigma2=0.5, prototypes=60).fit(x, y)
    partial = FixedSizeLSSVM(gamma=1e4, sigma2=0.5, prototypes=60, linear=True).fit(x, y)
    inside = np.linspace(-0.9, 0.9, 50)[:, None]
    assert partial.predict(inside) == pytest.approx(plain.predict(inside), abs=0.01)
    # the RBF part fades away from the data: the plain model falls back towards b
    assert np.max(np.abs(plain.predict(far) - truth)) > 2.0
    assert np.max(np.abs(partial.predict(far) - truth)) < 0.8


def duffing_like(u, a=(1.2, -0.5), k3=-0.1, b=0.5):
    """y_t = 1.2 y_{t−1} − 0.5 y_{t−2} − 0.1 y_{t−1}³ + 0.5 u_t (a loop)."""
    y = np.zeros(u.size)
    for t in range(u.size):
        y1 = y[t - 1] if t >= 1 else 0.0
        y2 = y[t - 2] if t >= 2 else 0.0
        y[t] = a[0] * y1 + a[1] * y2 + k3 * y1 ** 3 + b * u[t]
    return y


def test_narx_with_a_cubic_output_term_extrapolates_a_duffing_recursion():
    rng = np.random.default_rng(2)
    u_train = rng.uniform(-1.0, 1.0, 3000)
    u_far = 1.6 * rng.uniform(-1.0, 1.0, 600)          # 60 % beyond the training amplitude
    y_train, y_far = duffing_like(u_train), duffing_like(u_far)
    assert np.abs(y_far).max() > 1.3 * np.abs(y_train).max()
    options = dict(na=2, nb=1, delay=0, gamma=1e2, sigma2=20.0, engine="fixed-size",
                   prototypes=100)
    plain = NARX(**options).fit(u_train, y_train)
    cubic = NARX(**options, linear=True, cubic=1).fit(u_train, y_train)
    scale = np.std(y_far)
    err_plain = np.sqrt(np.mean((plain.simulate(u_far, y_far[:2]) - y_far) ** 2)) / scale
    err_cubic = np.sqrt(np.mean((cubic.simulate(u_far, y_far[:2]) - y_far) ** 2)) / scale
    assert err_cubic < 0.01
    assert err_plain > 10 * err_cubic
    # the fitted parametric part is the recursion itself (standardised units: y/σ_y, u/σ_u)
    reg, sy, su = cubic.regressor_, cubic.y_std_, cubic.u_std_[0]
    assert reg.linear_[:2] == pytest.approx([1.2, -0.5], abs=0.01)
    assert reg.cubic_[0] == pytest.approx(-0.1 * sy ** 2, rel=0.02)
    assert reg.linear_[2] == pytest.approx(0.5 * su / sy, rel=0.02)


@pytest.mark.parametrize("terms", ["cubes", "all"])
def test_the_free_run_loop_agrees_with_the_one_step_predictor_on_its_own_outputs(terms):
    rng = np.random.default_rng(3)
    u = rng.uniform(-1.0, 1.0, (800, 2))
    y = duffing_like(u[:, 0] + 0.5 * np.roll(u[:, 1], 2)) + 0.01 * rng.standard_normal(800)
    model = NARX(na=3, nb=[2, 1], delay=[0, 1], gamma=1e3, sigma2=10.0,
                 engine="fixed-size", prototypes=80, linear=True, cubic=3,
                 cubic_terms=terms).fit(u[:600], y[:600])
    simulated = model.simulate(u[600:], y[600:603])
    # fed its own outputs as if measured, the one-step predictor must give them back
    replay = model.predict(u[600:], simulated)
    assert replay[3:] == pytest.approx(simulated[3:], abs=1e-9)


@pytest.mark.parametrize("options, message", [
    (dict(engine="full", linear=True), "engine='fixed-size'"),
    (dict(engine="fixed-size", linear=False, cubic=1), "linear=True"),
    (dict(engine="fixed-size", linear=True, cubic=3), "at most na = 2"),
    (dict(engine="fixed-size", linear=True, cubic=1, cubic_terms="squares"), "cubes, all"),
])
def test_bad_parametric_options_get_certkit_input_errors(options, message):
    u = np.random.default_rng(4).standard_normal(300)
    with pytest.raises(DataInputError, match=message):
        NARX(na=2, nb=1, gamma=10.0, sigma2=5.0, prototypes=40, **options).fit(u, np.cumsum(u))
