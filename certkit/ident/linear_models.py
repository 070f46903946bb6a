"""Linear discrete-time models (ARX) for the linear blocks of Wiener models.

A(q)·y_t = B(q)·u_t:  y_t = Σ_{i=1..na} a_i·y_{t−i} + Σ_{j=0..nb−1} b_j·u_{t−j}  (the seed
paper's eq. 29 with n = na, m = nb − 1).  Fitted by linear least squares on one or more
experiments (lag windows never cross an experiment's boundary), simulated in free run.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.signal import lfilter

from certkit.ident.experiments import experiments


@dataclass
class ARX:
    """ARX model of orders ``na`` (outputs) and ``nb`` (inputs, lags 0..nb−1).

    Learned: ``a_`` (na,), ``b_`` (nb,), ``poles_``, ``stable_``, ``static_gain_``.
    """

    na: int = 6
    nb: int = 4

    def _rows(self, u: np.ndarray, y: np.ndarray):
        start = max(self.na, self.nb - 1)
        if u.size <= start + 1:
            raise ValueError(f"an experiment of {u.size} samples is too short for orders "
                             f"na={self.na}, nb={self.nb}")
        t = np.arange(start, u.size)
        past_y = np.column_stack([y[t - i] for i in range(1, self.na + 1)]) if self.na else \
            np.empty((t.size, 0))
        past_u = np.column_stack([u[t - j] for j in range(self.nb)])
        return np.hstack([past_y, past_u]), y[t]

    def fit(self, u, y) -> ARX:
        """Least squares on one experiment (arrays) or several (lists of arrays)."""
        rows, targets = zip(*(self._rows(a, b) for a, b in experiments(u, y)[0]))
        X, target = np.vstack(rows), np.concatenate(targets)
        theta, *_ = np.linalg.lstsq(X, target, rcond=None)
        self.a_, self.b_ = theta[:self.na], theta[self.na:]
        self.poles_ = np.roots(np.concatenate([[1.0], -self.a_])) if self.na else np.empty(0)
        self.stable_ = bool(np.all(np.abs(self.poles_) < 1.0))
        denominator = 1.0 - np.sum(self.a_)
        self.static_gain_ = float(np.sum(self.b_) / denominator) if denominator else float("nan")
        return self

    @property
    def gain_determined(self) -> bool:
        """Whether the static gain is well conditioned: Σb and 1 − Σa both clearly away
        from zero (relative to Σ|b| and 1 + Σ|a|)."""
        denominator = 1.0 - np.sum(self.a_)
        return bool(abs(np.sum(self.b_)) > 1e-6 * np.sum(np.abs(self.b_))
                    and abs(denominator) > 1e-6 * (1.0 + np.sum(np.abs(self.a_))))

    def normalised(self) -> ARX:
        """The same dynamics scaled to unit static gain (the gain goes to the nonlinearity),
        or to unit ‖b‖ with a positive largest coefficient when the gain is not determined."""
        if self.gain_determined:
            scale = self.static_gain_
        else:
            scale = float(np.linalg.norm(self.b_)) * np.sign(self.b_[np.argmax(np.abs(self.b_))])
        model = ARX(self.na, self.nb)
        model.a_, model.b_ = self.a_.copy(), self.b_ / scale
        model.poles_, model.stable_ = self.poles_, self.stable_
        denominator = 1.0 - np.sum(model.a_)
        model.static_gain_ = (float(np.sum(model.b_) / denominator) if self.gain_determined
                              else float("nan"))
        return model

    def simulate(self, u: np.ndarray) -> np.ndarray:
        """Free-run simulation from rest (zero past inputs and outputs; no measured output
        is used).  Identification signals are deviations that start at rest: the load and
        travels of a drop from touchdown, or the departures from a static point."""

        return lfilter(self.b_, np.concatenate([[1.0], -self.a_]), np.asarray(u, dtype=float))

    def predict(self, u: np.ndarray, y: np.ndarray) -> np.ndarray:
        """One-step-ahead prediction from measured past outputs (first rows: the data)."""
        u, y = np.asarray(u, dtype=float), np.asarray(y, dtype=float)
        X, _ = self._rows(u, y)
        out = y.copy()
        out[max(self.na, self.nb - 1):] = X @ np.concatenate([self.a_, self.b_])
        return out
