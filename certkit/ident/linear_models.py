"""Linear discrete-time models (ARX): the linear blocks of Wiener models, and a baseline.

A(q)·y_t = Σ_c B_c(q)·u_{c,t} + c₀ (Ljung 1999, eq. 4.7, with an intercept):

    y_t = Σ_{i=1..na} a_i·y_{t−i} + Σ_c Σ_{j=0..nb_c−1} b_{c,j}·u_{c, t−d_c−j} + c₀ + e_t

(for one input, delay 0 and no intercept: the seed paper's eq. 29 with n = na, m = nb − 1).
Fitted by linear least squares on one or more experiments (lag windows never cross an
experiment's boundary), simulated in free run (:mod:`certkit.ident.dynamic_model`).
"""

from __future__ import annotations

import numpy as np
from scipy.signal import lfilter, lfiltic

from certkit.ident.dynamic_model import DynamicModel, input_lags, regression_rows, regressors
from certkit.ident.experiments import DataInputError, order, per_channel
from certkit.ident.signature import orders_positional


class ARX(DynamicModel):
    """ARX model of orders ``na`` (outputs) and ``nb`` (inputs), least squares.

    Parameters
    ----------
    na : int, default 6
        Number of past outputs y_{t−1} … y_{t−na}.
    nb : int or sequence of int, default 4
        Input terms per channel: lags d … d + nb − 1 (one value for every channel, or
        one per channel).
    delay : int or sequence of int, default 0
        Input delay d (0: u_t acts on y_t), for every channel or per channel.
    fit_intercept : bool, default True
        Estimate the constant c₀ (an operating point: signals that are not deviations
        from rest).  ``False`` forces c₀ = 0.

    Attributes
    ----------
    a_ : numpy.ndarray, shape (na,)
        AR coefficients a_1 … a_na.
    b_ : numpy.ndarray, shape (nb,) or (n_inputs, max nb)
        Input coefficients b_{c,j} (j = 0 … nb_c − 1 after the delay); one row per channel
        when there are several (zero-padded to the longest).
    intercept_ : float
        c₀ [output unit] (0 when ``fit_intercept=False``).
    poles_ : numpy.ndarray of complex, shape (na,)
        Roots of z^na − a_1 z^(na−1) − … − a_na.
    stable_ : bool
        Every pole strictly inside the unit circle.
    static_gain_ : float or numpy.ndarray, shape (n_inputs,)
        Σ_j b_{c,j} / (1 − Σ_i a_i) per channel (NaN when 1 − Σa = 0).
    n_features_in_ : int
        Number of input channels.

    Notes
    -----
    ``predict(u, y)`` is the one-step-ahead predictor, ``predict(u)`` and ``simulate``
    the free run (:mod:`certkit.ident.dynamic_model`).  Least squares on the stacked
    regression rows is the prediction-error estimate of an ARX model (Ljung 1999, §7.3,
    eq. 7.34).

    References
    ----------
    L. Ljung, *System Identification: Theory for the User*, 2nd ed., Prentice Hall, 1999.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> u = rng.standard_normal(500)
    >>> y = lfilter([0.5], [1.0, -0.8], u) + 2.0       # y_t = 0.8 y_{t-1} + 0.5 u_t + 0.4
    >>> model = ARX(na=1, nb=1).fit(u[1:], y[1:])
    >>> np.round([model.a_[0], model.b_[0], model.intercept_], 6).tolist()
    [0.8, 0.5, 0.4]
    """

    @orders_positional()
    def __init__(self, na: int = 6, nb=4, *, delay=0, fit_intercept: bool = True):
        self.na = na
        self.nb = nb
        self.delay = delay
        self.fit_intercept = fit_intercept

    # ------------------------------------------------------------------ structure
    def _structure(self, n_inputs: int):
        na = order("na", self.na)
        nb = per_channel("nb", self.nb, n_inputs)
        delay = per_channel("delay", self.delay, n_inputs)
        if na + sum(nb) == 0:
            raise DataInputError("na, nb", "expected at least one output or input term, "
                                           "found na = 0 and nb = 0")
        return na, nb, delay

    @property
    def init_length(self) -> int:
        """Samples before the first regression row: max(na, d_c + nb_c − 1 over channels)."""
        nb, delay = self._nb, self._delay
        return max([self._na] + [d + n - 1 for d, n in zip(delay, nb)])

    def _regressors(self, u: np.ndarray, y: np.ndarray, t: np.ndarray) -> np.ndarray:
        rows = regressors(u, y, t, self._na, self._nb, self._delay)
        return np.hstack([rows, np.ones((t.size, 1))]) if self.fit_intercept else rows

    # ------------------------------------------------------------------ fitting
    def _fit(self, pairs) -> None:
        self._na, self._nb, self._delay = self._structure(pairs[0][0].shape[1])
        rows, targets = regression_rows(pairs, self._na, self._nb, self._delay)
        if self.fit_intercept:
            rows = np.hstack([rows, np.ones((rows.shape[0], 1))])
        theta, *_ = np.linalg.lstsq(rows, targets, rcond=None)
        self._set_coefficients(theta[:self._na], theta[self._na:self._na + sum(self._nb)],
                               float(theta[-1]) if self.fit_intercept else 0.0)

    def _set_coefficients(self, a: np.ndarray, b_flat: np.ndarray, intercept: float) -> None:
        self.a_ = np.asarray(a, dtype=float)
        self.b_flat_ = np.asarray(b_flat, dtype=float)
        splits = np.split(self.b_flat_, np.cumsum(self._nb)[:-1])
        if len(splits) == 1:
            self.b_ = splits[0]
        else:
            self.b_ = np.zeros((len(splits), max(self._nb)))
            for c, coefficients in enumerate(splits):
                self.b_[c, :coefficients.size] = coefficients
        self.intercept_ = intercept
        self.poles_ = (np.roots(np.concatenate([[1.0], -self.a_])) if self._na
                       else np.empty(0, dtype=complex))
        self.stable_ = bool(np.all(np.abs(self.poles_) < 1.0))
        denominator = 1.0 - np.sum(self.a_)
        gains = np.array([s.sum() / denominator if denominator else np.nan for s in splits])
        self.static_gain_ = float(gains[0]) if len(splits) == 1 else gains

    # ------------------------------------------------------------------ gain
    def _channel_b(self, channel: int = 0) -> np.ndarray:
        return np.split(self.b_flat_, np.cumsum(self._nb)[:-1])[channel]

    @property
    def gain_determined(self) -> bool:
        """Whether the static gain of input channel 0 is well conditioned: Σb and 1 − Σa
        both clearly away from zero (relative to Σ|b| and 1 + Σ|a|)."""
        b = self._channel_b(0)
        denominator = 1.0 - np.sum(self.a_)
        return bool(abs(np.sum(b)) > 1e-6 * np.sum(np.abs(b))
                    and abs(denominator) > 1e-6 * (1.0 + np.sum(np.abs(self.a_))))

    def normalised(self) -> ARX:
        """The same dynamics scaled to unit static gain of input channel 0 (the gain goes to
        a Wiener model's nonlinearity), or to unit ‖b‖ of channel 0 with a positive largest
        coefficient when that gain is not determined.  The intercept is dropped (the
        nonlinearity carries the offset)."""
        b = self._channel_b(0)
        if self.gain_determined:
            scale = float(np.sum(b) / (1.0 - np.sum(self.a_)))
        else:
            scale = float(np.linalg.norm(b)) * np.sign(b[np.argmax(np.abs(b))])
        model = ARX(self.na, self.nb, delay=self.delay, fit_intercept=False)
        model._na, model._nb, model._delay = self._na, self._nb, self._delay
        model._set_coefficients(self.a_.copy(), self.b_flat_ / scale, 0.0)
        if not self.gain_determined:
            model.static_gain_ = (float("nan") if np.ndim(model.static_gain_) == 0
                                  else np.full_like(model.static_gain_, np.nan))
        model.n_features_in_ = self.n_features_in_
        return model

    # ------------------------------------------------------------------ use
    def _forcing(self, u: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Σ_c Σ_j b_{c,j} u_{c,t−d_c−j} + c₀ at the steps ``t``."""
        out = np.full(t.size, self.intercept_)
        for coefficient, (c, lag) in zip(self.b_flat_, input_lags(self._nb, self._delay)):
            out += coefficient * u[t - lag, c]
        return out

    def _simulate_one(self, u: np.ndarray, y_init: np.ndarray) -> np.ndarray:
        n0, n = y_init.size, u.shape[0]
        out = np.empty(n)
        out[:n0] = y_init
        if n0 < n:
            den = np.concatenate([[1.0], -self.a_])
            forcing = self._forcing(u, np.arange(n0, n))
            if self._na:
                zi = lfiltic([1.0], den, y_init[::-1][:self._na])
                out[n0:] = lfilter([1.0], den, forcing, zi=zi)[0]
            else:
                out[n0:] = forcing
        return out

    def _from_rest(self, u: np.ndarray) -> np.ndarray:
        """From rest by the transfer functions B_c(q)/A(q) (zero initial state)."""
        den = np.concatenate([[1.0], -self.a_])
        out = np.zeros(u.shape[0])
        for c in range(u.shape[1]):
            numerator = np.concatenate([np.zeros(self._delay[c]), self._channel_b(c)])
            if numerator.size:
                out += lfilter(numerator, den, u[:, c])
        if self.intercept_:
            out += lfilter([self.intercept_], den, np.ones(u.shape[0]))
        return out

    def _one_step(self, u: np.ndarray, y: np.ndarray) -> np.ndarray:
        t = np.arange(self.init_length, y.size)
        out = y.copy()
        out[t] = self._regressors(u, y, t) @ np.concatenate(
            [self.a_, self.b_flat_] + ([[self.intercept_]] if self.fit_intercept else []))
        return out
