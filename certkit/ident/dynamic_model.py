"""What every identified dynamic model shares: the scikit-learn estimator protocol on time
series, free-run simulation from rest or from measured initial outputs, and one-step-ahead
prediction.

The models map input records to output records.  For scikit-learn, ``X`` is the input
``u`` (shape (n,) or (n, n_inputs): one row per time step, one column per input channel)
and ``y`` the output (n,); the rows are consecutive samples of one experiment, not
independent draws.  Several experiments are given as lists (see
:mod:`certkit.ident.experiments`).

What ``predict`` means (scikit-learn calls it without ``y``, e.g. in ``score`` and
``cross_val_score``):

* ``predict(X)`` is the **free-run simulation from rest** (:meth:`DynamicModel.simulate`
  with no initial outputs): only the input is used, so ``score`` is the free-run R², the
  figure a model is validated by (Ljung 1999, §16.6);
* ``predict(X, y)`` with the measured output is the **one-step-ahead prediction**
  ŷ_t = f(y_{t−1}, …, u_{t−d}, …): measured past outputs enter every step (its errors are
  far smaller than the free run's; report which is which).

"From rest" means every input and output is zero before the first sample (deviation
signals from an equilibrium, as a drop from touchdown); for records that do not start
there, give the first measured outputs as ``y_init``.

References
----------
L. Ljung, *System Identification: Theory for the User*, 2nd ed., Prentice Hall, 1999.
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.utils.validation import check_is_fitted, validate_data

from certkit.errors import DataInputError
from certkit.ident.experiments import experiments, inputs_only, is_experiment_list, signal


def _first(data):
    return data[0] if is_experiment_list(data) else data


class DynamicModel(RegressorMixin, BaseEstimator):
    """Base of the identified models: ``fit``, ``simulate``, ``predict``.

    Subclasses set their hyper-parameters in ``__init__`` (stored unchanged) and
    implement ``_fit(pairs)`` (a list of (input (n, n_inputs), output (n,)) experiments),
    ``init_length`` (samples of measured output a free run needs),
    ``_simulate_one(u, y_init)`` and ``_one_step(u, y)``.
    """

    # ------------------------------------------------------------------ scikit-learn
    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.two_d_array = True
        tags.target_tags.single_output = True
        tags.non_deterministic = False
        return tags

    def _feature_check(self, u, reset: bool) -> None:
        """n_features_in_ and feature_names_in_ (a DataFrame's columns), scikit-learn's way."""
        first = _first(u)
        shaped = first if hasattr(first, "columns") else np.asarray(first, dtype=float)
        if shaped.ndim == 1:
            shaped = shaped.reshape(-1, 1)
        validate_data(self, X=shaped, reset=reset, skip_check_array=True)

    # ------------------------------------------------------------------ fitting
    def fit(self, X, y):
        """Identify the model from one experiment or a list of experiments.

        Parameters
        ----------
        X : array_like, shape (n,) or (n, n_inputs), or list of such
            Input record(s) ``u`` [input units]; columns are input channels.
        y : array_like, shape (n,) or (n, 1), or list of such
            Output record(s), each as long as its input [output unit].  Lists are
            separate experiments: no lag window crosses from one into another.

        Returns
        -------
        self
        """
        if y is None:
            raise DataInputError("y", f"{type(self).__name__} requires y to be passed, but the "
                                      f"target y is None: expected the measured output")
        pairs, _ = experiments(X, y)
        self._fit(pairs)
        self._feature_check(X, reset=True)
        return self

    # ------------------------------------------------------------------ use
    def _inputs(self, u):
        check_is_fitted(self)
        us, single = inputs_only(u, self.n_features_in_, who=type(self).__name__)
        self._feature_check(u, reset=False)
        return us, single

    def simulate(self, u, y_init=None):
        """Free-run simulation: the model's own past outputs, never measured ones.

        Parameters
        ----------
        u : array_like, shape (n,) or (n, n_inputs), or list of such
            Input over the whole horizon [input units].
        y_init : array_like, shape (n0,), or list of such, optional
            Measured outputs y_0 … y_{n0−1} that start the free run, with
            :attr:`init_length` ≤ n0 ≤ n; they are copied to the first n0 samples of the
            result.  Omitted: the run starts from rest (every signal zero before sample 0)
            and every sample is simulated.

        Returns
        -------
        numpy.ndarray, shape (n,), or list of them (one per experiment given)
        """
        us, single = self._inputs(u)
        if y_init is None:
            out = [self._from_rest(ue) for ue in us]
        else:
            if is_experiment_list(y_init) == single:
                raise DataInputError("y_init", f"expected {'one array' if single else 'a list'}"
                                     f" of initial outputs, like u")
            inits = [y_init] if single else list(y_init)
            if len(inits) != len(us):
                raise DataInputError("y_init", f"expected {len(us)} initial records (one per "
                                               f"experiment of u), found {len(inits)}")
            out = []
            for k, (ue, ie) in enumerate(zip(us, inits)):
                name = "y_init" if single else f"y_init[{k}]"
                ie = signal(name, ie)
                if not self.init_length <= ie.size <= ue.shape[0]:
                    raise DataInputError(name, f"expected between init_length = "
                                               f"{self.init_length} and len(u) = {ue.shape[0]}"
                                               f" initial outputs, found {ie.size}")
                simulated = self._simulate_one(ue, ie)
                simulated[:ie.size] = ie
                out.append(simulated)
        return out[0] if single else out

    def _from_rest(self, u: np.ndarray) -> np.ndarray:
        """Free run with zero inputs and outputs before sample 0."""
        pad = self.init_length
        padded = np.vstack([np.zeros((pad, u.shape[1])), u])
        return self._simulate_one(padded, np.zeros(pad))[pad:]

    def predict(self, X, y=None):
        """Free-run simulation from rest (``y`` omitted), or the one-step-ahead prediction.

        Parameters
        ----------
        X : array_like, shape (n,) or (n, n_inputs), or list of such
            Input record(s).
        y : array_like, shape (n,), or list of such, optional
            Measured output(s).  Given: ŷ_t from measured past outputs (one step ahead);
            the first :attr:`init_length` samples, where no prediction exists, are copied
            from ``y``.  Omitted: :meth:`simulate` from rest, what scikit-learn's
            ``score`` and cross-validation then measure.

        Returns
        -------
        numpy.ndarray, shape (n,), or list of them
        """
        if y is None:
            return self.simulate(X)
        check_is_fitted(self)
        pairs, single = experiments(X, y, n_channels=self.n_features_in_,
                                    who=type(self).__name__)
        self._feature_check(X, reset=False)
        out = []
        for k, (ue, ye) in enumerate(pairs):
            if ye.size <= self.init_length:
                raise DataInputError("y" if single else f"y[{k}]",
                                     f"expected more than init_length = {self.init_length} "
                                     f"samples for a one-step prediction, found {ye.size}")
            out.append(self._one_step(ue, ye))
        return out[0] if single else out


def lagged(x: np.ndarray, t: np.ndarray, lags) -> np.ndarray:
    """Columns x[t − l] for each lag l (rows t), as an array of shape (len(t), len(lags))."""
    return np.column_stack([x[t - lag] for lag in lags]) if len(lags) else \
        np.empty((t.size, 0))


def input_lags(nb: tuple[int, ...], delay: tuple[int, ...]) -> list[tuple[int, int]]:
    """(channel, lag) of every input regressor: lags delay_c … delay_c + nb_c − 1."""
    return [(c, delay[c] + j) for c in range(len(nb)) for j in range(nb[c])]


def regressors(u: np.ndarray, y: np.ndarray, t: np.ndarray, na: int, nb: tuple[int, ...],
               delay: tuple[int, ...]) -> np.ndarray:
    """Rows x_t = [y_{t−1} … y_{t−na}, u_{1,t−d₁} … u_{1,t−d₁−nb₁+1}, u_{2,t−d₂} …] of one
    experiment (u of shape (n, n_inputs)), for the samples t: the regressors of ARX and NARX
    (Ljung, System Identification, 2nd ed., 1999, eqs. 4.11-4.12 and 5.51)."""
    columns = [lagged(y, t, range(1, na + 1))]
    columns += [u[t - lag, c][:, None] for c, lag in input_lags(nb, delay)]
    return np.hstack(columns)


def lag_window(pairs, na: int, nb: tuple[int, ...], delay: tuple[int, ...]) -> int:
    """t0 = max(na, d_c + nb_c − 1), the first sample with a regression row, after checking
    that every (u, y) experiment has one."""
    start = max([na] + [d + n - 1 for d, n in zip(delay, nb)])
    for k, (_, y) in enumerate(pairs):
        if y.size <= start:
            raise DataInputError(f"y[{k}]" if len(pairs) > 1 else "y",
                                 f"expected at least {start + 1} samples for these lags, "
                                 f"found {y.size} sample(s)")
    return start


def regression_rows(pairs, na: int, nb: tuple[int, ...], delay: tuple[int, ...]
                    ) -> tuple[np.ndarray, np.ndarray]:
    """:func:`regressors` and targets y_t of every (u, y) experiment, each from
    t0 = :func:`lag_window`, so that no window reaches into another experiment."""
    start = lag_window(pairs, na, nb, delay)
    blocks, targets = [], []
    for u, y in pairs:
        t = np.arange(start, y.size)
        blocks.append(regressors(u, y, t, na, nb, delay))
        targets.append(y[t])
    return np.vstack(blocks), np.concatenate(targets)
