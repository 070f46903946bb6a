"""SysIdentPy's FROLS polynomial NARX behind certkit's estimator protocol, for the benchmarks
that print it beside certkit (bench_cascaded_tanks.py, bench_silverbox.py).

SysIdentPy 0.9 is optional and never a certkit dependency (its wheel pins numpy <= 2.3.5):
``pip install --target /tmp/sip sysidentpy==0.9 --no-deps`` and PYTHONPATH=/tmp/sip.
"""

from __future__ import annotations

import warnings

import numpy as np
from sklearn.base import BaseEstimator

INSTALL_HINT = ("optional: pip install --target /tmp/sip sysidentpy==0.9 --no-deps, then "
                "PYTHONPATH=/tmp/sip")


class FROLSNARX(BaseEstimator):
    """FROLS polynomial NARX (AIC term selection over ``n_info_values`` terms) with fit on a
    list of experiments, simulate(u, y_init) and init_length, so that certkit's FreeRunCV
    scores it on the same folds.  SysIdentPy fits one record: experiments are concatenated
    (the few rows that straddle a junction are kept)."""

    def __init__(self, ylag=1, xlag=1, degree=2, n_info_values=20):
        self.ylag, self.xlag, self.degree = ylag, xlag, degree
        self.n_info_values = n_info_values

    @property
    def init_length(self) -> int:
        return max(self.ylag, self.xlag)

    def fit(self, u, y):
        from sysidentpy.basis_function import Polynomial
        from sysidentpy.model_structure_selection import FROLS
        from sysidentpy.parameter_estimation import LeastSquares
        u = np.concatenate(u) if isinstance(u, list) else np.asarray(u)
        y = np.concatenate(y) if isinstance(y, list) else np.asarray(y)
        self.model_ = FROLS(order_selection=True, n_info_values=self.n_info_values,
                            ylag=self.ylag, xlag=self.xlag, info_criteria="aic",
                            estimator=LeastSquares(),
                            basis_function=Polynomial(degree=self.degree))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            self.model_.fit(X=u.reshape(len(y), -1), y=y[:, None])
        return self

    def simulate(self, u, y_init):
        u = np.asarray(u, dtype=float)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            out = self.model_.predict(X=u.reshape(u.shape[0], -1),
                                      y=np.asarray(y_init)[:, None])[:, 0].copy()
        out[:len(y_init)] = y_init
        return out
