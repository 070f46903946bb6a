"""The traps a system-identification engineer met in certkit.ident (issue 29), one test each.

Every expected value is worked out here: the signature convention from its statement, the
memory of a dense kernel from its size (three N × N arrays of doubles), the edges of a
search from the ranges given, the reasons from systems built to fail in a known way.
"""

import inspect
import math
import os
from contextlib import contextmanager

import numpy as np
import pytest
from threadpoolctl import threadpool_limits

from certkit.errors import DataInputError, KeywordArgumentError
from certkit.ident import (ARX, NARX, FixedSizeLSSVM, FreeRunCV, HammersteinLSSVM,
                           LSSVMRegressor, WienerLSSVM, tune_free_run)
from certkit.ident.dynamic_model import DynamicModel
from certkit.ident.search_space import SearchEdge, SearchEdgeWarning


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


# --------------------------------------------------------------------- 3. edges and reasons
def by_hand(estimator, pairs):
    """A cost written here: least at the largest γ, and at σ² = 1 (log10 σ² = 0)."""
    return 1.0 / estimator.gamma + math.log10(estimator.sigma2) ** 2


RANGES = {"gamma": (1e-1, 1e5), "sigma2": (1e-2, 1e2)}     # 5 grid points: 1 per 1.5 dec.


def test_a_choice_on_the_upper_end_of_gamma_is_warned_and_recorded():
    u = np.random.default_rng(4).standard_normal(60)
    with pytest.warns(SearchEdgeWarning, match=r"gamma = 1e\+05 lies on the upper end"):
        model, surface = tune_free_run(HammersteinLSSVM(1, 1), u, u, cost=by_hand, grid=5,
                                       refine=False, **RANGES)
    assert (model.gamma, model.sigma2) == pytest.approx((1e5, 1.0))
    edge, = surface.edges
    assert (edge.parameter, edge.side, edge.value, edge.bound) == ("gamma", "upper", 1e5, 1e5)
    assert "widen it upwards, e.g. gamma=(0.1, 1e+07)" in edge.advice


def test_both_lower_corners_are_named_and_an_inner_choice_is_silent(recwarn):
    u = np.random.default_rng(5).standard_normal(60)
    with pytest.warns(SearchEdgeWarning) as caught:
        _, surface = tune_free_run(HammersteinLSSVM(1, 1), u, u, grid=5, refine=False,
                                   cost=lambda e, p: e.gamma + e.sigma2, **RANGES)
    assert len(caught) == 1
    assert [(e.parameter, e.side, e.bound) for e in surface.edges] == [
        ("gamma", "lower", 0.1), ("sigma2", "lower", 0.01)]
    assert "widen it downwards, e.g. sigma2=(0.0001, 100)" in surface.edges[1].advice
    # least at (γ, σ²) = (10^0.5, 1), two inner grid points: no edge, no warning
    _, inner = tune_free_run(HammersteinLSSVM(1, 1), u, u, grid=5, refine=False,
                             cost=lambda e, p: (math.log10(e.gamma) - 0.5) ** 2
                             + math.log10(e.sigma2) ** 2, **RANGES)
    assert inner.edges == () and len(recwarn) == 0


def test_an_order_at_the_end_of_its_list_is_an_edge():
    u = np.random.default_rng(6).standard_normal(60)

    def cost(estimator, pairs):          # least for the longest AR part listed
        return 1.0 / (1 + estimator.na)

    with pytest.warns(SearchEdgeWarning, match="na = 3 is the largest value searched: add "
                                               "larger values"):
        _, surface = tune_free_run(HammersteinLSSVM(1, 1), u, u, cost=cost,
                                   orders={"na": [2, 1, 3]}, gamma=10.0, sigma2=1.0)
    assert surface.edges == (SearchEdge("na", "upper", 3, 3, surface.edges[0].advice),)


def test_narx_tuning_itself_warns_when_it_lands_on_an_edge():
    # a 2 x 2 grid without refinement has only corners: whatever it picks is on two edges
    u = np.random.default_rng(7).uniform(-1.0, 1.0, 200)
    with pytest.warns(SearchEdgeWarning, match="NARX's own tuning"):
        model = NARX(1, 1, folds=2, tuning={"grid": 2, "refine": False}).fit(u, first_order(u))
    assert {e.parameter for e in model.tuning_.edges} == {"gamma", "sigma2"}


class Recursion(DynamicModel):
    """y_t = pole·y_{t−1} + u_{t−1} (a product of arrays, as a kernel model's matmul), with
    nothing to fit: a negative pole is refused by ``fit`` (a failed fit), |pole| > 1 grows
    as pole^t (a divergence).  ``reports_stability``: the fitted model says whether its
    pole is stable, as ARX and Hammerstein models do (``stable_``, ``poles_``)."""

    def __init__(self, pole=0.5, reports_stability=False):
        self.pole = pole
        self.reports_stability = reports_stability

    def _fit(self, pairs):
        if self.pole < 0:
            raise ValueError(f"this test model refuses the negative pole {self.pole}")
        if self.reports_stability:
            self.stable_, self.poles_ = abs(self.pole) < 1, np.array([self.pole])

    @property
    def init_length(self):
        return 1

    def _simulate_one(self, u, y_init):
        y = np.empty(u.shape[0])
        y[:y_init.size] = y_init
        for t in range(y_init.size, y.size):
            y[t] = (np.array([self.pole]) @ y[t - 1:t]) + u[t - 1, 0]
        return y

    def _one_step(self, u, y):
        return y.copy()


def test_free_run_cv_says_why_a_candidate_is_rejected_and_keeps_its_warnings(recwarn):
    u = np.random.default_rng(8).uniform(-1.0, 1.0, 1024)
    y = Recursion(0.5).fit(u, u).simulate(u, np.zeros(1))
    _, surface = tune_free_run(Recursion(), u, y, cost=FreeRunCV(folds=4, n_init=1),
                               orders={"pole": [0.5, 3.0, 1e200, -1.0],
                                       "reports_stability": [False, True]})
    assert len(recwarn) == 0                  # nothing leaked: overflows went to the record
    first = {(r["pole"], r["reports_stability"]): next(
        (o for o in found if o.rejected), found[-1]) for r, found in zip(surface.rows,
                                                                       surface.outcomes)}
    status = {key: o.status for key, o in first.items()}
    assert status == {(0.5, False): "scored", (0.5, True): "scored",
                      (3.0, False): "diverged", (3.0, True): "unstable",
                      (1e200, False): "diverged", (1e200, True): "unstable",
                      (-1.0, False): "failed fit", (-1.0, True): "failed fit"}
    # pole 3: |y| grows as 3^t, to about 1e120 within a 256-sample block: far outside the
    # band of the training outputs (about ±4.5), but finite
    assert "reached" in first[(3.0, False)].reason and "outside [" in first[(3.0, False)].reason
    assert "unstable (largest |pole| 3)" in first[(3.0, True)].reason
    assert "not finite from sample" in first[(1e200, False)].reason
    assert any(w.startswith("RuntimeWarning: overflow encountered in matmul")
               for w in first[(1e200, False)].warnings)
    assert first[(-1.0, False)].reason == ("ValueError: this test model refuses the negative "
                                           "pole -1.0")
    assert all(math.isinf(r["cost"]) == (r["pole"] != 0.5) for r in surface.rows)
    frame = surface.to_frame()
    assert list(frame.status) == [status[(r["pole"], r["reports_stability"])]
                                  for r in surface.rows]
    assert frame.reason[frame.status == "scored"].eq("").all()


# --------------------------------------------------------------------- 4. tied and listed orders
def searched_orders(orders, estimator=None, **options):
    """The (na, nb) settings tune_free_run gives its cost, in order, and the surface; the
    cost written here is least at na = nb = 3."""
    seen = []

    def cost(candidate, pairs):
        seen.append((candidate.na, candidate.nb))
        return abs(candidate.na - 3) + abs(candidate.nb - 3) + 1.0

    u = np.random.default_rng(9).standard_normal(80)
    _, surface = tune_free_run(estimator or ARX(delay=1), u, first_order(u), cost=cost,
                               orders=orders, **options)
    return seen, surface


def test_a_tie_searches_na_equal_to_nb_only(recwarn):
    seen, surface = searched_orders({"na": [1, 2, 3], "nb": "na"})
    assert seen == [(1, 1), (2, 2), (3, 3)]
    assert [(r["na"], r["nb"]) for r in surface.rows] == seen
    # the best, na = nb = 3, is the last value listed: one edge, named on the leader
    edge, = surface.edges
    assert (edge.parameter, edge.side) == ("na", "upper") and "nb follows it" in edge.advice
    assert len(recwarn) == 1 and recwarn[0].category is SearchEdgeWarning


def test_a_list_of_settings_is_searched_setting_by_setting():
    seen, surface = searched_orders([{"na": 3, "nb": 3}, {"na": 2, "nb": 4},
                                     {"na": 4, "nb": 1}])
    assert seen == [(3, 3), (2, 4), (4, 1)]
    assert surface.best == {"na": 3, "nb": 3} and surface.edges == ()
    # with (γ, σ²) searched: each setting gets its own grid of 2 x 2 points (all corners)
    with pytest.warns(SearchEdgeWarning):
        seen, surface = searched_orders([{"na": 3, "nb": 3}, {"na": 2, "nb": 4}],
                                        estimator=HammersteinLSSVM(1, 1), grid=2,
                                        refine=False, gamma=(1.0, 10.0), sigma2=(1.0, 10.0))
    assert seen == [(3, 3)] * 4 + [(2, 4)] * 4


@pytest.mark.parametrize("orders, message", [
    ({"nb": "na"}, "nb: expected the name of another order of the grid with a list of "
                   "values to tie nb to, found 'na'"),
    ({"na": [1, 2], "nb": "nb"}, "to tie nb to, found 'nb'"),
    ({"na": [1, 2], "nb": "na", "delay": "nb"}, "to tie delay to, found 'nb'"),
    ({"na": 3}, "na: expected a list of values, or the name of another order to tie it to, "
                "found 3"),
    ({"na": []}, "na: expected at least one value, found an empty list"),
    ({"nx": [1, 2]}, "expected parameters of ARX, found 'nx'"),
    ([], "expected at least one setting, found an empty list"),
    ([{"na": 1}, 3], r"orders\[1\]: expected a dict of parameter values, found 3"),
    ([{"na": 1, "nb": 1}, {"na": 2}], r"orders\[1\]: expected the parameters of orders\[0\] "
                                      r"\(na, nb\), found na"),
    ([{"na": 1}, {"na": 2}, {"na": 1}], r"orders\[2\]: expected settings that differ, found a "
                                        r"repeat of orders\[0\]"),
    (5, "expected a dict of value lists \\(a grid\\) or a list of dicts"),
])
def test_bad_orders_are_refused_with_what_was_expected(orders, message):
    u = np.random.default_rng(10).standard_normal(80)
    with pytest.raises(DataInputError, match=message) as raised:
        tune_free_run(ARX(delay=1), u, first_order(u), orders=orders,
                      cost=lambda estimator, pairs: 1.0)
    assert raised.value.problems[0].key == "orders"


def test_gamma_and_sigma2_are_searched_by_their_ranges_not_as_orders():
    u = np.random.default_rng(11).standard_normal(80)
    with pytest.raises(DataInputError, match="found 'gamma', which is searched by its range"):
        tune_free_run(NARX(1, 1), u, first_order(u), orders={"gamma": [1.0, 10.0]},
                      cost=lambda estimator, pairs: 1.0)
