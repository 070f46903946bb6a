"""The traps a system-identification engineer met in certkit.ident (issue 29), one test each.

Every expected value is worked out here: the signature convention from its statement, the
memory of a dense kernel from its size (three N × N arrays of doubles), the edges of a
search from the ranges given, the reasons from systems built to fail in a known way.
"""

import inspect

import pytest
from threadpoolctl import threadpool_limits

from certkit.errors import DataInputError, KeywordArgumentError
from certkit.ident import (ARX, NARX, FixedSizeLSSVM, HammersteinLSSVM, LSSVMRegressor,
                           WienerLSSVM)


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
    for cls in (NARX, HammersteinLSSVM):
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
