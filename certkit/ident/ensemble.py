"""An average of identified models: each runs its own free run (or one-step prediction) and
the outputs are averaged — what :func:`certkit.ident.tune_free_run` returns with
``ensemble=K``.

Averaging the outputs of several models fitted with different hyper-parameters reduces the
variance of a choice made on a short record: the mean of K predictors has a squared error
no larger than their average squared error, by the convexity of the square (the
"ambiguity decomposition", Krogh & Vedelsby 1995); bagging (Breiman 1996) averages models
fitted on resampled data for the same reason.

References
----------
A. Krogh, J. Vedelsby, "Neural network ensembles, cross validation, and active learning",
Advances in Neural Information Processing Systems 7 (1995) 231-238.
L. Breiman, "Bagging predictors", Machine Learning 24 (1996) 123-140.
"""

from __future__ import annotations

import numpy as np
from sklearn.base import clone

from certkit.errors import DataInputError
from certkit.ident.dynamic_model import DynamicModel


class EnsembleModel(DynamicModel):
    """The mean of several identified models (scikit-learn compatible).

    Parameters
    ----------
    estimators : sequence of DynamicModel
        The members, unfitted (clones are fitted on the same data by :meth:`fit`).

    Attributes
    ----------
    estimators_ : list of DynamicModel
        The fitted members.

    Notes
    -----
    :meth:`simulate` is the mean of the members' free runs, each from the same measured
    ``y_init`` (or from rest), never a free run of an averaged map: each member feeds back
    its own outputs.  ``predict(u, y)`` is the mean of the members' one-step predictions.
    :attr:`init_length` is the largest of the members'.
    """

    def __init__(self, estimators=()):
        self.estimators = estimators

    def _fit(self, pairs) -> None:
        if len(self.estimators) == 0:
            raise DataInputError("estimators", "expected at least one member model, found "
                                               "none")
        us, ys = [p[0] for p in pairs], [p[1] for p in pairs]
        self.estimators_ = [clone(e).fit(us, ys) for e in self.estimators]

    @property
    def init_length(self) -> int:
        members = getattr(self, "estimators_", None) or self.estimators
        return max(e.init_length for e in members)

    def _simulate_one(self, u: np.ndarray, y_init: np.ndarray) -> np.ndarray:
        return np.mean([e.simulate(u, y_init) for e in self.estimators_], axis=0)

    def _from_rest(self, u: np.ndarray) -> np.ndarray:
        return np.mean([e.simulate(u) for e in self.estimators_], axis=0)

    def _one_step(self, u: np.ndarray, y: np.ndarray) -> np.ndarray:
        return np.mean([e.predict(u, y) for e in self.estimators_], axis=0)
