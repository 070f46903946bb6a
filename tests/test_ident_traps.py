"""The traps a system-identification engineer met in certkit.ident (issue 29), one test each.

Every expected value is worked out here: the signature convention from its statement, the
memory of a dense kernel from its size (three N × N arrays of doubles), the edges of a
search from the ranges given, the reasons from systems built to fail in a known way.
"""

import inspect
import os
from contextlib import contextmanager

import numpy as np
import pytest
from threadpoolctl import threadpool_limits

from certkit.errors import DataInputError, KeywordArgumentError
from certkit.ident import (ARX, NARX, FixedSizeLSSVM, HammersteinLSSVM, LSSVMRegressor,
                           WienerLSSVM, tune_free_run)


@pytest.fixture(autouse=True, scope="module")
def one_blas_thread():
    with threadpool_limits(limits=1):
        yield


# --------------------------------------------------------------------- 1. signatures
ESTIMATORS = (ARX, NARX, HammersteinLSSVM, WienerLSSVM, LSSVMRegressor, FixedSizeLSSVM)


@pytest.mark.parametrize("cls", ESTIMATORS, ids=lambda c: c.__name__)
def test_only_the_orders_are_positional(cls):
    parameters = inspect.signature(cls).parameters.values()
    positional = [p.name for p in parameters if p.kind is p.POSITIONAL_OR_KEYWORD]
    assert positional == (["na", "nb"] if "na" in inspect.signature(cls).parameters else [])


def test_shared_parameters_have_the_same_names_everywhere():
    names = {cls: set(inspect.signature(cls).parameters) for cls in ESTIMATORS}
    for cls in (ARX, NARX, HammersteinLSSVM, WienerLSSVM):
        assert {"na", "nb", "delay"} <= names[cls], cls
    for cls in (NARX, HammersteinLSSVM, WienerLSSVM, LSSVMRegressor, FixedSizeLSSVM):
        assert {"gamma", "sigma2"} <= names[cls], cls
    for cls in (NARX, HammersteinLSSVM, WienerLSSVM):
        assert {"engine", "prototypes", "random_state"} <= names[cls], cls


@pytest.mark.parametrize("call, named, written", [
    (lambda: NARX(2, 2, 1, 10.0, 1.0), "delay, gamma, sigma2",
     "NARX(2, 2, delay=1, gamma=10.0, sigma2=1.0)"),
    # the call: the third place was gamma in HammersteinLSSVM's earlier signature
    (lambda: HammersteinLSSVM(4, 4, 0), "gamma", "HammersteinLSSVM(4, 4, gamma=0)"),
    (lambda: WienerLSSVM(6, 4, 0, 1e3), "delay, gamma", "WienerLSSVM(6, 4, delay=0, gamma=1000.0)"),
    (lambda: ARX(2, 2, 1, fit_intercept=False), "delay",
     "ARX(2, 2, delay=1, fit_intercept=False)"),
    (lambda: LSSVMRegressor(10.0, 1.0), "gamma, sigma2", "LSSVMRegressor(gamma=10.0, sigma2=1.0)"),
    (lambda: FixedSizeLSSVM(10.0, 1.0, prototypes=50), "gamma, sigma2",
     "FixedSizeLSSVM(gamma=10.0, sigma2=1.0, prototypes=50)"),
])
def test_a_positional_hyper_parameter_is_refused_naming_it(call, named, written):
    with pytest.raises(TypeError) as raised:
        call()
    error = raised.value
    assert isinstance(error, KeywordArgumentError) and isinstance(error, DataInputError)
    assert error.problems[0].key == named
    assert "by keyword" in str(error) and written in str(error)


# --------------------------------------------------------------------- 2. size guards
@contextmanager
def address_space_limit(extra: int):
    """Refuse allocations beyond the process's present address space plus ``extra`` bytes
    (Linux), so that a guard that failed to fire raises MemoryError in the test instead of
    paging a shared machine."""
    resource = pytest.importorskip("resource")
    try:
        with open("/proc/self/statm", encoding="ascii") as statm:
            present = int(statm.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
    except OSError:
        yield
        return
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    resource.setrlimit(resource.RLIMIT_AS, (present + extra, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


def first_order(u):
    """y_t = 0.8 y_{t−1} + tanh(u_{t−1}), from rest."""
    y = np.zeros(u.size)
    for t in range(1, u.size):
        y[t] = 0.8 * y[t - 1] + np.tanh(u[t - 1])
    return y


@pytest.mark.parametrize("make, rows, needed, advice", [
    # the record: 40 960 samples; NARX(2, 2) starts its rows after a 2-sample lag
    # window, so 40 958 rows; 3 × 8 × 40 958² B = 37.5 GiB
    (lambda: NARX(2, 2, gamma=10.0, sigma2=1.0), "40,958 rows", "37.5 GiB",
     "engine='fixed-size' with prototypes=300"),
    # the Hammerstein dual spans every sample: 3 × 8 × 40 960² B = 37.5 GiB
    (lambda: HammersteinLSSVM(2, 2), "40,960 rows", "37.5 GiB",
     "engine='fixed-size' with prototypes=100"),
    (lambda: WienerLSSVM(2, 2, gamma=10.0, sigma2=1.0), "40,960 rows", "37.5 GiB",
     "engine='fixed-size' with prototypes=100"),
], ids=["NARX", "Hammerstein", "Wiener"])
def test_a_full_engine_too_large_is_refused_with_the_option_that_fits(make, rows, needed,
                                                                       advice, monkeypatch):
    monkeypatch.setattr("certkit.ident.sizing.MEMORY_BUDGET", 2 * 2**30)   # a 4 GiB machine
    u = np.random.default_rng(0).uniform(-1.0, 1.0, 40_960)
    y = first_order(u)
    with address_space_limit(3 * 2**30), pytest.raises(DataInputError) as raised:
        make().fit(u, y)
    text = str(raised.value)
    assert raised.value.problems[0].key == "engine"
    assert rows in text and needed in text and "2 GiB" in text and advice in text


def test_a_dense_ls_svm_too_large_is_refused_naming_the_fixed_size_one(monkeypatch):
    monkeypatch.setattr("certkit.ident.sizing.MEMORY_BUDGET", 2 * 2**30)
    X = np.random.default_rng(1).standard_normal((20_000, 2))
    with address_space_limit(3 * 2**30), pytest.raises(DataInputError) as raised:
        LSSVMRegressor(gamma=1.0, sigma2=1.0).fit(X, X[:, 0])
    # 3 × 8 × 20 000² B = 9.6e9 B = 8.94 GiB
    assert "20,000 rows" in str(raised.value) and "8.94 GiB" in str(raised.value)
    assert "FixedSizeLSSVM(" in str(raised.value)


def test_auto_takes_the_dual_up_to_5000_samples_and_the_fixed_size_engine_above():
    from certkit.ident.sizing import choose_engine
    # the rule at its boundary (counts only: nothing is fitted)
    assert choose_engine("NARX", "auto", 5_000, 4_998, 300)[0] == "full"
    assert choose_engine("NARX", "auto", 5_001, 4_999, 300)[0] == "fixed-size"
    assert choose_engine("NARX", "auto", 100, 98, 300, "a parametric part needs it")[0] \
        == "fixed-size"


@pytest.mark.parametrize("make", [
    lambda **engine: NARX(1, 1, gamma=100.0, sigma2=2.0, prototypes=40, **engine),
    lambda **engine: HammersteinLSSVM(1, 2, gamma=100.0, sigma2=1.0, prototypes=40, **engine),
    lambda **engine: WienerLSSVM(1, 2, gamma=100.0, sigma2=1.0, prototypes=40, **engine),
], ids=["NARX", "Hammerstein", "Wiener"])
def test_auto_picks_by_size_says_why_and_fits_what_it_picked(make):
    u = np.random.default_rng(2).uniform(-1.0, 1.0, 6_500)
    y = first_order(u)
    for n, engine, said in ((1_000, "full", "1,000 training samples are at most "
                                            "AUTO_FULL_SAMPLES = 5,000"),
                            (6_000, "fixed-size", "6,000 training samples are more than "
                                                  "AUTO_FULL_SAMPLES = 5,000")):
        auto = make(engine="auto").fit(u[:n], y[:n])
        assert auto.engine_ == engine and said in auto.engine_reason_
        given = make(engine=engine).fit(u[:n], y[:n])
        assert given.engine_reason_ == f"engine={engine!r} as given"
        assert np.array_equal(auto.simulate(u[n:], y[n:n + 2]),
                              given.simulate(u[n:], y[n:n + 2]))


def test_a_search_tunes_with_the_engine_auto_takes_on_all_the_data():
    # 5 400 samples: "auto" takes the fixed-size engine; each of 8 folds trains on 4 725,
    # where "auto" alone would take the dual, so the folds must be told
    u = np.random.default_rng(3).uniform(-1.0, 1.0, 5_400)
    seen = []

    def cost(estimator, pairs):
        seen.append(estimator.engine)
        return 1.0

    model, _ = tune_free_run(NARX(1, 1, engine="auto", prototypes=30), u, first_order(u),
                             gamma=10.0, sigma2=2.0, cost=cost)
    assert seen == ["fixed-size"] and model.engine_ == "fixed-size"
